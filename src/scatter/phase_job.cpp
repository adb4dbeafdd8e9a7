#include "hydrolux/scatter/phase_job.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <utility>

#include "hydrolux/core/math.hpp"
#include "hydrolux/core/parse.hpp"
#include "hydrolux/optics/media.hpp"
#include "hydrolux/scatter/geometric.hpp"

namespace hydrolux::scatter {

namespace {

// --size-distribution's radii: a fixed quadrature (one radius; --nodes), or the distribution and the
// range the automatic average refines over; and its description.
struct SizeAverage {
  RadiusQuadrature quadrature;
  std::optional<SizeDistribution> refine;
  double r_min = 0, r_max = 0;
  std::string drops;
};

SizeAverage size_quadrature(const PhaseJob& job) {
  using Field = PhaseJobError::Field;
  SizeDistributionSpec spec;
  try {
    spec = parse_size_distribution(job.size_distribution);
  } catch (const Error& e) {
    throw PhaseJobError(Field::size_distribution, " " + escape_braces(e.what()));
  }
  const std::optional<int> nodes = job.numbers.nodes;
  // The automatic average's grid or the fixed quadrature, over [lo, hi] (m).
  const auto average = [&](const SizeDistribution& d, double lo, double hi, std::string drops) {
    SizeAverage out;
    if (nodes) {
      out.quadrature = d.quadrature(*nodes, lo, hi, d.kind() != SizeDistributionKind::marshall_palmer);
      const bool rain = d.kind() == SizeDistributionKind::marshall_palmer;  // described by its range, as always
      out.drops = rain ? std::move(drops) : fmt::format("{}, {} radii", drops, *nodes);
    } else {
      out.refine = d, out.r_min = lo, out.r_max = hi;
      out.drops = std::move(drops);
    }
    return out;
  };
  if (spec.kind == SizeDistributionKind::marshall_palmer) {
    if (job.radius_um)
      throw PhaseJobError(Field::radius_um,
                          fmt::format(" {:g}: {{size_distribution}} {} sets its own radii ({:g}-{:g} um); omit {{radius_um}}, "
                                      "or give mono, gamma:W or lognormal:W for drops of that radius",
                                      *job.radius_um, job.size_distribution, kPhaseRainMinRadiusUm,
                                      kPhaseRainMaxRadiusUm),
                          Field::size_distribution);
    return average(SizeDistribution::marshall_palmer(spec.parameter), kPhaseRainMinRadiusUm * 1e-6,
                   kPhaseRainMaxRadiusUm * 1e-6,
                   fmt::format("Marshall-Palmer rain, {:g} mm/h, radii {:g}-{:g} um", spec.parameter,
                               kPhaseRainMinRadiusUm, kPhaseRainMaxRadiusUm));
  }
  if (!job.radius_um) throw PhaseJobError(Field::radius_um, " is required (the mean radius for gamma and lognormal)");
  const double radius_um = *job.radius_um, r = radius_um * 1e-6;
  if (spec.kind == SizeDistributionKind::monodisperse) {
    if (nodes) throw one_radius_nodes_error(*nodes, job.size_distribution);
    // A tolerance other than the default (the library cannot tell the default given from one left alone).
    if (job.numbers.tolerance != PhaseRequest{}.tolerance)
      throw ParamError(fmt::format("{{tolerance}} {:g}: {{size_distribution}} {} is one radius, with nothing to average "
                                   "(omit {{tolerance}})",
                                   job.numbers.tolerance, escape_braces(job.size_distribution)));
    return {SizeDistribution::monodisperse(r).quadrature(1), std::nullopt, 0, 0, fmt::format("radius {:g} um", radius_um)};
  }
  const bool gamma = spec.kind == SizeDistributionKind::gamma;
  const auto d = gamma ? SizeDistribution::gamma(r, spec.parameter) : SizeDistribution::log_normal(r, spec.parameter);
  // A range holding the number and r^4-weighted tails: Mie intensities oscillate in r, which a range
  // rule with enough radii resolves (a Gaussian rule of n(r) would alias).
  const auto [lo, hi] = intensity_range(d);
  return average(d, lo, hi,
                 fmt::format("{} distribution, mean radius {:g} um, relative width {:g}", gamma ? "gamma" : "lognormal",
                             radius_um, spec.parameter));
}

}  // namespace

PhaseJobError::PhaseJobError(Field field, std::string_view rest, std::optional<Field> also)
    : ParamError(fmt::format("{{{}}}{}", field_name(field), rest)), field_(field), also_(also) {}

PhaseJobError one_radius_nodes_error(int nodes, std::string_view size_distribution) {
  return PhaseJobError(PhaseJobError::Field::nodes,
                       fmt::format(" {}: {{size_distribution}} {} is one radius, with nothing to average; {{nodes}} sets "
                                   "the radii of gamma:W, lognormal:W and marshall-palmer:H (omit {{nodes}})",
                                   nodes, size_distribution),
                       PhaseJobError::Field::size_distribution);
}

std::string_view PhaseJobError::field_name(Field field) {
  switch (field) {
    case Field::theory: return "theory";
    case Field::size_distribution: return "size_distribution";
    case Field::radius_um: return "radius_um";
    case Field::nodes: return "nodes";
  }
  return "?";
}

Theory phase_theory(std::string_view text) {
  try {
    return parse_theory(text);
  } catch (const UnknownNameError& e) {
    throw PhaseJobError(PhaseJobError::Field::theory, ": " + escape_braces(e.what()));
  }
}

PhasePlan plan_phase(PhaseJob job) {
  // The declared numbers in their ranges (the doors check them first, in their own words).
  for (const auto& f : phase_params())
    if (const double v = f.get(job.numbers); !std::isnan(v)) f.param.check(v);
  PhasePlan plan;
  plan.theory = phase_theory(job.theory);
  if (!job.medium || !job.surrounding) throw Error("plan_phase: the job needs both media");
  const auto& sphere = *job.medium;
  const auto& outside = *job.surrounding;
  if (const auto& t = job.numbers.temperature_c;
      t && !sphere.info().temperature_dependent && !outside.info().temperature_dependent)
    throw ParamError(fmt::format("{{temperature_c}} {:g}: neither {} nor {} has a temperature model", *t, sphere.info().name,
                            outside.info().name));
  for (const double a : job.angles_deg) require_in_range("angles_deg", a, 0.0, 180.0);
  try {
    parse::require_strictly_monotonic(job.angles_deg);  // the output's rows, a NetCDF coordinate
  } catch (const Error& e) {
    throw ParamError("{angles_deg}: " + escape_braces(e.what()));
  }
  SizeAverage sizes = size_quadrature(job);
  // The media at this wavelength (and temperature), so that a bad wavelength fails before any work.
  const double first_m = sizes.refine ? sizes.r_min : sizes.quadrature.radius_m.front();
  plan.problem = sphere_problem(first_m * 1e6, job.wavelength_nm, sphere, outside, job.numbers.temperature_c);
  if (sizes.refine) {  // the largest drop too, whose x bounds the work (and must be in the theory's domain)
    (void)sphere_problem(sizes.r_max * 1e6, job.wavelength_nm, sphere, outside, job.numbers.temperature_c);
  }
  plan.quadrature = std::move(sizes.quadrature);
  plan.refine = std::move(sizes.refine);
  plan.r_min = sizes.r_min, plan.r_max = sizes.r_max;
  plan.drops = std::move(sizes.drops);
  plan.job = std::move(job);
  return plan;
}

std::optional<std::string> undersampled_ripple_note(const PhasePlan& plan, std::string_view nodes_option) {
  const auto& q = plan.quadrature.radius_m;
  const bool wave = plan.theory.kind == TheoryKind::Mie || plan.theory.kind == TheoryKind::Debye;
  if (!wave || q.size() < 2) return std::nullopt;
  // x is proportional to r at one wavelength: the span of size parameters the radii cover.
  const auto [lo, hi] = std::minmax_element(q.begin(), q.end());
  const double x_per_m = plan.problem.x / q.front(), x_lo = *lo * x_per_m, x_hi = *hi * x_per_m;
  const double span = x_hi - x_lo;
  const double needed = std::ceil(kRippleNodesPerUnitX * span);
  if (double(q.size()) >= kRippleNodesPerUnitX / 2 * span || needed > kMaxQuadratureNodes) return std::nullopt;
  return fmt::format("{} radii over size parameters {:.3g} to {:.3g} ({:.2g} per unit of x): the Mie ripple is "
                     "under-sampled and the average can be off by tens of percent at some angles; give {} {:g} or "
                     "more (docs/mie.md, \"Size averages\")",
                     q.size(), x_lo, x_hi, double(q.size()) / span, nodes_option, needed);
}

PhaseResult compute_phase(const PhasePlan& plan, const ProgressFn& progress) {
  const PhaseJob& job = plan.job;
  std::vector<double> theta(job.angles_deg.size());
  for (std::size_t i = 0; i < theta.size(); ++i) theta[i] = deg_to_rad(job.angles_deg[i]);
  PhaseResult r;
  Intensities averaged;
  if (plan.refine) {
    auto refined = refine_average_intensities(plan.theory, *plan.refine, plan.r_min, plan.r_max, job.wavelength_nm,
                                              *job.medium, *job.surrounding, job.numbers.temperature_c, theta,
                                              job.numbers.tolerance, job.numbers.threads, progress);
    averaged = std::move(refined.averaged);
    r.quadrature = std::move(refined.quadrature);
    r.last_change = refined.last_change;
    r.error = refined.error;
    r.tolerance = job.numbers.tolerance;
    r.shifted_change = refined.shifted_change;
    if (!refined.converged && refined.shifted_change && *refined.shifted_change >= job.numbers.tolerance)
      r.notes.push_back(fmt::format("the size average stopped at {} radii (the most) while a grid shifted by {:.2f} of "
                                    "its spacing still differed by {:.2g}% at its worst angle: not within --tolerance "
                                    "{:g}% (docs/mie.md, \"Size averages\")",
                                    r.quadrature.size(), kRefineCheckShift, 100 * *refined.shifted_change,
                                    100 * job.numbers.tolerance));
    else if (!refined.converged)
      r.notes.push_back(fmt::format("the size average stopped at {} radii (the most) while its last halving still moved "
                                    "it by {:.2g}% at its worst angle: not within --tolerance {:g}% (docs/mie.md, "
                                    "\"Size averages\")",
                                    r.quadrature.size(), 100 * refined.last_change, 100 * job.numbers.tolerance));
  } else {
    averaged = average_intensities(plan.theory, plan.quadrature, job.wavelength_nm, *job.medium, *job.surrounding,
                                   job.numbers.temperature_c, theta, job.numbers.threads, progress);
    r.quadrature = plan.quadrature;
  }
  r.angles_deg = job.angles_deg;
  if (job.numbers.mueller) r.mueller = mueller_elements(averaged);
  r.i1 = averaged.i1;
  r.i2 = averaged.i2;
  r.intensity.resize(theta.size());
  for (std::size_t k = 0; k < theta.size(); ++k) r.intensity[k] = (r.i1[k] + r.i2[k]) / 2;
  r.theory = theory_name(plan.theory);
  r.drops = plan.drops;
  r.wavelength_nm = job.wavelength_nm;
  r.m = plan.problem.m;
  r.x = plan.problem.x;
  r.radii = r.quadrature.size();
  if (plan.theory.kind == TheoryKind::Airy)
    r.notes.push_back(fmt::format("Airy theory approximates order {} near its rainbow angle {:.2f} deg only (within a "
                                  "few degrees for x ~ 1000, less for larger drops); use mie or debye:{} elsewhere",
                                  plan.theory.p, rad_to_deg(rainbow_angle(r.m.real(), plan.theory.p)), plan.theory.p));
  if (plan.theory.kind == TheoryKind::Geometric && r.x < 100)
    r.notes.push_back(fmt::format("geometric optics needs x >> 1 (here x = {:.3g}); use mie", r.x));
  if (const auto note = undersampled_ripple_note(plan)) r.notes.push_back(*note);
  return r;
}

PhaseResult run_phase_job(PhaseJob job, const ProgressFn& progress) {
  return compute_phase(plan_phase(std::move(job)), progress);
}

}  // namespace hydrolux::scatter
