// hydrolux._core: the physics with numpy in and out. The Python layer (python/hydrolux/__init__.py)
// gives each function its documented signature, defaults and result type; this module does the work
// with the GIL released for anything long. No image files here: those are in hydrolux._image, which
// loads OpenImageIO (~260 libraries) only for the code that needs it.
#include <fmt/format.h>
#include <pybind11/complex.h>
#include <pybind11/stl.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <cmath>
#include <complex>
#include <cstring>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "common.hpp"
#include "hydrolux/atmos/lee.hpp"
#include "hydrolux/color/cie.hpp"
#include "hydrolux/core/math.hpp"
#include "hydrolux/core/memory.hpp"
#include "hydrolux/core/parse.hpp"  // batch: the CLI's number parsers (parse_number, parse_integer)
#include "hydrolux/drop/render.hpp"
#include "hydrolux/drop/shape.hpp"
#include "hydrolux/drop/trace.hpp"
#include "hydrolux/drop/undistort.hpp"
#include "hydrolux/io/files.hpp"
#include "hydrolux/optics/fresnel.hpp"
#include "hydrolux/optics/media.hpp"
#include "hydrolux/rain/rain.hpp"
#include "hydrolux/scatter/amplitudes.hpp"
#include "hydrolux/scatter/mie.hpp"
#include "hydrolux/scatter/size_distribution.hpp"
#include "hydrolux/scatter/sphere.hpp"
#include "hydrolux/scatter/theories.hpp"
#include "hydrolux/scene/environment.hpp"
#include "hydrolux/version.hpp"

namespace hydrolux::py_bind {
namespace {

using DoubleArray = CArray<double>;
using ComplexArray = py::array_t<std::complex<double>>;

std::vector<py::ssize_t> shape_of(const py::array& a) { return {a.shape(), a.shape() + a.ndim()}; }

// Runs f with at most `threads` threads (0: every core).
template <class F>
auto with_threads(int threads, F&& f) {
  if (threads <= 0) return f();
  tbb::task_arena arena(threads);
  return arena.execute(std::forward<F>(f));
}

// ---- interface optics -----------------------------------------------------------------------

py::dict fresnel(py::handle theta_arg, double n1, double n2, double k2) {
  const DoubleArray theta_deg = c_array<double>(theta_arg, "theta_deg");
  require_arg("n1", n1, 1e-3, 1000);
  require_arg("n2", n2, 1e-3, 1000);
  require_arg("k2", k2, 0, 1000);
  const auto shape = shape_of(theta_deg);
  DoubleArray rs(shape), rp(shape), r(shape), t(shape), theta_t(shape);
  py::array_t<bool> tir(shape);
  const double* th = theta_deg.data();
  for (py::ssize_t i = 0; i < theta_deg.size(); ++i) require_arg("theta_deg", th[i], 0, 90, "deg");
  const double nan = std::nan("");
  for (py::ssize_t i = 0; i < theta_deg.size(); ++i) {
    const double cos_i = std::cos(deg_to_rad(th[i]));
    if (k2 > 0) {
      const auto f = optics::fresnel_conductor(cos_i, n1, std::complex<double>(n2, k2));
      rs.mutable_data()[i] = f.R_s, rp.mutable_data()[i] = f.R_p, r.mutable_data()[i] = f.R;
      t.mutable_data()[i] = nan, theta_t.mutable_data()[i] = nan, tir.mutable_data()[i] = false;
    } else {
      const auto f = optics::fresnel_dielectric(cos_i, n1, n2);
      rs.mutable_data()[i] = f.R_s, rp.mutable_data()[i] = f.R_p, r.mutable_data()[i] = f.R;
      t.mutable_data()[i] = f.T;
      theta_t.mutable_data()[i] = f.tir ? nan : rad_to_deg(safe_acos(f.cos_t));
      tir.mutable_data()[i] = f.tir;
    }
  }
  py::dict d;
  d["theta_t_deg"] = theta_t, d["rs"] = rs, d["rp"] = rp, d["r"] = r, d["t"] = t, d["tir"] = tir;
  return d;
}

std::shared_ptr<const optics::Medium> medium_arg(const char* arg, const std::string& name) {
  try {
    return optics::find_medium(name);
  } catch (const UnknownNameError& e) {
    throw UnknownNameError(fmt::format("{}: {}", arg, e.what()));
  } catch (const DomainError& e) {
    throw Error(fmt::format("{} {}: {} {:g} is {}", arg, name, e.quantity(), e.value(), e.range_text()));
  }
}

py::list media() {
  py::list out;
  for (const auto& name : optics::medium_names()) {
    const auto& i = optics::find_medium(name)->info();
    py::dict d;
    d["medium"] = i.name, d["description"] = i.description, d["source"] = i.source;
    d["wavelength_nm"] = py::make_tuple(i.lambda_min_nm, i.lambda_max_nm);
    d["temperature_c"] = py::make_tuple(i.temperature_min_c, i.temperature_max_c);
    d["default_temperature_c"] = i.default_temperature_c;
    d["temperature_dependent"] = i.temperature_dependent;
    d["conductor"] = i.conductor;
    out.append(d);
  }
  return out;
}

ComplexArray refractive_index(const std::string& medium, py::handle wavelength_arg,
                              std::optional<double> temperature_c) {
  const DoubleArray wavelength_nm = c_array<double>(wavelength_arg, "wavelength_nm");
  const auto med = medium_arg("medium", medium);
  ComplexArray out(shape_of(wavelength_nm));
  const double* w = wavelength_nm.data();
  for (py::ssize_t i = 0; i < wavelength_nm.size(); ++i) out.mutable_data()[i] = med->index(w[i], temperature_c);
  return out;
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
  for (py::ssize_t i = 0; i < n; ++i)
    require_arg("x", x[i], scatter::kMieMinSizeParameter, scatter::kMieMaxSizeParameter);
  // m's domain by the library's own check (named m_real / m_imag), once, before any work.
  scatter::MieCoefficients probe;
  try {
    scatter::mie_coefficients(m, 1.0, probe, 1);
  } catch (const DomainError& e) {
    throw Error(fmt::format("m = ({:g}{:+g}j): {} {:g} is {}", m.real(), m.imag(), e.quantity(), e.value(),
                            e.range_text()));
  }
}

py::dict mie(std::complex<double> m, py::handle x_arg, py::handle angles_arg, py::handle threads_arg) {
  const int threads = int(whole_arg(threads_arg, "threads", 0, 1024));
  const DoubleArray x = c_array<double>(x_arg, "x");
  std::optional<DoubleArray> angles_deg;
  if (!angles_arg.is_none()) angles_deg = c_array<double>(angles_arg, "angles_deg");
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
  const int threads = int(whole_arg(threads_arg, "threads", 0, 1024));
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

// ---- Lee tables -----------------------------------------------------------------------------

atmos::LeeTableKind lee_kind(const std::string& table) {
  if (table == "rainbow") return atmos::LeeTableKind::rainbow;
  if (table == "corona") return atmos::LeeTableKind::corona;
  if (table == "glory") return atmos::LeeTableKind::glory;
  throw UnknownNameError(fmt::format("table '{}': expected rainbow, corona or glory", table));
}

py::dict lee(const std::string& table, const std::string& theory, std::optional<std::pair<double, double>> radius_um,
             std::optional<std::pair<double, double>> angle_deg,
             std::optional<std::pair<py::object, py::object>> size_arg,
             const std::string& radius_scale, const std::string& axis, double sun_disk_deg, bool limb_darkening,
             double size_spread, std::pair<double, double> wavelengths_nm, py::handle wavelengths_arg,
             std::optional<double> temperature_c, const std::string& medium, const std::string& sun,
             const std::string& color_space, double sampling, py::handle seed_arg, py::handle threads_arg) {
  // The whole numbers first, as the CLI's flags (--size's [1, 16384], --seed, --threads).
  std::optional<std::pair<int, int>> size;
  if (size_arg)
    size.emplace(int(whole_arg(size_arg->first, "size[0] (columns)", 1, 16384)),
                 int(whole_arg(size_arg->second, "size[1] (rows)", 1, 16384)));
  const int wavelengths = int(whole_arg(wavelengths_arg, "wavelengths", 0, 2000));
  const long long seed = whole_arg(seed_arg, "seed", 0, static_cast<long long>(rain::kMaxSeed));
  const int threads = int(whole_arg(threads_arg, "threads", 0, 1024));
  atmos::LeeSpec s = atmos::default_lee_spec(lee_kind(table));
  s.theory = scatter::parse_theory(theory);  // its errors name the theory and its value, and list the valid ones
  bool single = false;
  if (radius_um) {
    if (radius_um->second < radius_um->first) throw Error("radius_um: expected (A, B) with A <= B, micrometres");
    s.radius_min_um = radius_um->first, s.radius_max_um = radius_um->second;
    single = radius_um->first == radius_um->second;
  }
  if (angle_deg) {
    if (angle_deg->second < angle_deg->first) throw Error("angle_deg: expected (A, B) with A <= B, degrees");
    s.angle_min_deg = angle_deg->first, s.angle_max_deg = angle_deg->second;
  }
  if (single) s.columns = 1;
  if (size) {
    s.columns = size->first, s.rows = size->second;
    if (single && s.columns != 1)
      throw Error(fmt::format("size ({}, {}): a single radius makes one column; give size=(1, {})", size->first,
                              size->second, size->second));
  }
  if (s.rows > 1 && s.angle_min_deg == s.angle_max_deg)
    throw Error(fmt::format("angle_deg: a table of {} rows needs A < B (or one row)", s.rows));
  if (radius_scale != "log" && radius_scale != "linear")
    throw UnknownNameError(fmt::format("radius_scale '{}': expected log or linear", radius_scale));
  s.radius_scale = radius_scale == "log" ? atmos::RadiusScale::log : atmos::RadiusScale::linear;
  if (axis != "angle" && axis != "cos") throw UnknownNameError(fmt::format("axis '{}': expected angle or cos", axis));
  s.axis = axis == "angle" ? atmos::AngleAxis::angle : atmos::AngleAxis::cosine;
  s.sun_disk_deg = sun_disk_deg;
  s.limb_darkening = limb_darkening;
  s.size_spread = size_spread;
  if (wavelengths_nm.second < wavelengths_nm.first) throw Error("wavelengths_nm: expected (A, B) with A <= B");
  s.wavelength_min_nm = wavelengths_nm.first, s.wavelength_max_nm = wavelengths_nm.second;
  s.wavelengths = wavelengths;
  s.drop_medium = medium;
  const auto drop = medium_arg("medium", medium);
  if (temperature_c && drop->info().temperature_dependent)
    require_arg("temperature_c", *temperature_c, drop->info().temperature_min_c, drop->info().temperature_max_c, "C");
  else if (temperature_c)
    throw Error(fmt::format("temperature_c {:g}: {} has no temperature model; leave it None", *temperature_c,
                            drop->info().name));
  s.temperature_c = temperature_c;
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
  s.sampling = sampling;
  s.seed = std::uint64_t(seed);
  s.threads = threads;
  try {
    atmos::validate(s);
  } catch (const DomainError& e) {
    rethrow_named(e, {{"radius_um", {"radius_um"}}, {"angle_deg", {"angle_deg"}}, {"columns", {"size[0] (columns)"}},
                      {"rows", {"size[1] (rows)"}}, {"wavelength_nm", {"wavelengths_nm"}}});
  }
  const atmos::LeeTable t = run_cancellable([&](const ProgressFn& p) { return atmos::compute_lee_table(s, p); });
  const atmos::LeeImages im = atmos::lee_images(t);
  const py::ssize_t rows = t.rows(), cols = t.columns();
  py::array_t<double> xyz({rows, cols, py::ssize_t(3)}), rgb({rows, cols, py::ssize_t(3)});
  std::memcpy(xyz.mutable_data(), t.xyz.data(), t.xyz.size() * sizeof(double));
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      const auto v = t.rgb(r, c);
      for (int k = 0; k < 3; ++k) rgb.mutable_data()[(std::size_t(r) * cols + c) * 3 + k] = v[std::size_t(k)];
    }
  py::array_t<float> display({rows, cols, py::ssize_t(3)});
  std::memcpy(display.mutable_data(), im.display.data(), im.display.size() * sizeof(float));
  py::dict d;
  d["rgb"] = rgb, d["xyz"] = xyz, d["display"] = display;
  d["radius_um"] = py::array_t<double>(py::ssize_t(t.radius_um.size()), t.radius_um.data());
  d["angle_deg"] = py::array_t<double>(py::ssize_t(t.angle_deg.size()), t.angle_deg.data());
  d["cos_angle"] = py::array_t<double>(py::ssize_t(t.cos_angle.size()), t.cos_angle.data());
  d["wavelengths_nm"] = py::array_t<double>(py::ssize_t(t.wavelengths_nm.size()), t.wavelengths_nm.data());
  d["theory"] = scatter::theory_name(s.theory);
  d["color_space"] = std::string(color::rgb_space_name(s.rgb_space));
  d["exposure"] = im.exposure, d["white"] = im.white;
  d["evaluations"] = t.work.evaluations;
  return d;
}

// ---- the drop -------------------------------------------------------------------------------

py::array_t<float> drop_render(std::optional<py::array> env, double radius_mm, double distance_m, double focal_mm,
                               double f_number, std::optional<double> frame_mm, py::handle size_arg,
                               py::handle samples_arg, py::handle internal_arg,
                               const std::string& medium, std::optional<double> temperature_c, double wavelength_nm,
                               bool dispersion, bool background_blur, bool background, double exposure_ev,
                               const std::string& method, const std::string& shape, py::handle depth_arg) {
  // The CLI's ranges (tools/hydrolux/cmd_drop_render.cpp), in the same order.
  require_arg("radius_mm", radius_mm, 0.01, 100, "mm");
  require_arg("distance_m", distance_m, 0.001, 1e4, "m");
  require_arg("focal_mm", focal_mm, 1, 2000, "mm");
  require_arg("f_number", f_number, 0.5, 128);
  if (frame_mm) require_arg("frame_mm", *frame_mm, 1e-6, 1e6, "mm");
  const int size = int(whole_arg(size_arg, "size", 8, 16384, "px"));
  const int samples = int(whole_arg(samples_arg, "samples", 1, 64));
  const int internal = int(whole_arg(internal_arg, "internal", 0, 20));
  if (temperature_c) require_arg("temperature_c", *temperature_c, -273.15, 1000, "C");
  require_arg("wavelength_nm", wavelength_nm, 200, 2500, "nm");
  require_arg("exposure_ev", exposure_ev, -30, 30);
  const int depth = int(whole_arg(depth_arg, "depth", 6, 64));
  if (method != "model" && method != "exact") throw UnknownNameError("method '" + method + "': expected model or exact");
  if (shape != "sphere" && shape != "beard-chuang")
    throw UnknownNameError("shape '" + shape + "': expected sphere or beard-chuang");
  const auto water = medium_arg("medium", medium);
  const auto air = optics::find_medium("air");
  if (temperature_c && water->info().temperature_dependent)
    require_arg("temperature_c", *temperature_c, water->info().temperature_min_c, water->info().temperature_max_c, "C");
  else if (temperature_c)
    throw Error(fmt::format("temperature_c {:g}: {} has no temperature model; leave it None", *temperature_c,
                            water->info().name));
  if (distance_m <= 1.01 * radius_mm * 1e-3)
    throw Error(fmt::format("distance_m {:g} must exceed the drop radius ({:g} m) by at least 1%", distance_m,
                            radius_mm * 1e-3));
  if (shape == "beard-chuang") {
    const auto range = drop::drop_shape_radius_range_m();
    require_arg("radius_mm (Beard & Chuang shape)", radius_mm, range[0] * 1e3, range[1] * 1e3, "mm");
  }
  if (method == "model" && shape != "sphere")
    throw Error("shape " + shape + ": the model is for a sphere; use method='exact' for other shapes");
  double blur_rad = 0;
  if (background_blur) {
    if (distance_m <= 1.01 * focal_mm * 1e-3)
      throw Error(fmt::format("distance_m {:g} must exceed the focal length (focal_mm {:g}) to focus on the drop",
                              distance_m, focal_mm));
    blur_rad = drop::defocus_blur_radius_rad(focal_mm * 1e-3, f_number, distance_m);
    if (blur_rad > kPi<> / 6)
      throw Error(fmt::format("background_blur: focal_mm {:g} at f_number {:g} focused at distance_m {:g} gives a "
                              "defocus disk {:.1f} degrees wide; at most 60 degrees is supported",
                              focal_mm, f_number, distance_m, 2 * rad_to_deg(blur_rad)));
  }
  const auto relative = [&](double nm) { return water->n(nm, temperature_c) / air->n(nm); };
  drop::ChannelIndex mu;
  if (dispersion) {
    for (std::size_t c = 0; c < 3; ++c) mu[c] = relative(drop::kChannelWavelengthsNm[c]);
  } else {
    mu.fill(relative(wavelength_nm));
  }
  std::unique_ptr<scene::Environment> environment;
  if (env) {
    environment = std::make_unique<scene::EquirectEnvironment>(to_image(*env, "env"));
  } else {
    environment = std::make_unique<scene::BuiltinSky>();
  }
  drop::DropCamera cam;
  cam.radius_m = radius_mm * 1e-3;
  cam.distance_m = distance_m;
  cam.frame_m = (frame_mm ? *frame_mm : 5.0 * radius_mm) * 1e-3;
  cam.width = cam.height = size;
  try {
    drop::validate(cam);
  } catch (const DomainError& e) {
    rethrow_named(e, {{"radius_m", {"radius_mm", 1e3}}, {"distance_m", {"distance_m"}}, {"frame_m", {"frame_mm", 1e3}},
                      {"width", {"size"}}, {"height", {"size"}}});
  }
  Image img = run_cancellable([&](const ProgressFn& progress) {
    drop::RenderOptions opt;
    opt.samples_per_axis = samples;
    opt.n_internal = internal;
    opt.background = background;
    opt.background_blur_rad = blur_rad;
    opt.progress = progress;
    if (method == "model") return drop::render_model(cam, *environment, mu, opt);
    const auto surface = drop::make_drop_surface(
        cam, shape == "sphere" ? drop::DropShapeKind::sphere : drop::DropShapeKind::beard_chuang);
    drop::TraceOptions trace;
    trace.max_depth = depth;
    return drop::render_exact(cam, *environment, mu, *surface, opt, trace);
  });
  const float gain = float(std::exp2(exposure_ev));
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x)
      for (int c = 0; c < 3; ++c) img.at(x, y, c) *= gain;
  return to_array(img);
}

py::array_t<float> drop_undistort(const py::array& image, std::pair<double, double> drop_center, double drop_radius_px,
                                  double mu, double fov_deg, double yaw_deg, double pitch_deg,
                                  std::pair<py::object, py::object> size, bool transmission_correction) {
  require_arg("mu", mu, 1.0001, 10);  // the CLI's --mu
  drop::UndistortView view;
  view.yaw_deg = yaw_deg, view.pitch_deg = pitch_deg, view.fov_deg = fov_deg;
  view.width = int(whole_arg(size.first, "size[0] (width)", 1, 16384, "px"));
  view.height = int(whole_arg(size.second, "size[1] (height)", 1, 16384, "px"));
  try {
    drop::validate(view);
  } catch (const DomainError& e) {
    rethrow_named(e, {{"width", {"size[0] (width)"}}, {"height", {"size[1] (height)"}}});
  }
  const Image in = to_image(image, "image");
  Image out;
  try {
    py::gil_scoped_release release;
    out = drop::undistort(in, drop_center.first, drop_center.second, drop_radius_px, mu, view, transmission_correction);
  } catch (const DomainError& e) {
    rethrow_named(e, {{"radius_px", {"drop_radius_px"}}, {"center_x_px", {"drop_center[0]"}},
                      {"center_y_px", {"drop_center[1]"}}});
  }
  return to_array(out);
}

// ---- rain -----------------------------------------------------------------------------------

const std::map<std::string, ArgName>& rain_names() {
  static const std::map<std::string, ArgName> names = {{"height_m", {"camera_height_m"}}};
  return names;
}

// hydrolux rain's flag ranges (tools/hydrolux/cmd_rain.cpp), checked first so that Python refuses
// what the CLI refuses (the library's checks then add the ranges that depend on other values).
void check_rain_ranges(const py::dict& kw) {
  struct Range {
    const char* name;
    double lo, hi;
    const char* unit;
  };
  static constexpr Range ranges[] = {
      {"rate_mmh", 0, 500, "mm/h"},      {"wind_mps", 0, 50, "m/s"},        {"wind_dir_deg", -360, 360, "deg"},
      {"exposure_s", 1e-6, 1, "s"},      {"focal_mm", 1, 2000, "mm"},       {"fov_deg", 1, 170, "deg"},
      {"sensor_width_mm", 1, 100, "mm"}, {"pixel_pitch_um", 0.1, 1000, "um"}, {"f_number", 0, 64, ""},
      {"focus_m", 0.01, 1e4, "m"},       {"fps", 0.01, 1000, "1/s"},        {"camera_height_m", 0, 1000, "m"},
      {"pitch_deg", -80, 80, "deg"},     {"near_m", 0.05, 100, "m"},        {"far_m", 0.1, 1e4, "m"},
      {"min_radius_mm", 0.04, 2.9, "mm"}, {"max_radius_mm", 0.04, 2.9, "mm"}, {"min_alpha", 1e-5, 0.5, ""},
      {"extent_m", 0, 1e5, "m"},         {"backdrop_m", 1, 1e5, "m"},       {"oscillation", 0, 0.5, ""}};
  for (const auto& r : ranges)
    if (kw.contains(r.name) && !kw[r.name].is_none())
      require_arg(r.name, real_arg(kw[r.name], r.name), r.lo, r.hi, r.unit);
}

// The camera for a frame of width x height, as hydrolux rain makes it from its flags.
rain::RainCamera rain_camera(const py::dict& kw, int width, int height) {
  check_rain_ranges(kw);
  rain::RainCamera c;
  c.width = width, c.height = height;
  const auto get = [&](const char* k, double& v) {
    if (kw.contains(k) && !kw[k].is_none()) v = real_arg(kw[k], k);
  };
  get("focal_mm", c.focal_mm);
  get("sensor_width_mm", c.sensor_width_mm);
  get("f_number", c.f_number);
  get("focus_m", c.focus_m);
  get("exposure_s", c.exposure_s);
  get("fps", c.fps);
  get("camera_height_m", c.height_m);
  get("pitch_deg", c.pitch_deg);
  if (kw.contains("pixel_pitch_um") && !kw["pixel_pitch_um"].is_none()) {
    const double p = real_arg(kw["pixel_pitch_um"], "pixel_pitch_um");
    require_arg("pixel_pitch_um", p, 0.1, 1000, "um");
    c.sensor_width_mm = p * 1e-3 * width;
  }
  if (kw.contains("fov_deg") && !kw["fov_deg"].is_none()) {
    const double f = real_arg(kw["fov_deg"], "fov_deg");
    require_arg("fov_deg", f, 1, 170, "deg");
    c.focal_mm = rain::focal_mm_from_fov(f, c.sensor_width_mm);
  }
  try {
    rain::validate(c);
  } catch (const DomainError& e) {
    if (e.quantity() == "sensor_width_mm" && kw.contains("pixel_pitch_um") && !kw["pixel_pitch_um"].is_none())
      throw Error(fmt::format("pixel_pitch_um = {:g}: x {} px gives a sensor {:g} mm wide, outside [1, 100] mm",
                              real_arg(kw["pixel_pitch_um"], "pixel_pitch_um"), width, e.value()));
    rethrow_named(e, rain_names());
  }
  return c;
}

rain::RainSettings rain_settings(const py::dict& kw) {
  check_rain_ranges(kw);
  rain::RainSettings s;
  const auto get = [&](const char* k, double& v) {
    if (kw.contains(k) && !kw[k].is_none()) v = real_arg(kw[k], k);
  };
  get("rate_mmh", s.rate_mmh);
  get("wind_mps", s.wind_mps);
  get("wind_dir_deg", s.wind_dir_deg);
  get("near_m", s.near_m);
  get("far_m", s.far_m);
  get("min_radius_mm", s.min_radius_mm);
  get("max_radius_mm", s.max_radius_mm);
  get("min_alpha", s.min_alpha);
  get("extent_m", s.extent_m);
  get("backdrop_m", s.backdrop_m);
  get("oscillation", s.oscillation);
  // The seed as the CLI's --seed takes it: a whole number in [0, rain::kMaxSeed], in the same words.
  if (kw.contains("seed"))
    s.seed = std::uint64_t(whole_arg(kw["seed"], "seed", 0, static_cast<long long>(rain::kMaxSeed)));
  if (kw.contains("unresolved")) s.unresolved = flag_arg(kw["unresolved"], "unresolved");
  try {
    rain::validate(s);
  } catch (const DomainError& e) {
    rethrow_named(e, rain_names());
  }
  return s;
}

py::dict stats_dict(const rain::RainStats& s) {
  py::dict d;
  d["drops_total"] = s.drops_total, d["drops_in_view"] = s.drops_in_view, d["drops_visible"] = s.drops_visible;
  py::dict len, width;
  len["mean"] = s.streak_length_px_mean, len["p50"] = s.streak_length_px_p50, len["p95"] = s.streak_length_px_p95;
  len["max"] = s.streak_length_px_max;
  width["mean"] = s.streak_width_px_mean, width["max"] = s.streak_width_px_max;
  d["streak_length_px"] = len, d["streak_width_px"] = width;
  d["drop_luminance_mean"] = s.drop_luminance_mean;
  d["background_luminance_under_streaks"] = s.background_luminance_mean;
  d["streak_luminance_gain"] = s.streak_luminance_gain;
  d["streak_pixel_fraction"] = s.streak_pixel_fraction;
  d["alpha_mean"] = s.alpha_mean;
  d["unresolved_transmittance_mean"] = s.unresolved_transmittance_mean;
  d["negative_values_clamped"] = s.negative_values_clamped;  // the image's negative RGB values, read as 0
  return d;
}

// One rain for one camera: a sequence's frames go through one renderer (its field is built once).
class PyRainRenderer {
 public:
  PyRainRenderer(py::handle width_arg, py::handle height_arg, bool ground_plane, const py::dict& kw) {
    const int width = int(whole_arg(width_arg, "width", 16, 16384, "px"));
    const int height = int(whole_arg(height_arg, "height", 16, 16384, "px"));
    const rain::RainSettings s = rain_settings(kw);
    const rain::RainCamera c = rain_camera(kw, width, height);
    py::gil_scoped_release release;
    try {
      renderer_ = std::make_unique<rain::RainRenderer>(rain::RainField(s, c, ground_plane));
    } catch (const rain::TooManyDrops& e) {
      throw Error(fmt::format("min_alpha {:g}: the rain field would hold {:.3g} drops, more than the limit of {:.3g}; "
                              "raise min_alpha, near_m or min_radius_mm, or lower far_m or rate_mmh",
                              s.min_alpha, e.drops(), double(rain::RainField::kMaxDrops)));
    }
  }

  py::dict render(const py::array& image, std::optional<py::array> depth, py::handle frame_arg, bool with_layer) {
    const long long frame_index = whole_arg(frame_arg, "frame_index", 0, 1000000000);
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
  const int width = int(whole_arg(width_arg, "width", 16, 16384, "px"));
  const int height = int(whole_arg(height_arg, "height", 16, 16384, "px"));
  const rain::RainCamera c = rain_camera(kw, width, height);
  Image img;
  {
    py::gil_scoped_release release;
    img = rain::builtin_scene(c);
  }
  return to_array(img);
}

// ---- files ----------------------------------------------------------------------------------

// At most n threads for every parallel loop of this process from now on (0: every core again).
void set_threads(py::handle threads) {
  const int n = int(whole_arg(threads, "threads", 0, 1024));
  static std::unique_ptr<tbb::global_control> limit;
  limit.reset();
  if (n > 0) limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, std::size_t(n));
}

void write_file(const std::string& path, const py::bytes& data, const std::string& label) {
  std::string bytes = data;
  py::gil_scoped_release release;
  io::write_file(path, bytes, label);
}

}  // namespace
}  // namespace hydrolux::py_bind

PYBIND11_MODULE(_core, m) {
  using namespace hydrolux::py_bind;
  namespace sc = hydrolux::scatter;
  register_errors();
  m.doc() = "hydrolux's physics with numpy in and out (use the hydrolux package, which documents each call)";
  m.attr("__version__") = hydrolux::kVersion;
  m.def("simd_target", &sc::simd_target);
  m.def("fresnel", &fresnel, py::arg("theta_deg"), py::arg("n1"), py::arg("n2"), py::arg("k2"));
  m.def("media", &media);
  m.def("refractive_index", &refractive_index, py::arg("medium"), py::arg("wavelength_nm"), py::arg("temperature_c"));
  m.def("sphere_problem", &sphere_problem, py::arg("radius_um"), py::arg("wavelength_nm"), py::arg("medium"),
        py::arg("surrounding"), py::arg("temperature_c"));
  m.def("mie", &mie, py::arg("m"), py::arg("x"), py::arg("angles_deg"), py::arg("threads"));
  m.def("mie_terms", [](double x) {
    require_arg("x", x, sc::kMieMinSizeParameter, sc::kMieMaxSizeParameter);
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
      .def_static("marshall_palmer", &sc::SizeDistribution::marshall_palmer, py::arg("rain_rate_mm_per_h"),
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

  m.def("lee", &lee, py::arg("table"), py::arg("theory"), py::arg("radius_um"), py::arg("angle_deg"), py::arg("size"),
        py::arg("radius_scale"), py::arg("axis"), py::arg("sun_disk_deg"), py::arg("limb_darkening"),
        py::arg("size_spread"), py::arg("wavelengths_nm"), py::arg("wavelengths"), py::arg("temperature_c"),
        py::arg("medium"), py::arg("sun"), py::arg("color_space"), py::arg("sampling"), py::arg("seed"),
        py::arg("threads"));
  m.def("drop_render", &drop_render, py::arg("env"), py::arg("radius_mm"), py::arg("distance_m"), py::arg("focal_mm"),
        py::arg("f_number"), py::arg("frame_mm"), py::arg("size"), py::arg("samples"), py::arg("internal"),
        py::arg("medium"), py::arg("temperature_c"), py::arg("wavelength_nm"), py::arg("dispersion"),
        py::arg("background_blur"), py::arg("background"), py::arg("exposure_ev"), py::arg("method"), py::arg("shape"),
        py::arg("depth"));
  m.def("drop_undistort", &drop_undistort, py::arg("image"), py::arg("drop_center"), py::arg("drop_radius_px"),
        py::arg("mu"), py::arg("fov_deg"), py::arg("yaw_deg"), py::arg("pitch_deg"), py::arg("size"),
        py::arg("transmission_correction"));
  py::class_<PyRainRenderer>(m, "RainRenderer")
      .def(py::init<py::handle, py::handle, bool, const py::dict&>(), py::arg("width"), py::arg("height"),
           py::arg("ground_plane"), py::arg("options"))
      .def("render", &PyRainRenderer::render, py::arg("image"), py::arg("depth"), py::arg("frame_index"),
           py::arg("with_layer"))
      .def("field_info", &PyRainRenderer::field_info);
  m.def("builtin_scene", &builtin_scene, py::arg("width"), py::arg("height"), py::arg("options"));
  m.def("set_threads", &set_threads, py::arg("threads"));
  m.def("write_file", &write_file, py::arg("path"), py::arg("data"), py::arg("label"));
  // ---- batch: the CLI's own number parsers (python/hydrolux/batch parses every numeric flag with them) ----
  // parse_number: a finite decimal number, the whole text or None; parse_integer: a whole number
  // within +-2^53, also in exponent form ("1e3"), or None. Exactly what the CLI's flags accept.
  m.def("parse_number", [](const std::string& text) { return hydrolux::parse::number(text); }, py::arg("text"));
  m.def("parse_integer", [](const std::string& text) { return hydrolux::parse::integer(text); }, py::arg("text"));
  // The largest seed every door accepts (rain::kMaxSeed, 2^53).
  m.attr("kMaxSeed") = py::int_(hydrolux::rain::kMaxSeed);
  // The files of one run declared as the CLI declares them (io::FileSet): each input must be a regular
  // file; each planned output must not be an input or another output (through links too), a folder or a
  // device. OSError (the library's IoError) naming both files otherwise. Pairs are (label, path).
  m.def(
      "check_files",
      [](const std::vector<std::pair<std::string, std::string>>& inputs,
         const std::vector<std::pair<std::string, std::string>>& outputs) {
        hydrolux::io::FileSet files;
        for (const auto& [label, path] : inputs) files.input(label, path);
        for (const auto& [label, path] : outputs) files.planned_output(label, path);
      },
      py::arg("inputs"), py::arg("outputs"));
  // A value as an error message shows it (short, never an array's contents): the bindings' own words.
  m.def("describe", [](py::handle v) { return describe(v); }, py::arg("value"));
  // A text as hydrolux prints it in a message: one line that cannot drive the terminal.
  m.def("printable", [](const std::string& text) { return hydrolux::printable(text); }, py::arg("text"));
  // The memory this process can still expect to get, in bytes (core/memory.hpp).
  m.def("available_memory_bytes", [] { return hydrolux::available_memory_bytes(); });
  // ---- end batch ----
}
