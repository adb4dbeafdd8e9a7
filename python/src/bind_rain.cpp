// hydrolux._core: rain (rain/rain.hpp): the RainRenderer of one rain for one camera, and the
// built-in scene.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "bindings.hpp"
#include "hydrolux/io/rain_report.hpp"
#include "hydrolux/rain/detect.hpp"
#include "hydrolux/rain/lens_drops.hpp"
#include "hydrolux/rain/params.hpp"
#include "hydrolux/rain/rain.hpp"
#include "params.hpp"

namespace hydrolux::py_bind {
namespace {

// ---- rain -----------------------------------------------------------------------------------

// The options as hydrolux rain takes its flags: the declared parameters (rain/params.hpp).
rain::RainOptions rain_options(const py::dict& kw) {
  rain::RainOptions o;
  apply_kwargs(o, kw, rain::rain_params());
  return o;
}

// The camera for a frame of width x height, as hydrolux rain makes it from its flags.
rain::RainCamera rain_camera(const rain::RainOptions& o, int width, int height) {
  const rain::RainCamera c = rain::camera_for(o, width, height);
  rain::validate(c);
  return c;
}

py::object stats_dict(const rain::RainStats& s) {
  return py::module_::import("json").attr("loads")(io::rain_stats_json(s).dump());
}

// One rain for one camera: a sequence's frames go through one renderer (its field is built once).
class PyRainRenderer {
 public:
  PyRainRenderer(py::handle width_arg, py::handle height_arg, bool ground_plane, const py::dict& kw) {
    const int width = int(whole_arg(width_arg, "width", rain::kMinFrameSide, rain::kMaxFrameSide, "px"));
    const int height = int(whole_arg(height_arg, "height", rain::kMinFrameSide, rain::kMaxFrameSide, "px"));
    const rain::RainOptions o = rain_options(kw);
    const rain::RainSettings& s = o.settings;
    rain::validate(s);
    rain::refuse_fog_settings_without_fog(o);
    const rain::RainCamera c = rain_camera(o, width, height);
    // The library's memory check for a frame of this size (3 colour channels, a layer possible), as the
    // CLI's job makes it: a renderer whose frames cannot fit is refused before its field is built.
    rain::check_render_memory(c, 3, true, fmt::format("width, height ({}, {})", width, height));
    py::gil_scoped_release release;
    renderer_ = std::make_unique<rain::RainRenderer>(rain::RainField(s, c, ground_plane));
    if (o.has_fog()) renderer_->set_fog(o.fog);
  }

  py::dict render(const py::array& image, std::optional<py::array> depth, py::handle frame_arg, bool with_layer) {
    const Param& fi = rain::rain_param("frame_index");
    const long long frame_index = whole_arg(frame_arg, "frame_index", (long long)fi.lo, (long long)fi.hi);
    const auto& cam = renderer_->field().camera();
    Image frame = to_image(image, "image");
    if (frame.width != cam.width || frame.height != cam.height || frame.channels < 3)
      throw Error(fmt::format("image: {}x{} with {} channels; this rain was made for {}x{} RGB frames", frame.width,
                              frame.height, frame.channels, cam.width, cam.height));
    std::optional<Image> z;
    if (depth) {
      z = to_image(*depth, "depth");
      if (z->width != cam.width || z->height != cam.height || z->channels != 1)
        throw Error(fmt::format("depth: expected ({}, {}) metres, got {}x{} with {} channels", cam.height, cam.width,
                                z->width, z->height, z->channels));
    }
    py::dict d;
    {
      // The renderer and its result buffers are one sequence's: one render at a time, and the
      // result copied out before the next may start. Waiting for the lock without the GIL, and
      // taking the GIL back under it, cannot deadlock: no thread waits for the lock holding the GIL.
      py::gil_scoped_release release;
      std::lock_guard<std::mutex> lock(mutex_);
      try {
        renderer_->render_into(frame, z ? &*z : nullptr, frame_index, with_layer, result_);
      } catch (const rain::NonFinitePixel& e) {
        throw Error(fmt::format("image: {}", e.what()));  // the library's text names the pixel and its value
      }
      py::gil_scoped_acquire gil;
      d["image"] = to_array(result_.image);
      d["mask"] = to_array(result_.alpha);
      d["layer"] = with_layer ? py::object(to_array(result_.layer)) : py::object(py::none());
      d["stats"] = stats_dict(result_.stats);
    }
    return d;
  }

  py::dict field_info() const {
    const auto& f = renderer_->field();
    py::dict d;
    d["drops"] = f.drop_count();
    d["beta_total_per_m"] = f.beta_total_per_m();
    d["width"] = f.camera().width, d["height"] = f.camera().height;
    d["focal_px"] = f.camera().focal_px();
    return d;
  }

 private:
  std::unique_ptr<rain::RainRenderer> renderer_;
  rain::RainFrame result_;
  std::mutex mutex_;
};

py::array_t<float> builtin_scene(py::handle width_arg, py::handle height_arg, const py::dict& kw) {
  const int width = int(whole_arg(width_arg, "width", rain::kMinFrameSide, rain::kMaxFrameSide, "px"));
  const int height = int(whole_arg(height_arg, "height", rain::kMinFrameSide, rain::kMaxFrameSide, "px"));
  const rain::RainCamera c = rain_camera(rain_options(kw), width, height);
  Image img;
  {
    py::gil_scoped_release release;
    img = rain::builtin_scene(c);
  }
  return to_array(img);
}

// ---- lens drops (rain/lens_drops.hpp) ------------------------------------------------------------

// Drops on the lens or windshield over one image, with the declared parameters as keywords.
py::dict lens_drops(const py::array& image, const py::dict& kw) {
  rain::LensDropSettings s;
  apply_kwargs(s, kw, rain::lens_drops_params());
  const Image frame = to_image(image, "image");
  // The library's memory check, as the CLI's job and the batch make it (lens_drops.hpp).
  rain::check_lens_drops_memory(s, "image", frame.width, frame.height, frame.channels);
  // On a thread of its own without the GIL, stopped by Ctrl-C (KeyboardInterrupt) within ~50 ms: the
  // library calls the progress callback once a row (rain/lens_drops.hpp).
  const rain::LensDropsResult r =
      run_cancellable([&](const ProgressFn& progress) { return rain::render_lens_drops(frame, s, progress); });
  py::dict d;
  d["image"] = to_array(r.image);
  d["mask"] = to_array(r.mask);
  d["drops"] = r.drops;
  d["coverage"] = r.coverage;
  d["blur_diameter_px"] = r.blur_diameter_px;
  d["negative_values_clamped"] = r.negative_values_clamped;
  return d;
}

// ---- rain detection, removal and scores (rain/detect.hpp) -------------------------------------------

// A sequence of frames (a list of (H, W) or (H, W, C) arrays, or one (T, H, W[, C]) array), each as an Image.
std::vector<Image> frames_arg(const py::handle& frames, const char* arg) {
  std::vector<Image> out;
  for (const auto& f : frames) {
    out.push_back(to_image(py::array::ensure(f), arg));
    rain::check_finite(out.back(), fmt::format("{}[{}]", arg, out.size() - 1));
  }
  for (const auto& f : out)
    if (f.width != out[0].width || f.height != out[0].height || f.channels != out[0].channels)
      throw Error(fmt::format("{}: a frame of {}x{} with {} channels among frames of {}x{} with {}", arg, f.width,
                              f.height, f.channels, out[0].width, out[0].height, out[0].channels));
  return out;
}

py::array_t<std::uint8_t> masks_array(const std::vector<rain::Mask>& masks) {
  if (masks.empty()) return py::array_t<std::uint8_t>(std::vector<py::ssize_t>{0, 0, 0});
  py::array_t<std::uint8_t> out({py::ssize_t(masks.size()), py::ssize_t(masks[0].height), py::ssize_t(masks[0].width)});
  std::uint8_t* d = out.mutable_data();
  for (const auto& m : masks) d = std::copy(m.on.begin(), m.on.end(), d);
  return out;
}

std::vector<rain::Mask> masks_arg(const py::handle& masks, const char* arg) {
  std::vector<rain::Mask> out;
  for (const Image& m : frames_arg(masks, arg)) {
    rain::Mask mk{m.width, m.height, std::vector<std::uint8_t>(std::size_t(m.width) * std::size_t(m.height))};
    for (std::size_t i = 0; i < mk.on.size(); ++i) mk.on[i] = m.pixels[i * std::size_t(m.channels)] != 0;
    out.push_back(std::move(mk));
  }
  return out;
}

py::dict detect_rain(const py::handle& frames, const py::dict& kw) {
  rain::DetectSettings s;
  apply_kwargs(s, kw, rain::detect_params());
  rain::validate(s);
  std::vector<rain::GreyFrame> grey;
  for (const Image& f : frames_arg(frames, "frames")) grey.push_back(rain::grey_levels(f));
  const rain::Detection d =
      run_cancellable([&](const ProgressFn& progress) { return rain::detect_rain(grey, s, progress); });
  py::dict out;
  out["masks"] = masks_array(d.result);
  out["candidates"] = d.candidates.empty() ? py::object(py::none()) : py::object(masks_array(d.candidates));
  out["photometric"] = d.photometric.empty() ? py::object(py::none()) : py::object(masks_array(d.photometric));
  out["correlated"] = d.correlated.empty() ? py::object(py::none()) : py::object(masks_array(d.correlated));
  return out;
}

py::array_t<float> remove_rain(const py::handle& frames, const py::object& masks, const py::object& layers,
                               const py::dict& kw) {
  rain::RemoveSettings s;
  apply_kwargs(s, kw, rain::remove_params());
  rain::validate(s);
  const std::vector<Image> f = frames_arg(frames, "frames");
  if (f.empty()) throw Error("frames: none given");
  const bool gn = s.method == rain::RemoveMethod::garg_nayar, oracle = s.method == rain::RemoveMethod::oracle;
  if (gn && masks.is_none()) throw Error("masks: method garg-nayar replaces the masked pixels; give the masks");
  if (oracle && layers.is_none()) throw Error("layers: method oracle inverts the rain layers; give them");
  if (!gn && !masks.is_none()) throw Error("masks: used only with method garg-nayar");
  if (!oracle && !layers.is_none()) throw Error("layers: used only with method oracle");
  const std::vector<rain::Mask> m = gn ? masks_arg(masks, "masks") : std::vector<rain::Mask>{};
  const std::vector<Image> l = oracle ? frames_arg(layers, "layers") : std::vector<Image>{};
  if ((gn && m.size() != f.size()) || (oracle && l.size() != f.size()))
    throw Error(fmt::format("{}: {} for {} frames", gn ? "masks" : "layers", gn ? m.size() : l.size(), f.size()));
  if (gn && (m[0].width != f[0].width || m[0].height != f[0].height))
    throw Error(fmt::format("masks: {}x{} for frames of {}x{}", m[0].width, m[0].height, f[0].width, f[0].height));
  if (!oracle && f.size() < 3) throw Error(fmt::format("frames: {}; removal from the neighbouring frames needs 3", f.size()));
  const std::size_t c = std::size_t(f[0].channels);
  py::array_t<float> out({py::ssize_t(f.size()), py::ssize_t(f[0].height), py::ssize_t(f[0].width), py::ssize_t(c)});
  float* d = out.mutable_data();
  {
    py::gil_scoped_release release;
    for (std::size_t k = 0; k < f.size(); ++k) {
      const Image clear = gn ? rain::remove_from_neighbours(f, m, k)
                          : oracle ? rain::invert_rain_layer(f[k], l[k])
                                   : rain::temporal_median(f, k, s.median_frames);
      d = std::copy(clear.pixels.begin(), clear.pixels.end(), d);
    }
  }
  return out;
}

py::dict confusion_dict(const rain::Confusion& c) {
  py::dict d;
  const auto ratio = [](double v) { return std::isnan(v) ? py::object(py::none()) : py::object(py::float_(v)); };
  d["precision"] = ratio(c.precision());
  d["recall"] = ratio(c.recall());
  d["f1"] = ratio(c.f1());
  d["iou"] = ratio(c.iou());
  d["true_positive"] = c.true_positive;
  d["false_positive"] = c.false_positive;
  d["false_negative"] = c.false_negative;
  d["true_negative"] = c.true_negative;
  d["ignored"] = c.ignored;
  return d;
}

py::dict score_rain(const py::handle& predicted, const py::handle& truth_alpha, const py::object& clean,
                    const py::object& derained, const py::dict& kw) {
  rain::EvalSettings s;
  apply_kwargs(s, kw, rain::eval_params());
  rain::validate(s);
  const std::vector<rain::Mask> p = masks_arg(predicted, "predicted");
  const std::vector<Image> a = frames_arg(truth_alpha, "truth_alpha");
  if (clean.is_none() != derained.is_none())
    throw Error(clean.is_none() ? "derained: goes with clean" : "clean: goes with derained");
  const std::vector<Image> cl = clean.is_none() ? std::vector<Image>{} : frames_arg(clean, "clean");
  const std::vector<Image> dr = derained.is_none() ? std::vector<Image>{} : frames_arg(derained, "derained");
  if (p.size() != a.size() || (!cl.empty() && (cl.size() != p.size() || dr.size() != p.size())))
    throw Error(fmt::format("predicted: {} frames, truth_alpha {}{}", p.size(), a.size(),
                            cl.empty() ? std::string() : fmt::format(", clean {}, derained {}", cl.size(), dr.size())));
  rain::Confusion all;
  rain::RemovalError removal;
  py::list frames;
  for (std::size_t k = 0; k < p.size(); ++k) {
    if (a[k].width != p[k].width || a[k].height != p[k].height)
      throw Error(fmt::format("truth_alpha: frame {} is {}x{}, its prediction {}x{}", k, a[k].width, a[k].height,
                              p[k].width, p[k].height));
    std::vector<float> alpha(p[k].on.size());
    for (std::size_t i = 0; i < alpha.size(); ++i) alpha[i] = a[k].pixels[i * std::size_t(a[k].channels)];
    const rain::Confusion c = rain::score_mask(p[k].on, alpha, s);
    all += c;
    py::dict f = confusion_dict(c);
    if (!cl.empty()) {
      const rain::RemovalError e = rain::removal_error(dr[k], cl[k], alpha, s);
      removal += e;
      f["psnr_in_mask"] = e.psnr_in();
      f["psnr_out_mask"] = e.psnr_out();
    }
    frames.append(f);
  }
  py::dict out;
  out["overall"] = confusion_dict(all);
  if (!cl.empty()) {
    out["overall"]["psnr_in_mask"] = removal.psnr_in();
    out["overall"]["psnr_out_mask"] = removal.psnr_out();
  }
  out["frames"] = frames;
  return out;
}

}  // namespace

void bind_rain(py::module_& m) {
  m.def("detect_rain", &detect_rain, py::arg("frames"), py::arg("options"));
  m.def("remove_rain", &remove_rain, py::arg("frames"), py::arg("masks"), py::arg("layers"), py::arg("options"));
  m.def("score_rain", &score_rain, py::arg("predicted"), py::arg("truth_alpha"), py::arg("clean"),
        py::arg("derained"), py::arg("options"));
  py::class_<PyRainRenderer>(m, "RainRenderer")
      .def(py::init<py::handle, py::handle, bool, const py::dict&>(), py::arg("width"), py::arg("height"),
           py::arg("ground_plane"), py::arg("options"))
      .def("render", &PyRainRenderer::render, py::arg("image"), py::arg("depth"), py::arg("frame_index"),
           py::arg("with_layer"))
      .def("field_info", &PyRainRenderer::field_info);
  m.def("builtin_scene", &builtin_scene, py::arg("width"), py::arg("height"), py::arg("options"));
  m.def("lens_drops", &lens_drops, py::arg("image"), py::arg("options"));
}

}  // namespace hydrolux::py_bind
