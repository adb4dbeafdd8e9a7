#include "hydrolux/scatter/renderer_export.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <functional>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <tuple>
#include <utility>

#include "hydrolux/core/error.hpp"
#include "hydrolux/core/math.hpp"
#include "hydrolux/optics/media.hpp"
#include "hydrolux/scatter/params.hpp"
#include "hydrolux/scatter/size_distribution.hpp"
#include "hydrolux/scatter/sphere.hpp"
#include "hydrolux/scatter/theories.hpp"
#include "hydrolux/version.hpp"

namespace hydrolux::scatter {

namespace {

using K = ParamKind;

const Field<MediumRequest> kMedium[] = {
    {{"number_per_cm3", "--number-per-cm3", "drops", K::real, "cm^-3", 1e-6, 1e24,
      "Drops per cubic centimetre (fog 10-500, cloud 100-1000); or --lwc-g-m3; neither for marshall-palmer rain"},
     HYDROLUX_PARAM_OPTIONAL(number_per_cm3)},
    {{"lwc_g_m3", "--lwc-g-m3", "drops", K::real, "g/m^3", 1e-9, 1e4,
      "Liquid water content instead of the count (fog 0.01-0.5, cloud 0.1-1)", "number_per_cm3"},
     HYDROLUX_PARAM_OPTIONAL(lwc_g_m3)},
    {{"nodes", "--nodes", "drops", K::integer, "", 1, kMaxQuadratureNodes,
      "Radii in the phase's size average (Gauss-Legendre in ln r); default: gamma and lognormal from 64, doubled "
      "until twice as many move the phase by at most half of --max-error (L1 over the sphere); 64 for "
      "marshall-palmer",
      {}, kNodesOnlyWith, {}, kNodesWhy},
     HYDROLUX_PARAM_OPTIONAL(nodes)},
    {{"spectra_tolerance", "--spectra-tolerance", "drops", K::real, "", 1e-4, 0.2,
      "Relative error allowed in the spectra's size average at every wavelength (extinction, scattering, "
      "absorption, g), default 0.005: their evenly spaced radii are halved until two grids agree to half of it",
      {}, kNodesOnlyWith, {}, "{size_distribution=} is one radius, with nothing to average (omit {spectra_tolerance})"},
     HYDROLUX_PARAM_OPTIONAL(spectra_tolerance)},
    {{"temperature_c", "--temperature-c", "media", K::real, "C", kMinTemperatureC, kMaxTemperatureC,
      "Temperature in Celsius of the media that model it (water: 0 to 100); refused when neither medium does"},
     HYDROLUX_PARAM_OPTIONAL(temperature_c)},
    {{"phase_wavelength_nm", "--phase-wavelength-nm", "phase", K::real, "nm", kExportMinNm, kExportMaxNm,
      "Vacuum wavelength of the one phase table (and of pbrt's g); the coefficients are spectral, 360-830 nm"},
     HYDROLUX_PARAM_MEMBER(phase_wavelength_nm)},
    {{"values", "--values", "phase", K::integer, "", 3, kMaxTableValues,
      "Values in the phase table (uniform in cos theta); default: the smallest 2^k + 1 in [257, 65537] that "
      "meets --max-error"},
     HYDROLUX_PARAM_OPTIONAL(values)},
    {{"max_error", "--max-error", "phase", K::real, "", 1e-6, 2,
      "The L1 error over the sphere (table as the renderer interpolates it vs the Mie phase) the automatic table "
      "size and forward cut aim at"},
     HYDROLUX_PARAM_MEMBER(max_error)},
    {{"forward_cut_deg", "--forward-cut-deg", "phase", K::real, "deg", 0, 90,
      "Light scattered within this angle of forward is treated as unscattered (0: none); default: none, or the "
      "smallest cut up to 2 deg that meets --max-error where the forward peak is beyond 65537 values (rain)"},
     HYDROLUX_PARAM_OPTIONAL(forward_cut_deg)},
    {{"scene_unit_m", "--scene-unit-m", "renderer", K::real, "m", 1e-9, 1e9,
      "Length of one scene unit in metres: the renderers' scale turns the m^-1 coefficients into per scene unit"},
     HYDROLUX_PARAM_MEMBER(scene_unit_m)},
    {{"threads", "--threads", "run", K::integer, "", 0, kMaxThreads, "Worker threads (0 = all cores)"},
     HYDROLUX_PARAM_MEMBER(threads)},
};

std::vector<double> spectral_grid() {
  std::vector<double> nm;
  for (double l = kExportMinNm; l <= kExportMaxNm + 1e-9; l += kExportStepNm) nm.push_back(l);
  return nm;
}

// "water in air", with the temperature where a medium models it.
std::string media_text(const MediumJob& job) {
  std::string t = job.medium->info().name + " in " + job.surrounding->info().name;
  if (job.numbers.temperature_c) t += fmt::format(" at {:g} C", *job.numbers.temperature_c);
  return t;
}

// Never "--" inside an XML comment.
std::string xml_comment_text(std::string s) {
  for (std::size_t pos; (pos = s.find("--")) != std::string::npos;) s.replace(pos, 2, "- -");
  return s;
}

using Report = std::function<void(double, std::string_view)>;

// Rain's phase, each radius smoothed over angle first (docs/renderer-export.md, "Rain"): on a grid
// uniform in theta over [0, pi], per steradian (the average of (|S1|^2 + |S2|^2) / 2 over n(r) times
// 1 / (k^2 mean C_sca)), linear between its points.
struct SmoothedPhase {
  double step = 0;
  std::vector<double> p;
  double at(double theta) const {
    const double u = std::clamp(theta / step, 0.0, double(p.size() - 1));
    const std::size_t i = std::min(std::size_t(u), p.size() - 2);
    return p[i] + (p[i + 1] - p[i]) * (u - double(i));
  }
};

// Each radius's intensity ripples in angle: the rays that leave a drop beat with angular periods of
// 2 pi / (x db), db the difference of their impact parameters (up to 2), so down to pi / x, finer than
// a table can hold at rain's x up to 34,000; a few dozen radii average that ripple at random phases
// (64 radii left Marshall-Palmer rain's phase 0.04 off in L1, measured against 134,841 radii). So each
// radius's (|S1|^2 + |S2|^2) / 2 is first averaged over angle with a Hann window of half-width
// W = kRainSmoothingPeriods 2 pi / x, at most kRainSmoothingAngleRatio theta (the forward peak keeps
// its shape), on its own grid of kRainSmoothingPoints points per W (2 per pi / x, the fastest beat,
// where the Hann window passes nothing), reflected at 0 and pi; then the radii are averaged on a
// common grid as fine as the finest of theirs. What the drops' pattern holds at wider scales (the
// bows: Airy's width ~ x^(-2/3) rad) is kept. `report` rises from `from` to `to`, each radius
// weighted by its work (~ x^2).
SmoothedPhase smoothed_rain_phase(const MediumPlan& plan, const RadiusQuadrature& radii, double k_per_m,
                                  double mean_csca, const Report& report, double from, double to) {
  const MediumJob& job = plan.job;
  const auto problem = [&](double r_m) {
    return sphere_problem(r_m * 1e6, job.numbers.phase_wavelength_nm, *job.medium, *job.surrounding,
                          job.numbers.temperature_c);
  };
  const auto half_width = [](double x) { return kRainSmoothingPeriods * 2 * kPi<> / x; };
  double x_max = 0, work = 0;
  for (const double r : radii.radius_m) {
    const double x = problem(r).x;
    x_max = std::max(x_max, x);
    work += x * x;
  }
  SmoothedPhase out;
  out.step = kPi<> / std::ceil(kPi<> / (half_width(x_max) / kRainSmoothingPoints));
  const std::size_t n_out = std::size_t(std::lround(kPi<> / out.step)) + 1;
  std::vector<double> sum(n_out, 0.0);
  double weight = 0, done = 0;
  std::vector<double> theta, intensity, smooth;
  std::vector<Complex> s1, s2;
  for (std::size_t k = 0; k < radii.size(); ++k) {
    const SphereProblem sp = problem(radii.radius_m[k]);
    const double w0 = half_width(sp.x);
    const std::size_t n = std::size_t(std::ceil(kPi<> / (w0 / kRainSmoothingPoints))) + 1;
    const double h = kPi<> / double(n - 1);
    theta.resize(n), intensity.resize(n), smooth.resize(n), s1.resize(n), s2.resize(n);
    for (std::size_t i = 0; i < n; ++i) theta[i] = double(i) * h;
    amplitudes(Theory{}, sp.m, sp.x, theta, s1, s2, job.numbers.threads);
    for (std::size_t i = 0; i < n; ++i) intensity[i] = (std::norm(s1[i]) + std::norm(s2[i])) / 2;
    const auto at = [&](long j) {  // reflected at theta = 0 and pi
      const long last = long(n) - 1;
      if (j < 0) j = -j;
      if (j > last) j = 2 * last - j;
      return intensity[std::size_t(std::clamp(j, 0L, last))];
    };
    for (std::size_t i = 0; i < n; ++i) {
      const double w = std::min(w0, kRainSmoothingAngleRatio * theta[i]);
      const long half = long(w / h);
      if (half < 1) {
        smooth[i] = intensity[i];
        continue;
      }
      double num = 0, den = 0;
      for (long j = -half; j <= half; ++j) {
        const double hann = 0.5 * (1 + std::cos(kPi<> * double(j) * h / w));
        num += hann * at(long(i) + j);
        den += hann;
      }
      smooth[i] = num / den;
    }
    const double wr = radii.weight[k];
    for (std::size_t i = 0; i < n_out; ++i) {
      const double u = std::min(double(i) * out.step / h, double(n - 1));
      const std::size_t j = std::min(std::size_t(u), n - 2);
      sum[i] += wr * (smooth[j] + (smooth[j + 1] - smooth[j]) * (u - double(j)));
    }
    weight += wr;
    done += sp.x * sp.x;
    report(from + (to - from) * done / work, fmt::format("phase, radius {}/{} (smoothed over angle)", k + 1, radii.size()));
  }
  const double norm = 1 / (k_per_m * k_per_m * mean_csca * weight);
  out.p.resize(n_out);
  for (std::size_t i = 0; i < n_out; ++i) out.p[i] = sum[i] * norm;
  return out;
}

// The phase per steradian at the points mu (any order), over the radii chosen (PhaseRadii); for rain
// read from its smoothed phase.
struct PhaseEvaluator {
  const MediumPlan& plan;
  const RadiusQuadrature& radii;
  double k_per_m = 0;   // in the surrounding medium, at the phase wavelength
  double mean_csca = 0;  // number-weighted mean scattering cross section, m^2
  const SmoothedPhase* smoothed = nullptr;
  std::vector<double> operator()(std::span<const double> one_minus_mu, const ProgressFn& progress) const {
    std::vector<double> theta(one_minus_mu.size());
    for (std::size_t i = 0; i < theta.size(); ++i)
      theta[i] = 2 * std::asin(std::sqrt(std::clamp(one_minus_mu[i] / 2, 0.0, 1.0)));
    if (smoothed) {
      std::vector<double> p(theta.size());
      for (std::size_t i = 0; i < p.size(); ++i) p[i] = smoothed->at(theta[i]);
      if (progress) progress(1, "phase");
      return p;
    }
    const auto& job = plan.job;
    const auto avg = average_intensities(Theory{}, radii, job.numbers.phase_wavelength_nm,
                                         *job.medium, *job.surrounding, job.numbers.temperature_c, theta,
                                         job.numbers.threads, progress);
    std::vector<double> p(theta.size());
    const double norm = 1 / (k_per_m * k_per_m * mean_csca);
    for (std::size_t i = 0; i < p.size(); ++i) p[i] = (avg.i1[i] + avg.i2[i]) / 2 * norm;
    return p;
  }
};

// One table size's analysis: from p at the quarter points (4 (N - 1) + 1 of them, mu ascending).
struct Level {
  int n = 0;
  double h = 0;
  std::vector<double> e, s, t;  // per interval: L1 of linear interpolation, 2 pi int p, 2 pi int mu p
};

Level analyse(int n, const std::vector<double>& q) {
  Level L;
  L.n = n;
  L.h = 2.0 / (n - 1);
  const double two_pi = 2 * kPi<>;
  L.e.resize(std::size_t(n - 1));
  L.s.resize(L.e.size());
  L.t.resize(L.e.size());
  for (std::size_t i = 0; i + 1 < std::size_t(n); ++i) {
    const double* v = &q[4 * i];
    const double mu0 = -1 + double(i) * L.h, dq = L.h / 4;
    double dev[3];
    for (int j = 1; j <= 3; ++j) dev[j - 1] = std::fabs(v[j] - (v[0] + (v[4] - v[0]) * j / 4.0));
    L.e[i] = two_pi * L.h / 12 * (4 * dev[0] + 2 * dev[1] + 4 * dev[2]);
    L.s[i] = two_pi * dq / 3 * (v[0] + 4 * v[1] + 2 * v[2] + 4 * v[3] + v[4]);
    double mv[5];
    for (int j = 0; j < 5; ++j) mv[j] = (mu0 + j * dq) * v[j];
    L.t[i] = two_pi * dq / 3 * (mv[0] + 4 * mv[1] + 2 * mv[2] + 4 * mv[3] + mv[4]);
  }
  return L;
}

// The table of a level with `m` intervals cut at the forward end, and its estimated error. In the
// cone the table runs linearly from p(mu_c) to a flat cap: p(mu_c) itself where the cone holds more
// light than that (a forward peak), else lower, so that the table never holds more of it.
struct Choice {
  int m = 0;
  double cap = 0, cut_fraction = 0, trapezoid = 1, error = 0, g = 0;
};

// The table's value (before normalisation) at grid point j.
double table_value(const Level& L, const std::vector<double>& q, const Choice& c, int j) {
  return j <= L.n - 1 - c.m ? q[4 * std::size_t(j)] : c.cap;
}

Choice choose(const Level& L, const std::vector<double>& q, int m, double g_uncut) {
  const int intervals = L.n - 1, resolved = intervals - m;
  const double two_pi = 2 * kPi<>;
  Choice c;
  c.m = m;
  double sum_e = 0, sum_s = 0, sum_t = 0;
  for (int i = 0; i < resolved; ++i) {
    sum_e += L.e[std::size_t(i)];
    sum_s += L.s[std::size_t(i)];
    sum_t += L.t[std::size_t(i)];
  }
  double kept = 1;  // 1 - f: the fraction of the scattered light still scattered
  if (m > 0) {
    const double p_c = q[4 * std::size_t(resolved)];
    const double cone_mass = std::max(0.0, 1 - sum_s);  // the phase integrates to 1 exactly
    // Table mass in the cone: 2 pi h (p_c / 2 + (m - 1/2) cap).
    const double fit = (cone_mass / (two_pi * L.h) - p_c / 2) / (m - 0.5);
    c.cap = std::max(0.0, std::min(p_c, fit));
    double table_mass = 0, table_moment = 0;
    for (int j = resolved; j < intervals; ++j) {
      const double a = -1 + j * L.h, b = a + L.h;
      const double va = table_value(L, q, c, j), vb = table_value(L, q, c, j + 1);
      table_mass += two_pi * L.h * (va + vb) / 2;
      table_moment += two_pi * L.h / 6 * ((2 * a + b) * va + (a + 2 * b) * vb);  // int mu (linear) dmu, exact
    }
    c.cut_fraction = cone_mass - table_mass;
    kept = 1 - c.cut_fraction;
    c.g = (sum_t + table_moment) / kept;
  } else {
    c.g = g_uncut;
  }
  double trap = 0;
  for (int j = 0; j < intervals; ++j) trap += (table_value(L, q, c, j) + table_value(L, q, c, j + 1)) / 2 * L.h;
  c.trapezoid = two_pi * trap;
  c.error = sum_e / c.trapezoid + std::fabs(kept / c.trapezoid - 1) + (m == 0 ? std::fabs(1 - sum_s) : 0.0);
  return c;
}

double cut_angle_deg(const Level& L, int m) { return rad_to_deg(2 * std::asin(std::sqrt(m * L.h / 2))); }

// Simpson's rule of f over [a, b] with n (even) intervals.
template <class F>
double simpson(F&& f, double a, double b, int n) {
  const double h = (b - a) / n;
  double sum = f(a) + f(b);
  for (int i = 1; i < n; ++i) sum += (i % 2 ? 4 : 2) * f(a + i * h);
  return sum * h / 3;
}

}  // namespace

std::span<const Field<MediumRequest>> medium_params() { return kMedium; }

const Param& medium_param(std::string_view name) {
  if (const auto* f = find_field(medium_params(), name)) return f->param;
  throw std::logic_error("medium_param: no parameter " + std::string(name));
}

RendererFormat parse_renderer_format(std::string_view text) {
  if (text == "mitsuba3") return RendererFormat::mitsuba3;
  if (text == "pbrt-v4") return RendererFormat::pbrt_v4;
  throw UnknownNameError(fmt::format("unknown renderer format '{}' (valid: mitsuba3, pbrt-v4)", text));
}

std::string_view renderer_format_name(RendererFormat format) {
  return format == RendererFormat::mitsuba3 ? "mitsuba3" : "pbrt-v4";
}

std::optional<RendererFormat> renderer_format_for_extension(std::string_view ext) {
  if (ext == ".xml") return RendererFormat::mitsuba3;
  if (ext == ".pbrt") return RendererFormat::pbrt_v4;
  return std::nullopt;
}

bool valid_medium_name(std::string_view name) {
  if (name.empty() || name.size() > 64) return false;
  return std::all_of(name.begin(), name.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '.' ||
           c == '-';
  });
}

MediumPlan plan_medium(MediumJob job) {
  for (const auto& f : medium_params())
    if (const double v = f.get(job.numbers); !std::isnan(v)) f.param.check(v);
  if (job.numbers.number_per_cm3 && job.numbers.lwc_g_m3)
    throw ParamError("{number_per_cm3} and {lwc_g_m3} replace one another: give one");
  PhaseJob phase;
  phase.radius_um = job.radius_um;
  phase.wavelength_nm = job.numbers.phase_wavelength_nm;
  phase.size_distribution = job.size_distribution;
  phase.medium = job.medium;
  phase.surrounding = job.surrounding;
  // The phase's radii: the count given, or kMediumStartNodes (compute_medium doubles them for gamma and
  // lognormal). For one radius a count given is plan_phase's to refuse, as is a text that is no distribution.
  const bool one_radius = [&] {
    try {
      return parse_size_distribution(job.size_distribution).kind == SizeDistributionKind::monodisperse;
    } catch (const Error&) {
      return false;
    }
  }();
  if (!one_radius || job.numbers.nodes) phase.numbers.nodes = job.numbers.nodes.value_or(kMediumStartNodes);
  if (one_radius && job.numbers.spectra_tolerance)
    throw ParamError(fmt::format("{{spectra_tolerance}} {:g}: {{size_distribution}} {} is one radius, with nothing to "
                                 "average (omit {{spectra_tolerance}})",
                                 *job.numbers.spectra_tolerance, escape_braces(job.size_distribution)));
  phase.numbers.temperature_c = job.numbers.temperature_c;
  phase.numbers.threads = job.numbers.threads;
  MediumPlan plan;
  plan.phase = plan_phase(std::move(phase));
  // The count: the quadrature's weights are drops per m^3 of a distribution of one drop per m^3
  // (mono, gamma, lognormal; intensity_quadrature truncates the tails, which hold < 1e-6 of the
  // area), or of Marshall-Palmer rain with Garg & Nayar's N0 = 8e6 m^-4 per radius, which hydrolux
  // rain and sky double to Marshall and Palmer's own count (size_distribution.hpp).
  const SizeDistributionSpec spec = parse_size_distribution(job.size_distribution);  // checked by plan_phase
  if (spec.kind == SizeDistributionKind::marshall_palmer) {
    if (job.numbers.number_per_cm3 || job.numbers.lwc_g_m3)
      throw ParamError(fmt::format("{{{}}} {:g}: the count of {{size_distribution}} marshall-palmer rain follows from "
                                   "its rain rate; give neither {{number_per_cm3}} nor {{lwc_g_m3}}",
                              job.numbers.number_per_cm3 ? "number_per_cm3" : "lwc_g_m3",
                              job.numbers.number_per_cm3 ? *job.numbers.number_per_cm3 : *job.numbers.lwc_g_m3));
    plan.weight_scale = kMarshallPalmerN0PerRadius / 8e6;
    double n = 0;
    for (const double w : plan.phase.quadrature.weight) n += w;
    plan.number_per_m3 = n * plan.weight_scale;
    const auto rain = SizeDistribution::marshall_palmer(spec.parameter, kMarshallPalmerN0PerRadius);
    plan.spectral = rain.quadrature(std::max(kSpectralRainNodes, job.numbers.nodes.value_or(0)), kPhaseRainMinRadiusUm * 1e-6,
                                    kPhaseRainMaxRadiusUm * 1e-6);
    plan.spectra_drops = rain;
    plan.spectra_r_min = kPhaseRainMinRadiusUm * 1e-6, plan.spectra_r_max = kPhaseRainMaxRadiusUm * 1e-6;
  } else {
    if (!job.numbers.number_per_cm3 && !job.numbers.lwc_g_m3)
      throw ParamError("{number_per_cm3} (drops per cm^3, in [1e-06, 1e+24]) or {lwc_g_m3} (g/m^3) is required for " +
                       escape_braces(job.size_distribution) + " drops");
    double number = 0;
    const double r = *job.radius_um * 1e-6;
    const SizeDistribution d = spec.kind == SizeDistributionKind::gamma ? SizeDistribution::gamma(r, spec.parameter)
                               : spec.kind == SizeDistributionKind::log_normal
                                   ? SizeDistribution::log_normal(r, spec.parameter)
                                   : SizeDistribution::monodisperse(r);
    if (job.numbers.number_per_cm3) {
      number = *job.numbers.number_per_cm3 * 1e6;
    } else {
      const double mean_volume = 4.0 / 3 * kPi<> * d.moment(3) / d.moment(0);
      number = *job.numbers.lwc_g_m3 / (kWaterDensityGM3 * mean_volume);
      if (!(number > 0 && number <= 1e30))
        throw ParamError(fmt::format("{{lwc_g_m3}} {:g} makes {:g} drops per m^3 of this radius, outside (0, 1e30]",
                                *job.numbers.lwc_g_m3, number));
    }
    plan.weight_scale = number;
    plan.number_per_m3 = number;
    plan.spectral = spec.kind == SizeDistributionKind::monodisperse
                        ? plan.phase.quadrature
                        : intensity_quadrature(d, std::max(kSpectralNodes, job.numbers.nodes.value_or(0)));
    for (double& w : plan.spectral.weight) w *= number;
    if (spec.kind != SizeDistributionKind::monodisperse) {
      plan.spectra_drops = d;
      std::tie(plan.spectra_r_min, plan.spectra_r_max) = intensity_range(d);
      plan.spectra_scale = number;
    }
  }
  // The media over the whole grid, so that a medium without data there fails before any work.
  for (const double nm : spectral_grid())
    (void)sphere_problem(1, nm, *job.medium, *job.surrounding, job.numbers.temperature_c);
  plan.job = std::move(job);
  return plan;
}

namespace {

// The extinction, scattering and absorption spectra and g over the export's wavelengths, and the bulk
// optics at the phase wavelength (progress 0 to 0.1).
void compute_spectra(const MediumPlan& plan, MediumOptics& out, const Report& report) {
  const MediumJob& job = plan.job;
  const MediumRequest& req = job.numbers;
  const RadiusQuadrature& scaled = plan.spectral;
  double volume = 0;
  for (std::size_t i = 0; i < scaled.size(); ++i) volume += scaled.weight[i] * 4.0 / 3 * kPi<> * std::pow(scaled.radius_m[i], 3);
  out.lwc_g_m3 = volume * kWaterDensityGM3;
  out.wavelength_nm = spectral_grid();
  // The export's wavelengths and the phase's, last.
  std::vector<Complex> m;
  std::vector<double> k;
  for (const double nm : out.wavelength_nm) {
    const SphereProblem p = sphere_problem(1, nm, *job.medium, *job.surrounding, req.temperature_c);
    m.push_back(p.m);
    k.push_back(2 * kPi<> * p.n_surrounding / (nm * 1e-9));
  }
  const SphereProblem p0 = sphere_problem(1, req.phase_wavelength_nm, *job.medium, *job.surrounding, req.temperature_c);
  m.push_back(p0.m);
  k.push_back(2 * kPi<> * p0.n_surrounding / (req.phase_wavelength_nm * 1e-9));
  std::vector<MieBulkOptics> bulk;
  if (plan.spectra_drops) {
    // One grid of radii for every wavelength, chosen to the tolerance (refine_bulk_optics).
    const RefinedBulkOptics r = refine_bulk_optics(m, k, *plan.spectra_drops, plan.spectra_r_min, plan.spectra_r_max,
                                                   plan.spectra_scale, req.spectra_tolerance.value_or(kSpectraTolerance),
                                                   req.threads);
    bulk = r.optics;
    out.spectra_error_extinction = r.error_extinction;
    out.spectra_error_g = r.error_g;
    out.spectra_radii = r.radii;
    out.spectra_tolerance = req.spectra_tolerance.value_or(kSpectraTolerance);
    report(0.1, "spectra");
  } else {
    for (std::size_t i = 0; i < m.size(); ++i) {
      bulk.push_back(mie_bulk_optics(m[i], k[i], scaled, req.threads));
      report(0.1 * double(i + 1) / double(m.size()), "spectra");
    }
  }
  for (std::size_t i = 0; i < out.wavelength_nm.size(); ++i) {
    out.extinction_per_m.push_back(bulk[i].extinction_per_m);
    out.scattering_per_m.push_back(bulk[i].scattering_per_m);
    out.absorption_per_m.push_back(bulk[i].absorption_per_m);
    out.g.push_back(bulk[i].g);
  }
  out.at_phase_wavelength = bulk.back();
}

// The table found: the last level analysed, its quarter points and the chosen cut.
struct TableSearch {
  Level level;
  Choice best;
  std::vector<double> q;  // p at the quarter points of `level`, mu ascending
};

// The table: levels of 2^k + 1 values (or the one size asked for), each analysed from p at its
// quarter points; a level's quarter points hold the previous level's, which are reused (progress 0.3
// to 1). The automatic choices aim at `target` (max_error less the size average's own error).
TableSearch search_table(const MediumPlan& plan, const PhaseEvaluator& eval, double k0, double g_uncut,
                         double target, const Report& report) {
  const MediumRequest& req = plan.job.numbers;
  const bool auto_size = !req.values;
  std::vector<int> sizes;
  if (auto_size) {
    for (int n = kAutoMinValues; n <= kAutoMaxValues; n = 2 * n - 1) sizes.push_back(n);
  } else {
    sizes.push_back(int(*req.values));
  }
  // Whether the forward peak is beyond the largest automatic table: its lobe is ~ (3.83 / x)^2 / 2
  // wide in 1 - mu, with x the size parameter of the effective radius (sum r^3 / sum r^2, Hansen &
  // Travis), and linear interpolation meets 0.01 with about 12 intervals across it (measured on fog
  // drops: N ~ 3.3 x^2). Then a cut is considered at every size; otherwise only once the largest
  // size without one falls short (a cut changes the physics; a larger table only costs time).
  double m2 = 0, m3 = 0;
  for (std::size_t i = 0; i < eval.radii.size(); ++i) {
    const double r = eval.radii.radius_m[i], w = eval.radii.weight[i];
    m2 += w * r * r;
    m3 += w * r * r * r;
  }
  const double x_eff = k0 * m3 / m2;
  const bool hopeless = auto_size && 3.3 * x_eff * x_eff > 4.0 * kAutoMaxValues;
  TableSearch found;
  int q_n = 0;  // the level found.q belongs to
  double evaluated = 0, planned = 0;
  for (const int n : sizes) planned += 4.0 * (n - 1) + 1;
  if (auto_size) planned = 4.0 * (sizes.back() - 1) + 1;
  for (std::size_t li = 0; li < sizes.size(); ++li) {
    const int n = sizes[li];
    const std::size_t points = 4 * std::size_t(n - 1) + 1;
    const double dq = 2.0 / double(points - 1);
    std::vector<double> next(points);
    std::vector<double> todo;  // 1 - mu of the points not yet known
    std::vector<std::size_t> where;
    for (std::size_t j = 0; j < points; ++j) {
      if (q_n > 0 && (n - 1) == 2 * (q_n - 1) && j % 2 == 0) {
        next[j] = found.q[j / 2];
        continue;
      }
      todo.push_back(double(points - 1 - j) * dq);
      where.push_back(j);
    }
    const double before = evaluated;
    const auto values = eval(todo, [&](double f, std::string_view) {
      report(0.3 + 0.7 * (before + f * double(todo.size())) / planned, fmt::format("phase, {} values", n));
    });
    evaluated += double(todo.size());
    for (std::size_t i = 0; i < where.size(); ++i) next[where[i]] = values[i];
    found.q = std::move(next);
    q_n = n;
    found.level = analyse(n, found.q);
    const Level& level = found.level;
    // The cut: the one asked for, or none if that meets the target, else the smallest allowed one
    // that does (else the best allowed one).
    if (req.forward_cut_deg) {
      const double one_minus = 1 - std::cos(deg_to_rad(*req.forward_cut_deg));
      const int m = std::min(n - 2, int(std::lround(one_minus / level.h)));
      found.best = choose(level, found.q, m, g_uncut);
    } else {
      found.best = choose(level, found.q, 0, g_uncut);
      const bool last = li + 1 == sizes.size();
      for (int m = 1; (hopeless || last) && found.best.error > target && m < n - 1 &&
                      cut_angle_deg(level, m) <= kAutoMaxCutDeg;
           ++m) {
        const Choice c = choose(level, found.q, m, g_uncut);
        if (c.error < found.best.error) found.best = c;
      }
    }
    if (!auto_size || found.best.error <= target) break;
  }
  return found;
}

// pbrt-v4's Henyey-Greenstein against the same (cut) phase: Simpson on the quarter points over the
// resolved intervals, a fine Simpson rule over the cone (where the cut phase is the flat cap).
void compare_henyey_greenstein(const TableSearch& found, TabulatedPhase& t) {
  const Level& level = found.level;
  const Choice& best = found.best;
  const std::vector<double>& q = found.q;
  const int n = level.n, resolved = n - 1 - best.m;
  const double kept = 1 - best.cut_fraction, two_pi = 2 * kPi<>;
  t.hg_g = std::clamp(t.g, -0.99, 0.99);
  double hg = 0;
  for (int i = 0; i < resolved; ++i) {
    const double* v = &q[4 * std::size_t(i)];
    const double mu0 = -1 + i * level.h, dqq = level.h / 4;
    double d[5];
    for (int j = 0; j < 5; ++j) d[j] = std::fabs(henyey_greenstein(t.hg_g, mu0 + j * dqq) - v[j] / kept);
    hg += two_pi * dqq / 3 * (d[0] + 4 * d[1] + 2 * d[2] + 4 * d[3] + d[4]);
  }
  for (int i = resolved; i < n - 1; ++i) {  // the cone: the cut phase is the table's line
    const double a = -1 + i * level.h, va = table_value(level, q, best, i) / kept,
                 vb = table_value(level, q, best, i + 1) / kept;
    hg += two_pi * simpson(
                       [&](double mu) {
                         return std::fabs(henyey_greenstein(t.hg_g, mu) - (va + (vb - va) * (mu - a) / level.h));
                       },
                       a, a + level.h, 64);
  }
  t.hg_l1 = std::min(2.0, hg);
  const double forward = best.m > 0 ? best.cap / kept : q.back();
  t.hg_forward_ratio = henyey_greenstein(t.hg_g, 1) / forward;
  t.hg_backward_ratio = henyey_greenstein(t.hg_g, -1) / (q.front() / kept);
}

// The exported table from the search, with its stated error and cut.
void fill_table(const TableSearch& found, bool target_met, TabulatedPhase& t) {
  const Level& level = found.level;
  const Choice& best = found.best;
  const int n = level.n;
  t.exact.resize(std::size_t(n));
  t.values.resize(std::size_t(n));
  t.normalisation = 1 / best.trapezoid;
  for (int j = 0; j < n; ++j) {
    t.exact[std::size_t(j)] = found.q[4 * std::size_t(j)];
    t.values[std::size_t(j)] = table_value(level, found.q, best, j) * t.normalisation;
  }
  // Two phase functions are at most 2 apart in L1 (no overlap); an unresolved peak (a small table
  // asked for) can push the estimate past that.
  t.l1_error = std::min(2.0, best.error);
  t.target_met = target_met;
  t.cut_intervals = best.m;
  t.cut_deg = cut_angle_deg(level, best.m);
  t.cut_fraction = best.cut_fraction;
  t.g = best.g;
}

}  // namespace

namespace {

bool is_rain(const MediumPlan& plan) {
  return parse_size_distribution(plan.phase.job.size_distribution).kind == SizeDistributionKind::marshall_palmer;
}

// The phase over `radii` at kSizeCheckPoints values uniform in mu on [-1, mu_max], normalised to an
// integral of 1 over mu there (trapezoid rule): the L1 between two of them is over the sphere outside
// the cone mu > mu_max.
std::vector<double> normalised_phase(const MediumJob& m, const RadiusQuadrature& radii, double mu_max) {
  std::vector<double> theta(kSizeCheckPoints);
  const double dmu = (mu_max + 1) / (kSizeCheckPoints - 1);
  for (int i = 0; i < kSizeCheckPoints; ++i) theta[std::size_t(i)] = std::acos(std::clamp(-1 + i * dmu, -1.0, 1.0));
  const Intensities a = average_intensities(Theory{}, radii, m.numbers.phase_wavelength_nm, *m.medium, *m.surrounding,
                                            m.numbers.temperature_c, theta, m.numbers.threads);
  std::vector<double> p(theta.size());
  double total = 0;
  for (std::size_t i = 0; i < p.size(); ++i) p[i] = (a.i1[i] + a.i2[i]) / 2;
  for (std::size_t i = 0; i + 1 < p.size(); ++i) total += (p[i] + p[i + 1]) / 2 * dmu;
  for (double& v : p) v /= total;
  return p;
}
// The same of rain's smoothed phase, read at those values.
std::vector<double> normalised_phase(const SmoothedPhase& sp, double mu_max) {
  std::vector<double> p(kSizeCheckPoints);
  const double dmu = (mu_max + 1) / (kSizeCheckPoints - 1);
  double total = 0;
  for (int i = 0; i < kSizeCheckPoints; ++i) p[std::size_t(i)] = sp.at(std::acos(std::clamp(-1 + i * dmu, -1.0, 1.0)));
  for (std::size_t i = 0; i + 1 < p.size(); ++i) total += (p[i] + p[i + 1]) / 2 * dmu;
  for (double& v : p) v /= total;
  return p;
}
double l1_between(const std::vector<double>& a, const std::vector<double>& b, double mu_max) {
  const double dmu = (mu_max + 1) / double(a.size() - 1);
  double l1 = 0;
  for (std::size_t i = 0; i + 1 < a.size(); ++i) l1 += (std::abs(a[i] - b[i]) + std::abs(a[i + 1] - b[i + 1])) / 2 * dmu;
  return l1;
}

// The radii the phase averages over: the count given, or (MediumRequest::nodes unset, gamma and
// lognormal) kMediumStartNodes doubled while the phase over them is more than kMediumSizeShare of
// max_error from the phase over twice as many; with that distance as the average's own error
// (MediumOptics::phase_size_l1), L1 over the sphere between the two phases, each normalised on
// kSizeCheckPoints values uniform in mu (progress 0.1 to 0.3).
struct PhaseRadii {
  PhasePlan plan;                // the drops, described, and their radii
  std::optional<double> l1;      // against twice the radii; unset for one radius, rain and the largest counts
  bool chosen = false;
};

// Whether the phase's radii are checked against twice as many (gamma and lognormal, room to double), and
// whether they are then chosen (no count given).
bool checks_phase_radii(const MediumPlan& plan) {
  const int given = int(plan.phase.quadrature.size());
  return given >= 2 && 2 * given <= kMaxQuadratureNodes && !is_rain(plan);
}
bool chooses_phase_radii(const MediumPlan& plan) { return checks_phase_radii(plan) && !plan.job.numbers.nodes; }

PhaseRadii choose_phase_radii(const MediumPlan& plan, const Report& report) {
  const MediumJob& m = plan.job;
  PhaseRadii out{plan.phase, std::nullopt, false};
  const int given = int(plan.phase.quadrature.size());
  if (!checks_phase_radii(plan)) return out;
  out.chosen = chooses_phase_radii(plan);
  const auto normalised = [&](const RadiusQuadrature& radii) { return normalised_phase(m, radii, 1.0); };
  const auto with_nodes = [&](int n) {
    PhaseJob job = plan.phase.job;
    job.numbers.nodes = n;
    return plan_phase(std::move(job));
  };
  std::vector<double> a = normalised(plan.phase.quadrature);
  for (int n = given;; n *= 2) {
    report(0.1 + 0.2 * std::min(1.0, std::log2(double(n) / given) / 6), fmt::format("phase's radii, {}", n));
    PhasePlan finer = with_nodes(2 * n);
    std::vector<double> b = normalised(finer.quadrature);
    const double l1 = l1_between(a, b, 1.0);
    out.l1 = l1;
    if (!out.chosen || l1 <= kMediumSizeShare * m.numbers.max_error || 2 * n > kMediumMaxChosenNodes) break;
    out.plan = std::move(finer);
    a = std::move(b);
  }
  report(0.3, "phase's radii");
  return out;
}

}  // namespace

MediumOptics compute_medium(const MediumPlan& plan, const ProgressFn& progress) {
  const MediumJob& job = plan.job;
  const MediumRequest& req = job.numbers;
  const Report report = [&](double f, std::string_view label) {
    if (progress) progress(std::clamp(f, 0.0, 1.0), label);
  };
  MediumOptics out;
  out.media = media_text(job);
  out.number_per_m3 = plan.number_per_m3;
  out.scene_unit_m = req.scene_unit_m;
  out.phase_wavelength_nm = req.phase_wavelength_nm;
  compute_spectra(plan, out, report);
  const PhaseRadii radii = choose_phase_radii(plan, report);
  const RadiusQuadrature& q = radii.plan.quadrature;
  out.drops = radii.plan.drops;
  out.phase_radii = q.size();
  out.phase_radii_chosen = radii.chosen;
  out.phase_size_l1 = radii.l1;
  // A count given (or rain's) too few for the ripple at single angles; a count chosen states its error instead.
  if (!radii.chosen)
    if (auto note = undersampled_ripple_note(plan.phase, "{nodes}")) out.notes.push_back(std::move(*note));
  const double size_share = kMediumSizeShare * req.max_error;
  if (radii.l1 && *radii.l1 > size_share)
    out.notes.push_back(fmt::format("the size average over {} radii is itself {:.3g} (L1 over the sphere) from the same "
                                    "average over {} radii, more than half of {{max_error}} {:g}: {}",
                                    q.size(), *radii.l1, 2 * q.size(), req.max_error,
                                    radii.chosen ? fmt::format("{} radii are the most chosen", q.size())
                                                 : std::string("give more {nodes}, or none to have them chosen")));

  const SphereProblem p0 = sphere_problem(1, req.phase_wavelength_nm, *job.medium, *job.surrounding, req.temperature_c);
  const double k0 = 2 * kPi<> * p0.n_surrounding / (req.phase_wavelength_nm * 1e-9);
  // The phase's own normalisation and asymmetry parameter: over the phase's radii (so that the table
  // integrates to 1 exactly), which may differ from the spectra's denser radii by the ripple noise.
  const MieBulkOptics of_phase = mie_bulk_optics(p0.m, k0, q, req.threads);
  const double csca_sum = of_phase.scattering_per_m;
  double weight_sum = 0;
  for (const double w : q.weight) weight_sum += w;
  if (!(csca_sum > 0)) throw Error("the drops scatter no light (m = 1?): no phase function to export");
  // Rain: each radius smoothed over angle first (smoothed_rain_phase; progress 0.3 to 0.75), the table
  // then read from it (0.75 to 0.85).
  std::optional<SmoothedPhase> smoothed;
  if (is_rain(plan)) smoothed = smoothed_rain_phase(plan, q, k0, csca_sum / weight_sum, report, 0.3, 0.75);
  const PhaseEvaluator eval{plan, q, k0, csca_sum / weight_sum, smoothed ? &*smoothed : nullptr};
  const Report table_report = smoothed ? Report([&](double f, std::string_view label) {
    report(0.75 + 0.1 * (f - 0.3) / 0.7, label);
  })
                                       : report;

  // The table aims at what the size average leaves of max_error (at least half of it).
  const double size_error = std::min(radii.l1.value_or(0), size_share);
  const TableSearch found = search_table(plan, eval, k0, of_phase.g, req.max_error - size_error, table_report);
  fill_table(found, req.values.has_value() || found.best.error + radii.l1.value_or(0) <= req.max_error, out.phase);
  compare_henyey_greenstein(found, out.phase);
  if (smoothed && q.size() >= 4) {
    // Rain: the smoothed phase over its radii against the same over half as many, outside the table's
    // cut (progress 0.85 to 1).
    PhaseJob half = radii.plan.job;
    half.numbers.nodes = int(q.size() / 2);
    const RadiusQuadrature qh = plan_phase(std::move(half)).quadrature;
    double half_weight = 0;
    for (const double w : qh.weight) half_weight += w;
    const double half_csca = mie_bulk_optics(p0.m, k0, qh, req.threads).scattering_per_m / half_weight;
    const SmoothedPhase other = smoothed_rain_phase(plan, qh, k0, half_csca, report, 0.85, 1);
    const double mu_max = std::cos(deg_to_rad(out.phase.cut_deg));
    const double l1 = l1_between(normalised_phase(*smoothed, mu_max), normalised_phase(other, mu_max), mu_max);
    out.phase_size_l1 = l1;
    out.phase_smoothed = true;
    out.phase_radii_rain = !req.nodes;
    if (!req.values) out.phase.target_met = out.phase.l1_error + l1 <= req.max_error;
    if (l1 > size_share)
      out.notes.push_back(fmt::format("the size average over {} radii is itself {:.3g} (L1 over the sphere outside the "
                                      "forward cut) from the same average over {} radii, more than half of "
                                      "{{max_error}} {:g}: give more {{nodes}} (the phase's time grows with them)",
                                      q.size(), l1, qh.size(), req.max_error));
  }

  // The coefficients as exported: the cut light leaves the scattering (and the extinction).
  const double kept = 1 - found.best.cut_fraction;
  for (std::size_t i = 0; i < out.wavelength_nm.size(); ++i) {
    const double s = out.scattering_per_m[i] * kept, a = out.absorption_per_m[i];
    out.sigma_s_per_m.push_back(s);
    out.sigma_a_per_m.push_back(std::max(0.0, a));
    out.sigma_t_per_m.push_back(s + std::max(0.0, a));
    out.albedo.push_back(s / (s + std::max(0.0, a)));
  }
  report(1, "done");
  return out;
}

MediumOptics run_medium_job(MediumJob job, const ProgressFn& progress) {
  return compute_medium(plan_medium(std::move(job)), progress);
}

double tabphase_eval(std::span<const double> values, double mu) {
  const std::size_t n = values.size();
  if (n < 2) throw Error("tabphase_eval: at least two values");
  const double h = 2.0 / double(n - 1);
  double trap = 0;
  for (std::size_t j = 0; j + 1 < n; ++j) trap += (values[j] + values[j + 1]) / 2 * h;
  const double x = (std::clamp(mu, -1.0, 1.0) + 1) / h;
  const std::size_t i = std::min(n - 2, std::size_t(x));
  const double w = x - double(i);
  return ((1 - w) * values[i] + w * values[i + 1]) / (trap * 2 * kPi<>);
}

double henyey_greenstein(double g, double mu) {
  g = std::clamp(g, -0.99, 0.99);
  const double denom = 1 + g * g + 2 * g * -mu;  // pbrt's cos is between wo and wi: -mu
  return (1 - g * g) / (4 * kPi<> * denom * std::sqrt(denom));
}

namespace {

// The comment lines both files begin with (without the comment markers).
std::vector<std::string> header_lines(const MediumOptics& o, RendererFormat format) {
  const TabulatedPhase& t = o.phase;
  std::vector<std::string> l;
  std::size_t i550 = 0;
  for (std::size_t i = 0; i < o.wavelength_nm.size(); ++i)
    if (std::fabs(o.wavelength_nm[i] - 550) < std::fabs(o.wavelength_nm[i550] - 550)) i550 = i;
  l.push_back(fmt::format("hydrolux {} medium for {} (docs/renderer-export.md)", kVersion, renderer_format_name(format)));
  l.push_back(fmt::format("drops: {}; {}; {:.6g} per cm^3, liquid water {:.4g} g/m^3", o.drops, o.media,
                          o.number_per_m3 * 1e-6, o.lwc_g_m3));
  l.push_back(fmt::format("physical (Lorenz-Mie, no cut) at 550 nm: extinction {:.6g} m^-1 (visibility 3.912 / "
                          "extinction = {:.4g} m), scattering {:.6g} m^-1, albedo {:.9g}, g {:.6g}",
                          o.extinction_per_m[i550], 3.912 / o.extinction_per_m[i550], o.scattering_per_m[i550],
                          o.scattering_per_m[i550] / o.extinction_per_m[i550], o.g[i550]));
  l.push_back(fmt::format("spectra: {:g} to {:g} nm every {:g} nm (vacuum wavelengths); one scene unit = {:g} m",
                          kExportMinNm, kExportMaxNm, kExportStepNm, o.scene_unit_m));
  if (o.phase_size_l1)
    l.push_back(fmt::format("phase's size average: over {} radii{}; L1 distance {:.3g} over the sphere to the same "
                            "average over {} the radii (an estimate of its own error; the table's error below is "
                            "against this average, and the two add up)",
                            o.phase_radii,
                            o.phase_radii_chosen ? fmt::format(", doubled from {} until twice as many move it by at "
                                                               "most half of the error asked for",
                                                               kMediumStartNodes)
                            : o.phase_smoothed
                                ? fmt::format(" ({}; each radius's intensity first averaged over angle, a Hann window "
                                              "{:g} x 2 pi / x wide each side, at most {:g} theta; outside the "
                                              "forward cut)",
                                              o.phase_radii_rain ? "rain's fixed count" : "as given",
                                              kRainSmoothingPeriods, kRainSmoothingAngleRatio)
                                : std::string(" (as given)"),
                            *o.phase_size_l1, o.phase_smoothed ? "half" : "twice"));
  if (o.spectra_error_extinction)
    l.push_back(fmt::format("spectra's size average: over {} radii, chosen for {:g}% at every wavelength; estimated "
                            "error at the worst wavelength: extinction {:.2g}%, g {:.2g}%",
                            o.spectra_radii, 100 * o.spectra_tolerance, 100 * *o.spectra_error_extinction,
                            100 * *o.spectra_error_g));
  for (const auto& note : o.notes) l.push_back("note (the phase): " + spell_quantities(note, {}));
  if (t.cut_intervals > 0)
    l.push_back(fmt::format("forward cut: the fraction {:.6g} of the scattered light, scattered within {:.4g} deg of "
                            "forward, is treated as unscattered (delta-M-like truncation, Wiscombe 1977): sigma_s "
                            "and sigma_t are reduced by that fraction of sigma_s",
                            t.cut_fraction, t.cut_deg));
  else
    l.push_back("forward cut: none (the whole phase function is tabulated)");
  return l;
}

std::string number_list(std::span<const double> v, const char* sep) {
  std::string s;
  s.reserve(v.size() * 16);
  for (std::size_t i = 0; i < v.size(); ++i) {
    if (i) s += sep;
    s += fmt::format("{:.9g}", v[i]);
  }
  return s;
}

std::string spectrum_pairs(const std::vector<double>& nm, const std::vector<double>& v, double divide,
                           const char* pair, const char* sep) {
  std::string s;
  for (std::size_t i = 0; i < nm.size(); ++i) {
    if (i) s += sep;
    s += fmt::format("{:g}{}{:.9g}", nm[i], pair, v[i] / divide);
  }
  return s;
}

}  // namespace

std::string mitsuba3_medium_xml(const MediumOptics& o, std::string_view name) {
  if (!valid_medium_name(name)) throw Error(fmt::format("medium name '{}': 1 to 64 of A-Z a-z 0-9 _ . -", name));
  const TabulatedPhase& t = o.phase;
  const double sigma_max = *std::max_element(o.sigma_t_per_m.begin(), o.sigma_t_per_m.end());
  std::string s = "<?xml version=\"1.0\" encoding=\"utf-8\"?>\n<!--\n";
  for (const auto& line : header_lines(o, RendererFormat::mitsuba3)) s += "  " + xml_comment_text(line) + "\n";
  s += xml_comment_text(fmt::format(
      "  sigma_t: the extinction spectrum divided by its largest value (so that RGB variants, which bound a spectrum "
      "to [0, 1], keep it); scale = that value ({:.9g} m^-1) times the scene unit\n"
      "  albedo: sigma_s / sigma_t\n"
      "  phase: tabphase of {} values at {:g} nm, uniform in cos(theta) from -1 (back-scattering) to +1 "
      "(forward), the physics convention tabphase reads; linear in cos(theta) between them; normalised so that 2 pi "
      "times the trapezoid integral is 1 (Mitsuba's own normalisation then changes nothing); the values are "
      "hydrolux's phase per steradian times {:.9g}{}\n"
      "  error: L1 distance over the sphere between the table as Mitsuba interpolates it and hydrolux's phase{}: "
      "{:.3g} (estimated from three more values inside each interval){}\n"
      "  usage: mi.load_file(this file), or <include filename=\"this file\" name=\"interior\"/> inside a shape\n",
      sigma_max, t.size(), o.phase_wavelength_nm, t.normalisation,
      t.cut_intervals > 0 ? ", below the cut (a flat cap within it)" : "", t.cut_intervals > 0 ? " (with the cut)" : "",
      t.l1_error, t.target_met ? "" : " (more than the error asked for)"));
  s += "-->\n";
  s += fmt::format("<medium version=\"3.0.0\" type=\"homogeneous\" id=\"{}\">\n", name);
  s += fmt::format("    <spectrum name=\"sigma_t\" value=\"{}\"/>\n",
                   spectrum_pairs(o.wavelength_nm, o.sigma_t_per_m, sigma_max, ":", ", "));
  s += fmt::format("    <float name=\"scale\" value=\"{:.9g}\"/>\n", sigma_max * o.scene_unit_m);
  s += fmt::format("    <spectrum name=\"albedo\" value=\"{}\"/>\n",
                   spectrum_pairs(o.wavelength_nm, o.albedo, 1, ":", ", "));
  s += "    <phase type=\"tabphase\">\n";
  s += fmt::format("        <string name=\"values\" value=\"{}\"/>\n", number_list(t.values, ", "));
  s += "    </phase>\n</medium>\n";
  return s;
}

std::string pbrt_v4_medium(const MediumOptics& o, std::string_view name) {
  if (!valid_medium_name(name)) throw Error(fmt::format("medium name '{}': 1 to 64 of A-Z a-z 0-9 _ . -", name));
  const TabulatedPhase& t = o.phase;
  std::string s;
  for (const auto& line : header_lines(o, RendererFormat::pbrt_v4)) s += "# " + line + "\n";
  s += fmt::format("# sigma_a, sigma_s: m^-1; scale = the scene unit in metres ({:g}) makes them per scene unit\n",
                   o.scene_unit_m);
  s += fmt::format(
      "# phase: pbrt-v4's media take only Henyey-Greenstein; g = {:.6g}, the asymmetry parameter of hydrolux's phase "
      "at {:g} nm{}\n"
      "# error of Henyey-Greenstein against hydrolux's phase{}: L1 distance over the sphere {:.3g}; forward "
      "(0 deg) value {:.3g} times hydrolux's, backward (180 deg) {:.3g} times\n"
      "# usage: Include this file before the shapes, then MediumInterface \"{}\" \"\" on a closed shape (or "
      "\"\" \"{}\" on the camera's side)\n",
      t.hg_g, o.phase_wavelength_nm, t.hg_g != t.g ? fmt::format(" (clamped from {:.6g} as pbrt clamps it)", t.g) : "",
      t.cut_intervals > 0 ? " (with the cut)" : "", t.hg_l1, t.hg_forward_ratio, t.hg_backward_ratio, name, name);
  s += fmt::format("MakeNamedMedium \"{}\"\n    \"string type\" \"homogeneous\"\n", name);
  s += fmt::format("    \"spectrum sigma_a\" [ {} ]\n", spectrum_pairs(o.wavelength_nm, o.sigma_a_per_m, 1, " ", " "));
  s += fmt::format("    \"spectrum sigma_s\" [ {} ]\n", spectrum_pairs(o.wavelength_nm, o.sigma_s_per_m, 1, " ", " "));
  s += fmt::format("    \"float scale\" {:.9g}\n", o.scene_unit_m);
  s += fmt::format("    \"float g\" {:.9g}\n", t.hg_g);
  return s;
}

std::string renderer_medium_text(const MediumOptics& o, RendererFormat format, std::string_view name) {
  return format == RendererFormat::mitsuba3 ? mitsuba3_medium_xml(o, name) : pbrt_v4_medium(o, name);
}

}  // namespace hydrolux::scatter
