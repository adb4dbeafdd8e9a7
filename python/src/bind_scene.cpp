// hydrolux._core: a rainbow scene (scene/sky_scene.hpp, scene/compositor.hpp) rendered into an
// array, with the declared parameters (hydrolux sky's flags) as keywords: hydrolux.sky.
#include <fmt/format.h>

#include <memory>
#include <optional>
#include <string>

#include "bindings.hpp"
#include "hydrolux/atmos/lee.hpp"
#include "hydrolux/core/error.hpp"
#include "hydrolux/scene/compositor.hpp"
#include "hydrolux/scene/bow_tables.hpp"
#include "hydrolux/scene/environment.hpp"
#include "hydrolux/scene/sky_params.hpp"
#include "hydrolux/scene/sky_scene.hpp"
#include "params.hpp"

namespace hydrolux::py_bind {

namespace {

// hydrolux sky's frame as arrays: the radiance (cd/m^2; the Stokes images' 9 channels with stokes)
// and the display values its PNG holds (tone-mapped, linear; none with stokes), with the numbers its
// summary states. The checks are the job's (scene/sky_scene.hpp), in the keywords' names.
py::dict sky(const std::string& shape_name, std::optional<py::array> environment, std::optional<py::array> moisture,
             const py::dict& options) {
  scene::SkyOptions o;
  apply_kwargs(o, options, scene::sky_params());
  o.shape = shape_name;
  const scene::SkySettings& s = o.settings;
  scene::validate(s);
  const atmos::DropShapeSpec shape = atmos::parse_drop_shape(o.shape);  // "shape 'egg': expected sphere, ..."
  scene::check_sky_request(o, shape, /*tables_given=*/false, Door::python);
  const auto given = [&](std::string_view name) {
    const std::string key(name);
    return options.contains(key) && !options[key.c_str()].is_none();
  };
  scene::refuse_unused_sky_params(o, given, false, environment.has_value(), Door::python);
  scene::check_sky_memory(s, Door::python);
  std::shared_ptr<const scene::Environment> env;
  if (environment) {
    try {
      env = std::make_shared<scene::EquirectEnvironment>(to_image(*environment, "environment"));
    } catch (const DomainError&) {
      throw;
    } catch (const Error& e) {
      throw Error(fmt::format("environment: {}", e.what()));
    }
  }
  std::optional<Image> mask;
  if (moisture) mask = to_image(*moisture, "moisture");
  // On a thread of its own without the GIL, stopped by Ctrl-C within ~50 ms (the tables' work calls
  // the progress callback as it goes).
  struct Frame {
    Image radiance, display;
    double l_ref = 0, sun_lux = 0, optical_depth = 0;
    int positions = 1;
    scene::ProfileAccuracy accuracy;
  };
  const Frame f = run_cancellable([&](const ProgressFn& progress) {
    scene::SkyTables t = scene::compute_sky_tables(o, shape, progress);
    const scene::ProfileAccuracy accuracy = scene::profile_accuracy(t.rainbow, t.corona);
    const scene::SkyCompositor comp(s, std::move(t.rainbow), std::move(t.corona), env, o.environment_scale);
    Frame r;
    r.radiance = comp.render(mask ? &*mask : nullptr);
    // The PNG's exposure (hydrolux sky): a polariser passes half of unpolarised light, for which a
    // camera opens up one stop.
    r.l_ref = comp.sun_sky().l_ref * (s.polarizer_deg ? 0.5 : 1.0);
    if (!s.stokes) r.display = scene::tone_map(r.radiance, r.l_ref);
    r.sun_lux = comp.sun_sky().sun_illuminance_lux;
    r.optical_depth = comp.beta_geo_per_m() * (s.curtain_far_m - s.curtain_near_m);
    r.positions = comp.rainbow_positions();
    r.accuracy = accuracy;
    return r;
  });
  py::dict d;
  d["image"] = to_array(f.radiance);
  d["display"] = s.stokes ? py::object(py::none()) : py::object(to_array(f.display));
  py::dict st;
  st["l_ref"] = f.l_ref;
  st["sun_illuminance_lux"] = f.sun_lux;
  st["optical_depth"] = f.optical_depth;
  st["shape"] = atmos::drop_shape_name(shape);
  st["positions"] = f.positions;
  const scene::ProfileAccuracy& a = f.accuracy;
  st["profile_error"] = a.error ? py::object(py::float_(*a.error)) : py::object(py::none());
  // As hydrolux.lee's info["sampling"]: the profiles' (largest) multiplier, whether it was chosen, and
  // where some were computed twice, the first pass's (largest) estimate.
  py::dict sampling;
  sampling["multiplier"] = a.sampling;
  sampling["automatic"] = !o.sampling.has_value();
  if (a.first_error) {
    py::dict first;
    first["multiplier"] = 1.0, first["luminance_rms"] = *a.first_error;
    sampling["first_pass"] = first;
  } else {
    sampling["first_pass"] = py::none();
  }
  st["sampling"] = sampling;
  py::list notes;
  if (auto note = scene::sky_profile_note(a.error, a.sampling, Door::python)) notes.append(*note);
  st["notes"] = notes;
  d["stats"] = st;
  return d;
}

}  // namespace

void bind_scene(py::module_& m) {
  m.def("sky", &sky, py::arg("shape"), py::arg("environment"), py::arg("moisture"), py::arg("options"));
}

}  // namespace hydrolux::py_bind
