// hydrolux._core: the drop (drop/render.hpp, shape.hpp, trace.hpp, undistort.hpp): its render
// and the undistortion of the scene seen through it.
#include <fmt/format.h>

#include <cmath>
#include <memory>
#include <optional>
#include <string>
#include <utility>

#include "bindings.hpp"
#include "hydrolux/drop/params.hpp"
#include "hydrolux/drop/render.hpp"
#include "hydrolux/drop/undistort.hpp"
#include "hydrolux/optics/media.hpp"
#include "hydrolux/scene/environment.hpp"
#include "params.hpp"

namespace hydrolux::py_bind {
namespace {

// ---- the drop -------------------------------------------------------------------------------

// The numbers and switches as hydrolux drop render takes its flags: the declared parameters
// (drop/params.hpp), checked in the table's order; the medium by name.
py::array_t<float> drop_render(std::optional<py::array> env, const std::string& medium, const py::dict& kw) {
  drop::DropRenderRequest r;
  // None is the default only of the values that have none of their own (frame_mm, temperature_c):
  // for the others it is refused, as their converters refuse it.
  for (const auto& f : drop::drop_render_params()) {
    const std::string key(f.param.name);
    if (kw.contains(key) && kw[key.c_str()].is_none() && !std::isnan(f.get(r))) param_value(f.param, py::none());
  }
  apply_kwargs(r, kw, drop::drop_render_params());
  const auto water = medium_arg("medium", medium);
  const auto air = optics::find_medium("air");
  if (r.temperature_c && water->info().temperature_dependent)
    require_arg("temperature_c", *r.temperature_c, water->info().temperature_min_c, water->info().temperature_max_c,
                "C");
  else if (r.temperature_c)
    throw Error(fmt::format("temperature_c {:g}: {} has no temperature model; leave it None", *r.temperature_c,
                            water->info().name));
  drop::check_clearance(r, drop::ParamWords::names);
  drop::check_shape(r, drop::ParamWords::names);
  const double blur_rad = drop::background_blur_rad(r, drop::ParamWords::names);
  const drop::ChannelIndex mu = drop::relative_index(r, *water, *air);
  std::unique_ptr<scene::Environment> environment;
  if (env) {
    environment = std::make_unique<scene::EquirectEnvironment>(to_image(*env, "env"));
  } else {
    environment = std::make_unique<scene::BuiltinSky>();
  }
  const drop::DropCamera cam = drop::camera_for(r);
  try {
    drop::validate(cam);
  } catch (const DomainError& e) {
    rethrow_named(e, {{"radius_m", {"radius_mm", 1e3}}, {"distance_m", {"distance_m"}}, {"frame_m", {"frame_mm", 1e3}},
                      {"width", {"size"}}, {"height", {"size"}}});
  }
  return to_array(run_cancellable(
      [&](const ProgressFn& progress) { return drop::render_request(r, cam, *environment, mu, blur_rad, progress); }));
}

// The numbers as hydrolux drop undistort takes its flags: the declared parameters
// (drop/undistort.hpp), checked in the table's order and named by their keywords; `size` is
// (width, height).
py::array_t<float> drop_undistort(const py::array& image, std::pair<double, double> drop_center, double drop_radius_px,
                                  double mu, double fov_deg, double yaw_deg, double pitch_deg,
                                  std::pair<py::object, py::object> size, bool transmission_correction) {
  drop::UndistortRequest r;
  r.drop_radius_px = drop_radius_px, r.mu = mu, r.fov_deg = fov_deg, r.yaw_deg = yaw_deg, r.pitch_deg = pitch_deg;
  r.width = int(whole_arg(size.first, "size[0] (width)", 1, 16384, "px"));
  r.height = int(whole_arg(size.second, "size[1] (height)", 1, 16384, "px"));
  r.transmission_correction = transmission_correction;
  check_fields(drop::undistort_params(), r);
  const drop::UndistortView view = r.view();
  const Image in = to_image(image, "image");
  Image out;
  try {
    py::gil_scoped_release release;
    out = drop::undistort(in, drop_center.first, drop_center.second, *r.drop_radius_px, r.mu, view,
                          r.transmission_correction);
  } catch (const DomainError& e) {
    rethrow_named(e, {{"center_x_px", {"drop_center[0]"}}, {"center_y_px", {"drop_center[1]"}}});
  }
  return to_array(out);
}

}  // namespace

void bind_drop(py::module_& m) {
  m.def("drop_render", &drop_render, py::arg("env"), py::arg("medium"),
        py::arg("options"));
  m.def("drop_undistort", &drop_undistort, py::arg("image"), py::arg("drop_center"), py::arg("drop_radius_px"),
        py::arg("mu"), py::arg("fov_deg"), py::arg("yaw_deg"), py::arg("pitch_deg"), py::arg("size"),
        py::arg("transmission_correction"));
}

}  // namespace hydrolux::py_bind
