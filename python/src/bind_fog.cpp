// hydrolux._core: fog, haze and mist (rain/fog.hpp) over one image, with the declared parameters
// (hydrolux fog's flags) as keywords.
#include <fmt/format.h>

#include <cmath>
#include <optional>
#include <vector>

#include "bindings.hpp"
#include "hydrolux/core/error.hpp"
#include "hydrolux/rain/fog.hpp"
#include "hydrolux/rain/rain.hpp"
#include "params.hpp"

namespace hydrolux::py_bind {

namespace {

py::dict fog(const py::array& image, std::optional<py::array> depth, std::optional<std::vector<double>> sky_rgb,
             const py::dict& kw) {
  rain::FogOptions o;
  apply_kwargs(o, kw, rain::fog_params());
  rain::validate(o.settings);
  const Image frame = to_image(image, "image");
  if (frame.channels < 3) throw Error(fmt::format("image: {} channels; fog needs RGB (H, W, 3 or more)", frame.channels));
  if (frame.width < rain::kMinFrameSide || frame.height < rain::kMinFrameSide)
    throw Error(fmt::format("image: {}x{}; fog needs at least {} pixels a side", frame.width, frame.height, rain::kMinFrameSide));
  // The library's memory check, as the CLI's job and the batch make it (rain.hpp).
  rain::check_fog_memory("image", frame.width, frame.height, frame.channels, o.settings.glow);
  const rain::RainCamera cam = rain::fog_camera_for(o, frame.width, frame.height);
  std::optional<Vec3> sky;
  if (sky_rgb) {
    if (sky_rgb->size() != 3) throw Error(fmt::format("sky_rgb: expected 3 values (R, G, B), got {}", sky_rgb->size()));
    for (double v : *sky_rgb)
      if (!std::isfinite(v) || v < 0) throw Error(fmt::format("sky_rgb: {} is not a finite value >= 0 (linear light)", v));
    sky = Vec3((*sky_rgb)[0], (*sky_rgb)[1], (*sky_rgb)[2]);
  }
  std::optional<Image> z;
  if (depth) {
    z = to_image(*depth, "depth");
    if (z->width != frame.width || z->height != frame.height || z->channels != 1)
      throw Error(fmt::format("depth: expected ({}, {}) metres, got {}x{} with {} channels", frame.height, frame.width,
                              z->width, z->height, z->channels));
  }
  // On a thread of its own without the GIL, stopped by Ctrl-C (KeyboardInterrupt) within ~50 ms: the
  // library's loops call the progress callback once a row (rain/fog.hpp).
  rain::FogOptics optics;
  const rain::FogFrame r = run_cancellable([&](const ProgressFn& progress) {
    try {
      optics = rain::fog_optics(o.settings);
      return rain::render_fog(frame, z ? &*z : nullptr, cam, o.settings, optics, sky, progress);
    } catch (const DomainError&) {
      throw;
    } catch (const Error& e) {
      throw Error(fmt::format("image: {}", e.what()));
    }
  });
  py::dict d;
  d["image"] = to_array(r.image);
  d["mask"] = to_array(r.alpha);
  py::dict st;
  st["beta_per_m"] = optics.beta_per_m;
  st["visibility_m"] = optics.visibility_m;
  st["lwc_g_m3"] = optics.lwc_g_m3;
  st["number_per_cm3"] = optics.number_per_cm3;
  st["effective_radius_um"] = optics.effective_radius_um;
  st["asymmetry_g"] = optics.g;
  st["transmittance_mean"] = r.stats.transmittance_mean;
  st["transmittance_min"] = r.stats.transmittance_min;
  st["transmittance_max"] = r.stats.transmittance_max;
  st["range_m_median"] = r.stats.range_m_median;
  st["sky_fraction"] = r.stats.sky_fraction;
  st["sky_rgb"] = py::make_tuple(r.stats.sky[0], r.stats.sky[1], r.stats.sky[2]);
  st["glow_luminance_mean"] = r.stats.glow_mean;
  st["glow_source_fraction"] = r.stats.glow_source_fraction;
  st["negative_values_clamped"] = r.stats.negative_values_clamped;
  d["stats"] = st;
  return d;
}

}  // namespace

void bind_fog(py::module_& m) { m.def("fog", &fog, py::arg("image"), py::arg("depth"), py::arg("sky_rgb"), py::arg("options")); }

}  // namespace hydrolux::py_bind
