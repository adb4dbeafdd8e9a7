// hydrolux._core: Mie scattering (scatter/mie.hpp, amplitudes.hpp), spheres in a medium
// (scatter/sphere.hpp), size distributions and bulk optics (scatter/size_distribution.hpp), a drop's
// phase function (scatter/phase_job.hpp).
#include <fmt/format.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <span>
#include <utility>
#include <vector>

#include "bindings.hpp"
#include "hydrolux/core/math.hpp"
#include "hydrolux/core/parse.hpp"
#include "hydrolux/optics/media.hpp"
#include "hydrolux/scatter/amplitudes.hpp"
#include "hydrolux/scatter/mie.hpp"
#include "hydrolux/scatter/mie_dataset.hpp"
#include "hydrolux/scatter/mueller.hpp"
#include "hydrolux/scatter/params.hpp"
#include "hydrolux/scatter/phase_job.hpp"
#include "hydrolux/scatter/renderer_export.hpp"
#include "hydrolux/scatter/size_distribution.hpp"
#include "hydrolux/scatter/sphere.hpp"
#include "params.hpp"

namespace hydrolux::py_bind {
namespace {

// Runs f with at most `threads` threads (0: every core).
template <class F>
auto with_threads(int threads, F&& f) {
  if (threads <= 0) return f();
  tbb::task_arena arena(threads);
  return arena.execute(std::forward<F>(f));
}

// m and x of spheres of the given radii (um) in a medium at one wavelength.
py::tuple sphere_problem(py::handle radius_arg, double wavelength_nm, const std::string& medium,
                         const std::string& surrounding, std::optional<double> temperature_c) {
  const DoubleArray radius_um = c_array<double>(radius_arg, "radius_um");
  const auto sphere = medium_arg("medium", medium);
  const auto outside = medium_arg("surrounding", surrounding);
  if (temperature_c && !sphere->info().temperature_dependent && !outside->info().temperature_dependent)
    throw Error(fmt::format("temperature_c {:g}: neither {} nor {} has a temperature model; leave it None",
                            *temperature_c, sphere->info().name, outside->info().name));
  DoubleArray x(shape_of(radius_um));
  std::complex<double> m;
  const double* r = radius_um.data();
  for (py::ssize_t i = 0; i < radius_um.size(); ++i) {
    require_arg("radius_um", r[i], 1e-300, 1e6, "um");
    const auto p = scatter::sphere_problem(r[i], wavelength_nm, *sphere, *outside, temperature_c);
    m = p.m;
    x.mutable_data()[i] = p.x;
  }
  if (radius_um.size() == 0)  // m alone, from any radius
    m = scatter::sphere_problem(1.0, wavelength_nm, *sphere, *outside, temperature_c).m;
  return py::make_tuple(m, x);
}

// ---- Mie --------------------------------------------------------------------------------------

// Work of `work` units: inline with the GIL released when small (a thread start would cost more than
// the call), on run_cancellable's thread, stoppable by Ctrl-C, when larger than `cancellable_from`.
template <class Body>
void run_sized(double work, double cancellable_from, Body&& body) {
  if (work > cancellable_from) {
    run_cancellable(body);
  } else {
    py::gil_scoped_release release;
    body(ProgressFn{});
  }
}

void check_mie_args(std::complex<double> m, const double* x, py::ssize_t n) {
  const Param& x_param = scatter::mie_param("x");  // hydrolux mie --x's range
  for (py::ssize_t i = 0; i < n; ++i) x_param.check(x[i]);
  // m's domain by the library's own check (named m_real / m_imag), once, before any work.
  scatter::MieCoefficients probe;
  try {
    scatter::mie_coefficients(m, 1.0, probe, 1);
  } catch (const DomainError& e) {
    throw Error(fmt::format("m = ({:g}{:+g}j): {} {:g} is {}", m.real(), m.imag(), e.quantity(), e.value(),
                            e.range_text()));
  }
}

// Scattering angles from the CLI's text ("A:B:N" or "0,10,90"), read by the library's parser with the
// CLI's limits and in its words (hydrolux mie/phase --angles-deg): mie(), phase() and
// _core.parse_angles give exactly the CLI's angles, and refuse exactly what it refuses.
constexpr std::size_t kMaxAngles = 1000000;
std::vector<double> angles_from_text(const std::string& text) {
  try {
    return parse::range_or_list(text, 0, 180, kMaxAngles);
  } catch (const Error& e) {
    throw Error(fmt::format("angles_deg '{}': {}; expected A:B:N (N angles from A to B, N in [2, 1000000], or "
                            "N = 1 with A = B) or a list 0,10,90, angles in [0, 180] deg, strictly increasing or "
                            "decreasing",
                            printable(text), e.what()));
  }
}

py::dict mie(std::complex<double> m, py::handle x_arg, py::handle angles_arg, py::handle threads_arg,
             bool mueller) {
  // threads and x as hydrolux mie takes --threads and --x: the declared parameters (scatter/params.hpp).
  const int threads = int(param_value(scatter::mie_param("threads"), threads_arg)[0]);
  const DoubleArray x = c_array<double>(x_arg, "x");
  std::optional<DoubleArray> angles_deg;
  if (!angles_arg.is_none()) angles_deg = c_array<double>(angles_arg, "angles_deg");
  if (mueller && !angles_deg) throw Error("mueller=True derives from the amplitudes; angles_deg=None computes none");
  const double* xs = x.data();
  const py::ssize_t n = x.size();
  check_mie_args(m, xs, n);
  const auto shape = shape_of(x);
  DoubleArray qext(shape), qsca(shape), qabs(shape), qback(shape), g(shape);
  py::array_t<std::int32_t> terms(shape);
  py::dict d;
  // Per size, filled without the GIL, copied into the arrays after.
  std::vector<scatter::MieEfficiencies> q(static_cast<std::size_t>(n));
  std::vector<int> nt(static_cast<std::size_t>(n));
  if (!angles_deg) {
    // Efficiencies alone: the fast path, sizes in parallel (each size's result is independent of
    // the thread that computes it).
    double work = 0;
    for (py::ssize_t i = 0; i < n; ++i) work += xs[i];
    const auto body = [&](const ProgressFn& progress) {
      with_threads(threads, [&] {
        tbb::parallel_for(py::ssize_t(0), n, [&](py::ssize_t i) {
          if (progress) progress(0, {});
          q[std::size_t(i)] = scatter::mie_efficiencies(m, xs[i]);
          nt[std::size_t(i)] = scatter::mie_terms(xs[i]);
        });
        return 0;
      });
      return 0;
    };
    run_sized(work, 1e6, body);
  } else {
    const DoubleArray& ang = *angles_deg;
    if (ang.ndim() != 1) throw Error("angles_deg: expected a 1-D array of angles in degrees");
    const py::ssize_t na = ang.size();
    if (na > 1000000) throw Error(fmt::format("angles_deg: {} angles, more than the limit of 1000000", na));
    std::vector<double> mu(static_cast<std::size_t>(na));
    for (py::ssize_t j = 0; j < na; ++j) {
      require_arg("angles_deg", ang.data()[j], 0, 180, "deg");
      mu[std::size_t(j)] = std::cos(deg_to_rad(ang.data()[j]));
    }
    // As the CLI's --angles-deg: the angles label the result's rows (and a NetCDF coordinate), so none
    // twice and in one direction, checked here rather than at to_xarray().
    try {
      parse::require_strictly_monotonic(std::span<const double>(ang.data(), std::size_t(na)));
    } catch (const Error& e) {
      throw Error(fmt::format("angles_deg: {}", e.what()));
    }
    auto s_shape = shape;
    s_shape.push_back(na);
    ComplexArray s1(s_shape), s2(s_shape);
    std::complex<double>* p1 = s1.mutable_data();
    std::complex<double>* p2 = s2.mutable_data();
    double work = 0;
    for (py::ssize_t i = 0; i < n; ++i) work += (xs[i] + 10) * double(na + 1);
    const auto body = [&](const ProgressFn& progress) {
      scatter::MieCoefficients c;
      for (py::ssize_t i = 0; i < n; ++i) {
        if (progress) progress(double(i) / double(n), {});
        scatter::mie_coefficients(m, xs[i], c);
        q[std::size_t(i)] = scatter::mie_efficiencies(c);
        nt[std::size_t(i)] = c.terms();
        scatter::mie_amplitudes(c, mu, {p1 + i * na, std::size_t(na)}, {p2 + i * na, std::size_t(na)}, threads,
                                progress);
      }
      return 0;
    };
    run_sized(work, 2e7, body);
    d["s1"] = s1, d["s2"] = s2;
    if (mueller) {
      // The Mueller elements (B&H eq. 4.77) of each size and angle, of the shape of S1.
      const std::size_t total = std::size_t(n) * std::size_t(na);
      const auto e = scatter::mueller_elements({p1, total}, {p2, total});
      const auto array = [&](const std::vector<double>& v) {
        DoubleArray a(s_shape);
        std::copy(v.begin(), v.end(), a.mutable_data());
        return a;
      };
      d["s11"] = array(e.s11), d["s12"] = array(e.s12), d["s33"] = array(e.s33), d["s34"] = array(e.s34);
    }
  }
  for (py::ssize_t i = 0; i < n; ++i) {
    const auto& e = q[std::size_t(i)];
    qext.mutable_data()[i] = e.qext, qsca.mutable_data()[i] = e.qsca, qabs.mutable_data()[i] = e.qabs;
    qback.mutable_data()[i] = e.qback, g.mutable_data()[i] = e.g, terms.mutable_data()[i] = nt[std::size_t(i)];
  }
  d["qext"] = qext, d["qsca"] = qsca, d["qabs"] = qabs, d["qback"] = qback, d["g"] = g, d["n_terms"] = terms;
  return d;
}

py::dict bulk_optics(std::complex<double> m, double wavenumber_per_m, py::handle radius_arg, py::handle weight_arg,
                     py::handle threads_arg) {
  const int threads = int(param_value(scatter::mie_param("threads"), threads_arg)[0]);
  require_arg("wavenumber_per_m", wavenumber_per_m, 1e-300, 1e300);
  const DoubleArray radius_m = c_array<double>(radius_arg, "radius_m"), weight = c_array<double>(weight_arg, "weight");
  if (radius_m.ndim() != 1 || weight.ndim() != 1 || radius_m.size() != weight.size())
    throw Error("radius_m, weight: expected two 1-D arrays of the same length");
  scatter::RadiusQuadrature q;
  q.radius_m.assign(radius_m.data(), radius_m.data() + radius_m.size());
  q.weight.assign(weight.data(), weight.data() + weight.size());
  scatter::MieBulkOptics b;
  {
    py::gil_scoped_release release;
    b = scatter::mie_bulk_optics(m, wavenumber_per_m, q, threads);
  }
  py::dict d;
  d["extinction_per_m"] = b.extinction_per_m, d["scattering_per_m"] = b.scattering_per_m;
  d["absorption_per_m"] = b.absorption_per_m, d["backscatter_per_m"] = b.backscatter_per_m, d["g"] = b.g;
  return d;
}


// ---- the phase function ---------------------------------------------------------------------

// hydrolux phase's job (scatter/phase_job.hpp): the same checks and numbers as the CLI, said in the
// keywords' names. The declared numbers (nodes, temperature_c, threads, mueller) come in `options`.
// The drops of a phase or medium job (scatter::PhaseJob, scatter::MediumJob): radius_um (None: unset)
// in sphere_problem's range, the media by name, and a temperature_c refused where neither medium
// models one; each error names its keyword.
template <class Job>
void drops_args(Job& job, py::handle radius_arg, const std::string& medium, const std::string& surrounding) {
  if (!radius_arg.is_none()) {
    const double r = real_arg(radius_arg, "radius_um");
    require_arg("radius_um", r, 1e-6, 1e6, "um");  // scatter::sphere_problem's range
    job.radius_um = r;
  }
  job.medium = medium_arg("medium", medium);
  job.surrounding = medium_arg("surrounding", surrounding);
  if (const auto& t = job.numbers.temperature_c;
      t && !job.medium->info().temperature_dependent && !job.surrounding->info().temperature_dependent)
    throw Error(fmt::format("temperature_c {:g}: neither {} nor {} has a temperature model; leave it None", *t,
                            job.medium->info().name, job.surrounding->info().name));
}

// The library's quantities of a drop population in phase()'s and renderer_medium()'s keywords (the
// CLI's flags_for_quantity, for Python).
std::map<std::string, ArgName> drop_quantity_names() {
  return {
      {"x", {"radius_um (size parameter x)"}},
      {"m_real", {"medium, surrounding (relative index, real part)"}},
      {"m_imag", {"medium, surrounding (relative index, imaginary part)"}},
      {"radius_m", {"radius_um", 1e6}},
      {"mean_radius_m", {"radius_um", 1e6}},
      {"r_min_m", {"radius_um (smallest radius of the distribution, m)"}},
      {"r_max_m", {"radius_um (largest radius of the distribution, m)"}},
  };
}

py::dict phase(const std::string& theory, py::handle radius_arg, py::handle wavelength_arg,
               const std::string& size_distribution, const std::string& medium, const std::string& surrounding,
               py::handle angles_arg, const py::dict& options) {
  scatter::PhaseJob job;
  // None is a value only where the parameter has no default (temperature_c).
  for (const auto& f : scatter::phase_params())
    if (const py::str key(std::string(f.param.name)); options.contains(key) && options[key].is_none() &&
                                                        !std::isnan(f.get(scatter::PhaseRequest{})))
      (void)param_value(f.param, options[key]);  // "nodes: expected a whole number in [1, 4096], got None"
  apply_kwargs(job.numbers, options, scatter::phase_params());
  drops_args(job, radius_arg, medium, surrounding);
  job.wavelength_nm = real_arg(wavelength_arg, "wavelength_nm");
  if (!(job.wavelength_nm > 0 && job.wavelength_nm <= 1e6))  // as --wavelength-nm
    throw Error(fmt::format("wavelength_nm = {:g} is outside (0, 1e+06] nm", job.wavelength_nm));
  job.theory = theory;
  job.size_distribution = size_distribution;
  if (py::isinstance<py::str>(angles_arg)) {  // the CLI's text, read by the same parser: the same angles
    job.angles_deg = angles_from_text(angles_arg.cast<std::string>());
  } else {
    const DoubleArray a = c_array<double>(angles_arg, "angles_deg");
    if (a.ndim() != 1) throw Error("angles_deg: expected a 1-D array of angles in degrees");
    if (std::size_t(a.size()) > kMaxAngles)
      throw Error(fmt::format("angles_deg: {} angles, more than the limit of {}", a.size(), kMaxAngles));
    for (py::ssize_t j = 0; j < a.size(); ++j) require_arg("angles_deg", a.data()[j], 0, 180, "deg");
    job.angles_deg.assign(a.data(), a.data() + a.size());
  }
  std::map<std::string, ArgName> names = drop_quantity_names();
  names.emplace("p", ArgName{"theory (order P)"});
  scatter::PhasePlan plan;
  try {
    plan = scatter::plan_phase(std::move(job));
  } catch (const DomainError& e) {
    rethrow_named(e, names);
  }
  // The work: each radius's amplitudes at every angle, ~(x + 10) terms each.
  const auto& q = plan.quadrature;
  const double x_per_m = plan.problem.x / (plan.refine ? plan.r_min : q.radius_m.front());
  double work = plan.refine ? 1e9 : 0;  // an automatic average takes thousands of radii: cancellable
  for (const double r : q.radius_m) work += (x_per_m * r + 10) * double(plan.job.angles_deg.size() + 1);
  scatter::PhaseResult res;
  try {
    if (work > 2e7) {
      res = run_cancellable([&](const ProgressFn& progress) { return scatter::compute_phase(plan, progress); });
    } else {
      py::gil_scoped_release release;
      res = scatter::compute_phase(plan);
    }
  } catch (const DomainError& e) {
    rethrow_named(e, names);
  }
  const auto array = [](const std::vector<double>& v) { return DoubleArray(py::ssize_t(v.size()), v.data()); };
  py::dict d;
  d["angles_deg"] = array(res.angles_deg);
  d["phase"] = array(res.intensity), d["i1"] = array(res.i1), d["i2"] = array(res.i2);
  if (res.mueller) {
    const auto& mm = *res.mueller;
    d["s11"] = array(mm.s11), d["s12"] = array(mm.s12), d["s33"] = array(mm.s33), d["s34"] = array(mm.s34);
  }
  py::dict info;
  info["theory"] = res.theory, info["drops"] = res.drops, info["wavelength_nm"] = res.wavelength_nm;
  info["m"] = res.m;
  info["x"] = res.radii == 1 ? py::object(py::float_(res.x)) : py::object(py::none());
  info["radii"] = res.radii;
  const auto& used = res.quadrature;
  std::vector<double> radius_um(used.radius_m.size()), weight = used.weight;
  for (std::size_t k = 0; k < radius_um.size(); ++k) radius_um[k] = used.radius_m[k] * 1e6;
  // The automatic average's tolerance, its last halving's largest change and its estimated error per
  // Mueller element (None for one radius or a fixed count).
  info["last_change"] = res.last_change ? py::object(py::float_(*res.last_change)) : py::object(py::none());
  info["shifted_change"] = res.shifted_change ? py::object(py::float_(*res.shifted_change)) : py::object(py::none());
  if (res.error) {
    py::dict error;
    error["s11"] = res.error->s11, error["s12"] = res.error->s12, error["s33"] = res.error->s33,
    error["s34"] = res.error->s34;
    info["error"] = error;
  } else {
    info["error"] = py::none();
  }
  info["tolerance"] = res.tolerance ? py::object(py::float_(*res.tolerance)) : py::object(py::none());
  info["radius_um"] = array(radius_um), info["weight"] = array(weight);
  py::list notes;
  for (const auto& n : res.notes) notes.append(n);
  info["notes"] = notes;
  d["info"] = info;
  return d;
}

// MieResult.to_xarray(): a result of mie() (its arrays by field name, x 0-D or 1-D) as
// scatter::mie_dataset describes it, the description hydrolux mie -o phase.nc writes.
py::dict mie_dataset(std::complex<double> m, py::handle x_arg, const py::dict& fields, py::handle angles_arg,
                     const std::string& history) {
  const DoubleArray x = c_array<double>(x_arg, "x");
  if (x.ndim() > 1)
    throw Error(fmt::format("to_xarray: x has shape {}; a labelled form takes one size parameter or a 1-D array of "
                            "them (compute over x.ravel())",
                            describe(x_arg)));
  const std::size_t n = std::size_t(x.size());
  std::vector<DoubleArray> keep;
  const auto reals = [&](const char* name) -> std::span<const double> {
    if (!fields.contains(name) || fields[name].is_none()) return {};
    keep.push_back(c_array<double>(fields[name], name));
    return {keep.back().data(), std::size_t(keep.back().size())};
  };
  scatter::MieDatasetInput in;
  in.m = m;
  in.x = {x.data(), n};
  in.qext = reals("qext"), in.qsca = reals("qsca"), in.qabs = reals("qabs"), in.qback = reals("qback");
  in.g = reals("g");
  const CArray<std::int32_t> terms = c_array<std::int32_t>(fields["n_terms"], "n_terms");
  std::vector<int> nt(terms.data(), terms.data() + terms.size());
  in.n_terms = nt;
  std::vector<double> angles;
  std::vector<std::complex<double>> s1, s2;
  if (!angles_arg.is_none()) {
    const DoubleArray a = c_array<double>(angles_arg, "angles_deg");
    angles.assign(a.data(), a.data() + a.size());
    const auto amplitudes = [&](const char* name, std::vector<std::complex<double>>& out) {
      const CArray<std::complex<double>> c = c_array<std::complex<double>>(fields[name], name);
      out.assign(c.data(), c.data() + c.size());
    };
    amplitudes("s1", s1), amplitudes("s2", s2);
    in.s11 = reals("s11"), in.s12 = reals("s12"), in.s33 = reals("s33"), in.s34 = reals("s34");
  }
  in.angles_deg = angles, in.s1 = s1, in.s2 = s2;
  return dataset_dict(scatter::mie_dataset(in, history));
}

// ---- a renderer's medium ---------------------------------------------------------------------

// hydrolux medium's job (scatter/renderer_export.hpp): the file's text for a renderer and the numbers
// it holds; the declared numbers come in `options` (None: the default).
py::dict renderer_medium(py::handle radius_arg, const std::string& size_distribution, const std::string& medium,
                         const std::string& surrounding, const std::string& format, const std::string& name,
                         const py::dict& options) {
  scatter::MediumJob job;
  apply_kwargs(job.numbers, options, scatter::medium_params());
  drops_args(job, radius_arg, medium, surrounding);
  job.size_distribution = size_distribution;
  scatter::RendererFormat renderer;
  try {
    renderer = scatter::parse_renderer_format(format);
  } catch (const UnknownNameError& e) {
    throw UnknownNameError(fmt::format("format: {}", e.what()));
  }
  if (!scatter::valid_medium_name(name))
    throw Error(fmt::format("name '{}': expected 1 to 64 of A-Z a-z 0-9 _ . -", name));
  std::map<std::string, ArgName> names = drop_quantity_names();
  names.emplace("wavelength_nm", ArgName{"medium, surrounding (their data's wavelengths)"});
  scatter::MediumPlan plan;
  scatter::MediumOptics o;
  try {
    plan = scatter::plan_medium(std::move(job));
    o = run_cancellable([&](const ProgressFn& progress) { return scatter::compute_medium(plan, progress); });
  } catch (const DomainError& e) {
    rethrow_named(e, names);
  }
  const auto array = [](const std::vector<double>& v) { return DoubleArray(py::ssize_t(v.size()), v.data()); };
  py::dict d;
  d["text"] = scatter::renderer_medium_text(o, renderer, name);
  d["wavelength_nm"] = array(o.wavelength_nm);
  d["sigma_t_per_m"] = array(o.sigma_t_per_m), d["sigma_s_per_m"] = array(o.sigma_s_per_m);
  d["sigma_a_per_m"] = array(o.sigma_a_per_m), d["albedo"] = array(o.albedo);
  d["phase"] = array(o.phase.values);
  py::dict info;
  info["format"] = std::string(scatter::renderer_format_name(renderer)), info["drops"] = o.drops;
  info["number_per_m3"] = o.number_per_m3, info["lwc_g_m3"] = o.lwc_g_m3, info["scene_unit_m"] = o.scene_unit_m;
  info["extinction_per_m"] = array(o.extinction_per_m), info["scattering_per_m"] = array(o.scattering_per_m);
  info["phase_wavelength_nm"] = o.phase_wavelength_nm, info["l1_error"] = o.phase.l1_error;
  info["target_met"] = o.phase.target_met, info["cut_deg"] = o.phase.cut_deg;
  info["cut_fraction"] = o.phase.cut_fraction, info["g"] = o.phase.g, info["hg_g"] = o.phase.hg_g;
  info["hg_l1_error"] = o.phase.hg_l1, info["normalisation"] = o.phase.normalisation;
  py::list notes;  // in the keywords' names
  for (const auto& n : o.notes) notes.append(spell_quantities(n, {}));
  info["notes"] = notes;
  // A distribution's spectra: the radii chosen and the estimated error at the worst wavelength.
  if (o.spectra_error_extinction) {
    py::dict error;
    error["extinction"] = *o.spectra_error_extinction, error["g"] = *o.spectra_error_g;
    info["spectra_error"] = error;
  } else {
    info["spectra_error"] = py::none();
  }
  info["spectra_radii"] = o.spectra_radii;
  info["phase_size_l1"] = o.phase_size_l1 ? py::object(py::float_(*o.phase_size_l1)) : py::object(py::none());
  info["phase_radii"] = o.phase_radii, info["phase_radii_chosen"] = o.phase_radii_chosen;
  info["phase_smoothed"] = o.phase_smoothed;
  d["info"] = info;
  return d;
}

}  // namespace

void bind_scatter(py::module_& m) {
  m.def("mie_dataset", &mie_dataset, py::arg("m"), py::arg("x"), py::arg("fields"), py::arg("angles_deg"),
        py::arg("history"));
  namespace sc = hydrolux::scatter;
  m.def("simd_target", &sc::simd_target);
  m.def("sphere_problem", &sphere_problem, py::arg("radius_um"), py::arg("wavelength_nm"), py::arg("medium"),
        py::arg("surrounding"), py::arg("temperature_c"));
  m.def("mie", &mie, py::arg("m"), py::arg("x"), py::arg("angles_deg"), py::arg("threads"),
        py::arg("mueller") = false);
  m.def("phase", &phase, py::arg("theory"), py::arg("radius_um"), py::arg("wavelength_nm"),
        py::arg("size_distribution"), py::arg("medium"), py::arg("surrounding"), py::arg("angles_deg"),
        py::arg("options"));
  m.def("renderer_medium", &renderer_medium, py::arg("radius_um"), py::arg("size_distribution"), py::arg("medium"),
        py::arg("surrounding"), py::arg("format"), py::arg("name"), py::arg("options"));
  m.def(
      "parse_angles",
      [](const std::string& text) {
        const std::vector<double> a = angles_from_text(text);
        return DoubleArray(py::ssize_t(a.size()), a.data());
      },
      py::arg("text"));
  m.def("mie_terms", [](double x) {
    sc::mie_param("x").check(x);
    return sc::mie_terms(x);
  });
  m.def("bulk_optics", &bulk_optics, py::arg("m"), py::arg("wavenumber_per_m"), py::arg("radius_m"), py::arg("weight"),
        py::arg("threads"));

  py::class_<sc::SizeDistribution>(m, "SizeDistribution")
      .def_static("monodisperse", &sc::SizeDistribution::monodisperse, py::arg("radius_m"), py::arg("number_per_m3"))
      .def_static("gamma", &sc::SizeDistribution::gamma, py::arg("mean_radius_m"), py::arg("relative_width"),
                  py::arg("number_per_m3"))
      .def_static("log_normal", &sc::SizeDistribution::log_normal, py::arg("mean_radius_m"), py::arg("relative_width"),
                  py::arg("number_per_m3"))
      .def_static("marshall_palmer", &sc::SizeDistribution::marshall_palmer, py::arg("rain_rate_mmh"),
                  py::arg("n0_per_m4"))
      .def_property_readonly("kind",
                             [](const sc::SizeDistribution& d) {
                               switch (d.kind()) {
                                 case sc::SizeDistributionKind::monodisperse: return "monodisperse";
                                 case sc::SizeDistributionKind::gamma: return "gamma";
                                 case sc::SizeDistributionKind::log_normal: return "log_normal";
                                 default: return "marshall_palmer";
                               }
                             })
      .def("number_density",
           [](const sc::SizeDistribution& d, py::handle r_arg) {
             const DoubleArray r = c_array<double>(r_arg, "radius_m");
             DoubleArray out(shape_of(r));
             for (py::ssize_t i = 0; i < r.size(); ++i) out.mutable_data()[i] = d.number_density(r.data()[i]);
             return out;
           })
      .def("moment", &sc::SizeDistribution::moment)
      .def_property_readonly("number_concentration", &sc::SizeDistribution::number_concentration)
      .def_property_readonly("mean_radius", &sc::SizeDistribution::mean_radius)
      .def_property_readonly("radius_variance", &sc::SizeDistribution::radius_variance)
      .def_property_readonly("effective_radius", &sc::SizeDistribution::effective_radius)
      .def_property_readonly("parameters",
                             [](const sc::SizeDistribution& d) {
                               py::dict p;
                               p["alpha"] = d.alpha(), p["beta"] = d.beta(), p["mu"] = d.mu(), p["sigma"] = d.sigma();
                               p["lambda"] = d.lambda(), p["n0"] = d.n0(), p["radius"] = d.radius();
                               return p;
                             })
      .def("quadrature",
           [](const sc::SizeDistribution& d, py::handle nodes_arg, std::optional<double> r_min,
              std::optional<double> r_max, bool log_spaced) {
             const int nodes = int(whole_arg(nodes_arg, "nodes", 1, sc::kMaxQuadratureNodes));
             sc::RadiusQuadrature q;
             if (r_min || r_max) {
               if (!r_min || !r_max) throw hydrolux::Error("r_min_m, r_max_m: give both or neither");
               q = d.quadrature(nodes, *r_min, *r_max, log_spaced);
             } else {
               q = d.quadrature(nodes);
             }
             return py::make_tuple(py::array_t<double>(py::ssize_t(q.size()), q.radius_m.data()),
                                   py::array_t<double>(py::ssize_t(q.size()), q.weight.data()));
           },
           py::arg("nodes"), py::arg("r_min_m"), py::arg("r_max_m"), py::arg("log_spaced"));
}

}  // namespace hydrolux::py_bind
