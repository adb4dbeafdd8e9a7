// hydrolux._core: rain (rain/rain.hpp): the RainRenderer of one rain for one camera, and the
// built-in scene.
#include <fmt/format.h>

#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include "bindings.hpp"
#include "hydrolux/io/rain_report.hpp"
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

}  // namespace

void bind_rain(py::module_& m) {
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
