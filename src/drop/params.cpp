#include "hydrolux/drop/params.hpp"

#include <fmt/format.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "hydrolux/core/error.hpp"
#include "hydrolux/core/math.hpp"
#include "hydrolux/core/shared_params.hpp"
#include "hydrolux/drop/trace.hpp"
#include "hydrolux/optics/media.hpp"
#include "hydrolux/scatter/drop_shape.hpp"

namespace hydrolux::drop {

namespace {

using K = ParamKind;


const Field<DropRenderRequest> kDropRender[] = {
    {{"radius_mm", "--radius-mm", "drop", K::real, "mm", 0.01, 100, "Drop radius in mm"}, HYDROLUX_PARAM_MEMBER(radius_mm)},
    {{"distance_m", "--distance-m", "camera", K::real, "m", 0.001, 1e4,
      "Distance from the camera to the drop's centre in metres"},
     HYDROLUX_PARAM_MEMBER(distance_m)},
    {{"focal_mm", "--focal-mm", "camera", K::real, "mm", 1, 2000,
      "Lens focal length in mm (sets the aperture for --background-blur)"},
     HYDROLUX_PARAM_MEMBER(focal_mm)},
    {{"f_number", "--f-number", "camera", K::real, "", 0.5, 128, "Lens f-number (aperture = focal / f-number)"},
     HYDROLUX_PARAM_MEMBER(f_number)},
    {{"frame_mm", "--frame-mm", "camera", K::real, "mm", 1e-6, 1e6,
      "Width of the field at the drop's distance in mm [default: 5 x the drop radius]"},
     HYDROLUX_PARAM_OPTIONAL(frame_mm)},
    {{"size", "--size", "camera", K::integer, "px", 8, 16384, "Image width and height in pixels"}, HYDROLUX_PARAM_MEMBER(size)},
    {{"samples", "--samples", "render", K::integer, "", 1, 64, "Supersamples per pixel along each axis (anti-aliasing)"},
     HYDROLUX_PARAM_MEMBER(samples)},
    {{"internal", "--internal", "render", K::integer, "", 0, 20, "Internal reflections added by the model (eq. 19)"},
     HYDROLUX_PARAM_MEMBER(internal)},
    {temperature_param("drop",
      "Drop temperature in Celsius, for media with a temperature model (water: 0 to 100) [medium's default]"),
     HYDROLUX_PARAM_OPTIONAL(temperature_c)},
    {{"wavelength_nm", "--wavelength-nm", "drop", K::real, "nm", 200, 2500,
      "Vacuum wavelength of the index without --dispersion"},
     HYDROLUX_PARAM_MEMBER(wavelength_nm)},
    {flag_param("dispersion", "--dispersion", "drop",
                "Per-channel index at 610/550/465 nm: the channels' paths part (colour fringes)"),
     HYDROLUX_PARAM_MEMBER(dispersion)},
    {flag_param("background_blur", "--background-blur", "camera",
                "Defocus the background: the camera is focused on the drop, the scene is at infinity"),
     HYDROLUX_PARAM_MEMBER(background_blur)},
    {flag_param("background", "--no-background", "camera", "Black background with the drop's coverage in alpha"),
     HYDROLUX_PARAM_MEMBER(background)},
    {{"exposure_ev", "--exposure-ev", "camera", K::real, "", -30, 30, "Exposure adjustment in stops applied to the output"},
     HYDROLUX_PARAM_MEMBER(exposure_ev)},
    {choice_param("method", "--method", "render", "model|exact",
                  "model: Garg & Nayar's model (eq. 19); exact: the Fresnel-split ray tracer (every path to --depth)"),
     HYDROLUX_PARAM_MEMBER(method)},
    {choice_param("shape", "--shape", "drop", "sphere|beard-chuang",
                  "Drop shape for --method exact: sphere, or beard-chuang (the falling drop's equilibrium shape, "
                  "radius 0.5-4.5 mm, seen from the side)"),
     HYDROLUX_PARAM_MEMBER(shape)},
    {{"depth", "--depth", "render", K::integer, "", 6, 64, "Surface interactions the exact tracer follows per path"},
     HYDROLUX_PARAM_MEMBER(depth)},
};

std::string said(std::string_view name, ParamWords words) {
  const Param& p = drop_render_param(name);
  return std::string(words == ParamWords::flags ? p.flag : p.name);
}

}  // namespace

std::span<const Field<DropRenderRequest>> drop_render_params() { return kDropRender; }

const Param& drop_render_param(std::string_view name) {
  if (const auto* f = find_field(drop_render_params(), name)) return f->param;
  throw std::logic_error("drop_render_param: no parameter " + std::string(name));
}

void check_clearance(const DropRenderRequest& r, ParamWords words) {
  if (r.distance_m <= 1.01 * r.radius_mm * 1e-3)
    throw Error(fmt::format("{} {:g} must exceed the drop radius ({:g} m) by at least 1%", said("distance_m", words),
                            r.distance_m, r.radius_mm * 1e-3));
}

void check_shape(const DropRenderRequest& r, ParamWords words) {
  if (r.shape == DropShapeKind::sphere) return;
  const auto range = scatter::drop_shape_radius_range_m();
  if (r.radius_mm < range[0] * 1e3 || r.radius_mm > range[1] * 1e3)
    throw Error(fmt::format("{} {:g} is outside the valid range [{:g}, {:g}] mm of the Beard & Chuang shape",
                            said("radius_mm", words), r.radius_mm, range[0] * 1e3, range[1] * 1e3));
  if (r.method == RenderMethod::model)
    throw Error(fmt::format("{} beard-chuang: the model is for a sphere; use {} exact for other shapes",
                            said("shape", words), said("method", words)));
}

double background_blur_rad(const DropRenderRequest& r, ParamWords words) {
  if (!r.background_blur) return 0;
  const auto w = [words](std::string_view name) { return said(name, words); };
  if (r.distance_m <= 1.01 * r.focal_mm * 1e-3)
    throw Error(fmt::format("{} {:g} must exceed the focal length ({} {:g}) to focus on the drop", w("distance_m"),
                            r.distance_m, w("focal_mm"), r.focal_mm));
  // The lens is focused on the drop, the scene is at infinity.
  const double blur_rad = defocus_blur_radius_rad(r.focal_mm * 1e-3, r.f_number, r.distance_m);
  if (blur_rad > kPi<> / 6)
    throw Error(fmt::format("{}: {} {:g} at {} {:g} focused at {} {:g} gives a defocus disk {:.1f} degrees wide; at "
                            "most 60 degrees is supported",
                            w("background_blur"), w("focal_mm"), r.focal_mm, w("f_number"), r.f_number,
                            w("distance_m"), r.distance_m, 2 * rad_to_deg(blur_rad)));
  return blur_rad;
}

ChannelIndex relative_index(const DropRenderRequest& r, const optics::Medium& drop, const optics::Medium& around) {
  const auto relative = [&](double nm) { return drop.n(nm, r.temperature_c) / around.n(nm); };
  ChannelIndex mu;
  if (r.dispersion) {
    for (std::size_t c = 0; c < 3; ++c) mu[c] = relative(kChannelWavelengthsNm[c]);
  } else {
    mu.fill(relative(r.wavelength_nm));
  }
  return mu;
}

DropCamera camera_for(const DropRenderRequest& r) {
  DropCamera cam;
  cam.radius_m = r.radius_mm * 1e-3;
  cam.distance_m = r.distance_m;
  cam.frame_m = (r.frame_mm ? *r.frame_mm : 5.0 * r.radius_mm) * 1e-3;
  cam.width = cam.height = r.size;
  return cam;
}

Image render_request(const DropRenderRequest& r, const DropCamera& camera, const scene::Environment& env,
                     const ChannelIndex& mu, double blur_rad, ProgressFn progress) {
  RenderOptions opt;
  opt.samples_per_axis = r.samples;
  opt.n_internal = r.internal;
  opt.background = r.background;
  opt.background_blur_rad = blur_rad;
  opt.progress = std::move(progress);
  Image img;
  if (r.method == RenderMethod::model) {
    img = render_model(camera, env, mu, opt);
  } else {
    const auto surface = make_drop_surface(camera, r.shape);
    TraceOptions trace;
    trace.max_depth = r.depth;
    img = render_exact(camera, env, mu, *surface, opt, trace);
  }
  const float gain = float(std::exp2(r.exposure_ev));
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x)
      for (int c = 0; c < 3; ++c) img.at(x, y, c) *= gain;
  return img;
}

}  // namespace hydrolux::drop
