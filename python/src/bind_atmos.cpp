// hydrolux._core: the Lee tables (atmos/lee.hpp): rainbow, corona and glory.
#include <fmt/format.h>

#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>

#include "bindings.hpp"
#include "hydrolux/core/error.hpp"
#include "hydrolux/atmos/lee.hpp"
#include "hydrolux/atmos/lee_params.hpp"
#include "hydrolux/color/cie.hpp"
#include "hydrolux/io/lee_files.hpp"
#include "hydrolux/optics/media.hpp"
#include "hydrolux/scatter/theories.hpp"
#include "params.hpp"

namespace hydrolux::py_bind {
namespace {

// ---- Lee tables -----------------------------------------------------------------------------

py::dict lee(const std::string& theory, std::optional<std::pair<double, double>> radius_um,
             std::pair<double, double> wavelengths_nm,
             py::handle wavelengths_arg,
             const std::string& shape, const std::string& medium, const std::string& sun,
             const std::string& color_space, const py::dict& options) {
  // The table's named values (atmos::LeeRequest), whose rules and errors the CLI shares
  // (atmos::make_lee_spec); the count of wavelengths first, then the declared values
  // (atmos/lee_params.hpp): the size, seed and threads in the table's ranges; the reals' ranges checked by atmos::validate (which reads them from the table) and the temperature's by the
  // medium, below. None is a value only where the parameter has no default (temperature_c). The
  // drops' shape is parsed by make_lee_spec ("shape 'egg': expected sphere, spheroid:Q ..."), and
  // validate refuses a non-spherical shape without Airy theory of a rainbow ("shape beard-chuang:
  // ..."): both messages name the argument and its value.
  atmos::LeeRequest req;
  const int wavelengths = int(whole_arg(wavelengths_arg, "wavelengths", 0, 2000));
  for (const auto& f : atmos::lee_params())
    if (const py::str key(std::string(f.param.name)); options.contains(key) && options[key].is_none() &&
                                                        !std::isnan(f.get(atmos::LeeRequest{})))
      (void)param_value(f.param, options[key]);  // "seed: expected a whole number in [0, 2^53], got None"
  apply_kwargs(req, options, atmos::lee_params(), RealRanges::by_library);
  req.theory = scatter::parse_theory(theory);  // its errors name the theory and its value, and list the valid ones
  if (radius_um) {
    if (radius_um->second < radius_um->first) throw Error("radius_um: expected (A, B) with A <= B, micrometres");
    req.radius_um = {radius_um->first, radius_um->second};
  }
  req.shape = shape;
  atmos::LeeSpec s = atmos::make_lee_spec(req);
  if (wavelengths_nm.second < wavelengths_nm.first) throw Error("wavelengths_nm: expected (A, B) with A <= B");
  s.wavelength_min_nm = wavelengths_nm.first, s.wavelength_max_nm = wavelengths_nm.second;
  s.wavelengths = wavelengths;
  s.drop_medium = medium;
  const auto drop = medium_arg("medium", medium);
  if (const auto& t = req.temperature_c; t && drop->info().temperature_dependent)
    require_arg("temperature_c", *t, drop->info().temperature_min_c, drop->info().temperature_max_c, "C");
  else if (t)
    throw Error(fmt::format("temperature_c {:g}: {} has no temperature model; leave it None", *t, drop->info().name));
  try {
    s.sun = color::Illuminant::parse(sun);
  } catch (const DomainError& e) {
    throw Error(fmt::format("sun '{}': {:g} K is {}", sun, e.value(), e.range_text()));
  } catch (const Error& e) {
    throw Error(fmt::format("sun: {}", e.what()));
  }
  try {
    s.rgb_space = color::parse_rgb_space(color_space);
  } catch (const Error& e) {
    throw Error(fmt::format("color_space: {}", e.what()));
  }
  try {
    atmos::validate(s);
  } catch (const DomainError& e) {
    rethrow_named(e, {{"radius_um", {"radius_um"}}, {"angle_deg", {"angle_deg"}}, {"columns", {"size[0] (columns)"}},
                      {"rows", {"size[1] (rows)"}}, {"wavelength_nm", {"wavelengths_nm"}}});
  }
  // The CLI's up-front memory check, the library's one (the same estimate, the same numbers): a table
  // too large for this machine is a ValueError naming size and what would fit, not a process killed.
  atmos::check_table_memory({&s},
                            req.size ? fmt::format("({}, {})", s.columns, s.rows)
                                     : fmt::format("({}, {}) (the default)", s.columns, s.rows),
                            atmos::SizeSyntax::python);
  const atmos::LeeTable t = run_cancellable([&](const ProgressFn& p) { return atmos::compute_lee_table(s, p); });
  const atmos::LeeImages im = atmos::lee_images(t);
  // The labelled form (io::lee_dataset, as hydrolux lee -o table.nc writes it; its history is set by
  // the Python layer): the table's arrays are its variables' arrays, one copy of each.
  const py::dict dataset = dataset_dict(io::lee_dataset(t, im, ""));
  py::dict arrays;
  for (const auto& item : dataset["variables"]) {
    const auto v = item.cast<py::tuple>();  // (name, dims, array, attrs)
    arrays[v[0]] = v[2];
  }
  py::dict d;
  d["dataset"] = dataset;
  d["rgb"] = arrays["rgb"], d["xyz"] = arrays["xyz"], d["display"] = arrays["display"];
  d["radius_um"] = arrays["radius"], d["angle_deg"] = arrays["scattering_angle"];
  d["cos_angle"] = arrays["cos_scattering_angle"], d["wavelengths_nm"] = arrays["wavelength"];
  d["theory"] = scatter::theory_name(s.theory);
  d["color_space"] = std::string(color::rgb_space_name(s.rgb_space));
  // What the table cannot resolve, naming the keywords that fix it (atmos::lee_resolution_notes).
  py::list notes;
  for (const auto& n : t.notes) notes.append(spell_quantities(n, {}));
  d["notes"] = notes;
  // The table's estimated error (atmos::LeeError): relative RMS over the table; None with one wavelength.
  py::dict error;
  error["luminance_rms"] = t.error.luminance_rms ? py::object(py::float_(*t.error.luminance_rms)) : py::object(py::none());
  if (s.stokes) error["q_rms"] = t.error.q_rms ? py::object(py::float_(*t.error.q_rms)) : py::object(py::none());
  d["error"] = error;
  // The sampling the table was computed at, and with automatic sampling's second pass the first's
  // sampling and estimated error (atmos::LeeTable::first_sampling, first_error), as the sidecar states them.
  py::dict sampling;
  sampling["multiplier"] = t.spec.sampling;
  sampling["automatic"] = t.spec.sampling_most > 0;
  if (t.first_sampling && t.first_error) {
    py::dict first;
    first["multiplier"] = *t.first_sampling, first["luminance_rms"] = *t.first_error;
    sampling["first_pass"] = first;
  } else {
    sampling["first_pass"] = py::none();
  }
  d["sampling"] = sampling;
  d["exposure"] = im.exposure, d["white"] = im.white;
  d["evaluations"] = t.work.evaluations;
  // The drops' shape as the JSON sidecar states it (io/lee_files.cpp): its name, and for
  // non-spherical drops the bow's point, the canting and each column's axis ratio.
  py::dict shape_info;
  shape_info["name"] = atmos::drop_shape_name(s.shape);
  if (!s.shape.spherical()) {
    shape_info["sun_elevation_deg"] = s.sun_elevation_deg;
    shape_info["position_deg"] = s.position_deg;
    shape_info["canting_deg"] = s.canting_deg;
    py::array_t<double> q(py::ssize_t(t.radius_um.size()));
    for (std::size_t c = 0; c < t.radius_um.size(); ++c)
      q.mutable_data()[c] = atmos::drop_axis_ratio(s.shape, t.radius_um[c]);
    shape_info["axis_ratio"] = q;
  }
  d["drop_shape"] = shape_info;
  if (s.stokes) d["q_xyz"] = arrays["q_xyz"], d["dolp"] = arrays["dolp"];  // LeeTable::q_xyz, Q_Y / I_Y
  return d;
}

}  // namespace

void bind_atmos(py::module_& m) {
  m.def("lee", &lee, py::arg("theory"), py::arg("radius_um"),
        py::arg("wavelengths_nm"), py::arg("wavelengths"),
        py::arg("shape"), py::arg("medium"), py::arg("sun"), py::arg("color_space"), py::arg("options"));
}

}  // namespace hydrolux::py_bind
