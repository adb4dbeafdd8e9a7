#include "hydrolux/scatter/theories.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>

#include <charconv>
#include <cmath>
#include <numbers>
#include <optional>
#include <vector>

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "hydrolux/core/error.hpp"
#include "hydrolux/core/math.hpp"
#include "hydrolux/scatter/airy.hpp"
#include "hydrolux/scatter/amplitudes.hpp"
#include "hydrolux/scatter/debye.hpp"
#include "hydrolux/scatter/geometric.hpp"
#include "hydrolux/scatter/sphere.hpp"

namespace hydrolux::scatter {

namespace {

// The cost of a radius in a size average, in units of one angle's amplitudes: its Mie coefficients cost about
// as much as its amplitudes at 80 angles (the shifted grid, at 37 angles, adds 34-56% to an average at 181
// angles: BENCHMARKS.md). Only the progress shown uses it.
constexpr double kRadiusCostInAngles = 80;
constexpr const char* kTheories = "mie, debye:P, airy[:P], geometric[:P]";

int parse_order(std::string_view text, std::string_view whole) {
  int p = 0;
  const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), p);
  if (ec != std::errc() || ptr != text.data() + text.size())
    throw UnknownNameError(fmt::format("theory '{}': the order must be a whole number; valid: {}", whole, kTheories));
  return p;
}
}  // namespace

Theory parse_theory(std::string_view text) {
  const auto colon = text.find(':');
  const std::string_view name = text.substr(0, colon);
  const bool has_p = colon != std::string_view::npos;
  const int p = has_p ? parse_order(text.substr(colon + 1), text) : -1;
  if (name == "mie" && !has_p) return {TheoryKind::Mie, 0};
  if (name == "debye" && has_p) {
    require_in_range("p", p, 0, kMaxDebyeOrder, "the Debye series");
    return {TheoryKind::Debye, p};
  }
  if (name == "airy") {
    const int order = has_p ? p : 2;
    require_in_range("p", order, 2, 20, "Airy theory (rainbow orders)");
    return {TheoryKind::Airy, order};
  }
  if (name == "geometric") {
    const int order = has_p ? p : 3;
    require_in_range("p", order, 0, 50, "geometric optics");
    return {TheoryKind::Geometric, order};
  }
  throw UnknownNameError(fmt::format("unknown theory '{}'; valid: {}", text, kTheories));
}

std::string theory_name(const Theory& t) {
  switch (t.kind) {
    case TheoryKind::Mie: return "mie";
    case TheoryKind::Debye: return fmt::format("debye:{}", t.p);
    case TheoryKind::Airy: return fmt::format("airy:{}", t.p);
    case TheoryKind::Geometric: return fmt::format("geometric:{}", t.p);
  }
  return "?";
}

void amplitudes(const Theory& t, Complex m, double x, std::span<const double> theta_rad,
                std::span<Complex> s1, std::span<Complex> s2, int threads) {
  std::vector<double> mu(theta_rad.size());
  for (std::size_t i = 0; i < mu.size(); ++i) mu[i] = std::cos(theta_rad[i]);
  switch (t.kind) {
    case TheoryKind::Mie: return mie_amplitudes(mie_coefficients(m, x), mu, s1, s2, threads);
    case TheoryKind::Debye: return mie_amplitudes(debye_coefficients(m, x, t.p), mu, s1, s2, threads);
    case TheoryKind::Airy:
      // Airy theory needs a real index between 1 and p (a rainbow of order p exists).
      require_in_range("m_real", m.real(), 1.0 + 1e-9, double(t.p) - 1e-9, theory_name(t));
      return airy_amplitudes(m.real(), x, t.p, theta_rad, s1, s2);
    case TheoryKind::Geometric:
      return geometric_amplitudes(m, x, t.p, theta_rad, s1, s2, /*diffraction=*/true);
  }
}

std::pair<double, double> intensity_range(const SizeDistribution& d) {
  switch (d.kind()) {
    case SizeDistributionKind::monodisperse: return {d.radius(), d.radius()};
    case SizeDistributionKind::gamma: {
      // Ten standard deviations (sqrt(a) b) either side of the mean a b, the lower end kept above
      // a thousandth of the mean for wide distributions. A fixed lower end at 1e-3 of the mean put
      // every node outside the peak of a narrow distribution (relative width 1e-3: 64 nodes 1.6%
      // apart across a peak 0.1% wide).
      const double a = d.alpha(), b = d.beta();
      return {std::max(1e-3 * d.mean_radius(), b * (a - 10 * std::sqrt(a))), b * (a + 4 + 10 * std::sqrt(a + 4))};
    }
    case SizeDistributionKind::log_normal: {
      const double mu = d.mu(), s = d.sigma();
      return {std::exp(mu - 8 * s), std::exp(mu + 4 * s * s + 8 * s)};
    }
    case SizeDistributionKind::marshall_palmer: break;
  }
  throw Error("intensity_quadrature: give Marshall-Palmer rain its radius range explicitly");
}

RadiusQuadrature intensity_quadrature(const SizeDistribution& d, int nodes) {
  if (d.kind() == SizeDistributionKind::monodisperse) return d.quadrature(1);
  const auto [lo, hi] = intensity_range(d);
  return d.quadrature(nodes, lo, hi, true);
}

Intensities average_intensities(const Theory& t, const RadiusQuadrature& q, double wavelength_nm,
                                const optics::Medium& drop, const optics::Medium& surrounding,
                                std::optional<double> temperature_c, std::span<const double> theta_rad,
                                int threads, const ProgressFn& progress) {
  Intensities out{std::vector<double>(theta_rad.size()), std::vector<double>(theta_rad.size()),
                  std::vector<Complex>(theta_rad.size())};
  std::vector<Complex> s1(theta_rad.size()), s2(theta_rad.size());
  double total = 0;
  for (std::size_t k = 0; k < q.radius_m.size(); ++k) {
    const auto sp = sphere_problem(q.radius_m[k] * 1e6, wavelength_nm, drop, surrounding, temperature_c);
    amplitudes(t, sp.m, sp.x, theta_rad, s1, s2, threads);
    for (std::size_t i = 0; i < theta_rad.size(); ++i) {
      out.i1[i] += q.weight[k] * std::norm(s1[i]);
      out.i2[i] += q.weight[k] * std::norm(s2[i]);
      out.s2_s1conj[i] += q.weight[k] * (s2[i] * std::conj(s1[i]));
    }
    total += q.weight[k];
    if (progress)
      progress(double(k + 1) / double(q.radius_m.size()),
               fmt::format("radius {:.4g} um ({}/{})", q.radius_m[k] * 1e6, k + 1, q.radius_m.size()));
  }
  if (!(total > 0)) throw Error("size distribution: the quadrature has no weight");
  for (std::size_t i = 0; i < theta_rad.size(); ++i) {
    out.i1[i] /= total;
    out.i2[i] /= total;
    out.s2_s1conj[i] /= total;
  }
  return out;
}

namespace {

// Sums over radii of n(r) w_trapezoid times each intensity, per angle.
struct WeightedSums {
  std::vector<double> i1, i2;
  std::vector<Complex> c;
  double weight = 0;
  explicit WeightedSums(std::size_t angles) : i1(angles), i2(angles), c(angles) {}
  // Adds one radius's amplitudes at every angle (s1, s2 of size i1.size()), weighted w.
  void add(double w, std::span<const Complex> s1, std::span<const Complex> s2) {
    for (std::size_t k = 0; k < i1.size(); ++k) {
      i1[k] += w * std::norm(s1[k]);
      i2[k] += w * std::norm(s2[k]);
      c[k] += w * (s2[k] * std::conj(s1[k]));
    }
    weight += w;
  }
  Intensities mean() const {
    Intensities out{i1, i2, c};
    for (std::size_t k = 0; k < i1.size(); ++k) {
      out.i1[k] /= weight;
      out.i2[k] /= weight;
      out.s2_s1conj[k] /= weight;
    }
    return out;
  }
};

// The change from `before` to `after` at each angle, relative to S11 there, in i1, i2 and S2 S1*, and
// in the Mueller elements S11, S12, S33 and S34 the output derives from them at the first `asked` angles.
struct Changes {
  double largest = 0;      // in i1, i2 or S2 S1* at any angle: what the refinement stops on
  double sum_squares = 0;  // of i1, i2 and |S2 S1*| over every angle: the spread of the change
  MuellerErrors element;   // the largest in each Mueller element at an angle asked
};
Changes changes(const Intensities& before, const Intensities& after, std::size_t asked) {
  Changes c;
  const auto relative = [](double change, double s11) { return s11 > 0 ? change / s11 : (change > 0 ? INFINITY : 0.0); };
  for (std::size_t k = 0; k < after.i1.size(); ++k) {
    const double s11 = (after.i1[k] + after.i2[k]) / 2;
    const double d1 = relative(std::abs(after.i1[k] - before.i1[k]), s11),
                 d2 = relative(std::abs(after.i2[k] - before.i2[k]), s11);
    const Complex dc = after.s2_s1conj[k] - before.s2_s1conj[k];
    const double d3 = relative(std::abs(dc), s11);
    c.largest = std::max({c.largest, d1, d2, d3});
    c.sum_squares += d1 * d1 + d2 * d2 + d3 * d3;
    if (k >= asked) continue;
    const double di1 = after.i1[k] - before.i1[k], di2 = after.i2[k] - before.i2[k];
    c.element.s11 = std::max(c.element.s11, relative(std::abs(di1 + di2) / 2, s11));
    c.element.s12 = std::max(c.element.s12, relative(std::abs(di2 - di1) / 2, s11));
    c.element.s33 = std::max(c.element.s33, relative(std::abs(dc.real()), s11));
    c.element.s34 = std::max(c.element.s34, relative(std::abs(dc.imag()), s11));
  }
  return c;
}

}  // namespace

RefinedIntensities refine_average_intensities(const Theory& t, const SizeDistribution& d, double r_min, double r_max,
                                              double wavelength_nm, const optics::Medium& drop,
                                              const optics::Medium& surrounding, std::optional<double> temperature_c,
                                              std::span<const double> theta_rad, double tolerance, int threads,
                                              const ProgressFn& progress) {
  if (!(r_min > 0) || !(r_max > r_min) || !(tolerance > 0))
    throw std::logic_error("refine_average_intensities: needs 0 < r_min < r_max and a tolerance > 0");
  // The angles checked: those asked, and for Mie a kRefineProbeStepDeg grid's angles more than half a step
  // from every one of them, so that a few angles asked cannot let resonances pass unseen. (One Debye order,
  // Airy theory and geometric optics leave most angles dark, where a relative change is noise.)
  std::vector<double> checked(theta_rad.begin(), theta_rad.end());
  const double probe_step = deg_to_rad(kRefineProbeStepDeg);
  for (int i = 0; t.kind == TheoryKind::Mie && double(i) * kRefineProbeStepDeg <= 180 + 1e-9; ++i) {
    const double probe = double(i) * probe_step;
    bool near = false;
    for (const double a : theta_rad) near = near || std::abs(a - probe) <= probe_step / 2;
    if (!near) checked.push_back(probe);
  }
  const std::size_t angles = checked.size();
  // The first grid: 2^k + 1 radii, at least kMinRefinedRadii, and for a wave theory kRefineStartStepX apart in x
  // at most (x is proportional to r at one wavelength).
  const double x_per_m = sphere_problem(r_max * 1e6, wavelength_nm, drop, surrounding, temperature_c).x / r_max;
  const bool wave = t.kind == TheoryKind::Mie || t.kind == TheoryKind::Debye;
  const double wanted = wave ? (r_max - r_min) * x_per_m / kRefineStartStepX + 1 : 0;
  std::size_t intervals = kMinRefinedRadii - 1;
  while (double(intervals + 1) < wanted && 8 * intervals + 1 <= kMaxRefinedRadii) intervals *= 2;  // two halvings left

  // Progress: the work done over the work foreseen if the grid being computed is the last one needed (for Mie,
  // with its shifted check), in radii weighted by their cost (kRadiusCostInAngles + the angles computed). It
  // rises while the halvings converge as foreseen; where a grid is found off, the work foreseen grows (one
  // halving more), the fraction steps back and the label says why.
  double work_done = 0, work_foreseen = 0;
  const auto cost = [](std::size_t radii_count, std::size_t angle_count) {
    return double(radii_count) * (kRadiusCostInAngles + double(angle_count));
  };
  std::string stage;  // what the label names before the counts
  const auto report = [&](std::size_t done, std::size_t of, std::string_view what) {
    if (progress)
      progress(std::min(work_done / work_foreseen, 1.0),
               fmt::format("{}{} of {} {} (to {:g}%)", stage, done, of, what, 100 * tolerance));
  };

  WeightedSums sums(angles);
  std::vector<double> radii;  // every radius computed, in the order computed
  tbb::task_arena arena(threads > 0 ? threads : tbb::task_arena::automatic);
  constexpr std::size_t kBlock = 64;
  // S1 and S2 at the angles `at` for each radius of `r` (radius-major), one radius a task.
  const auto solve = [&](std::span<const double> r, std::span<const double> at, std::vector<Complex>& s1,
                         std::vector<Complex>& s2) {
    s1.resize(r.size() * at.size());
    s2.resize(r.size() * at.size());
    arena.execute([&] {
      tbb::parallel_for(std::size_t(0), r.size(), [&](std::size_t j) {
        const auto sp = sphere_problem(r[j] * 1e6, wavelength_nm, drop, surrounding, temperature_c);
        amplitudes(t, sp.m, sp.x, at, std::span(s1).subspan(j * at.size(), at.size()),
                   std::span(s2).subspan(j * at.size(), at.size()), 1);
      });
    });
  };
  // Adds the radii r_min + (first + j stride) h for j < count, weighted n(r) (half at the range's ends): in
  // blocks computed in parallel and summed in order (the same sums on any thread count).
  const auto add = [&](double h, std::size_t first, std::size_t stride, std::size_t count, std::size_t level_total) {
    std::vector<Complex> s1, s2;
    std::vector<double> r;
    for (std::size_t b0 = 0; b0 < count; b0 += kBlock) {
      const std::size_t nb = std::min(kBlock, count - b0);
      r.resize(nb);
      for (std::size_t j = 0; j < nb; ++j) r[j] = r_min + double(first + (b0 + j) * stride) * h;
      solve(r, checked, s1, s2);
      for (std::size_t j = 0; j < nb; ++j) {
        const bool end = first + (b0 + j) * stride == 0 || r[j] >= r_max - 0.5 * h;
        sums.add(d.number_density(r[j]) * (end ? 0.5 : 1.0), std::span(s1).subspan(j * angles, angles),
                 std::span(s2).subspan(j * angles, angles));
        radii.push_back(r[j]);
      }
      work_done += cost(nb, angles);
      report(radii.size(), level_total, "radii");
    }
  };

  // The shifted grid's angles (Mie only: it checks for the resonances): per probe of a kRefineProbeStepDeg
  // grid the angle asked nearest it within half a step, or else the probe, an index into `checked`;
  // ascending, so those asked come first.
  std::vector<std::size_t> check_at;
  for (int i = 0; t.kind == TheoryKind::Mie && double(i) * kRefineProbeStepDeg <= 180 + 1e-9; ++i) {
    const double probe = double(i) * probe_step;
    std::size_t best = checked.size();
    for (std::size_t k = 0; k < checked.size(); ++k) {
      const bool usable = k < theta_rad.size() ? std::abs(checked[k] - probe) <= probe_step / 2 : checked[k] == probe;
      if (usable && (best == checked.size() || std::abs(checked[k] - probe) < std::abs(checked[best] - probe)))
        best = k;
    }
    if (best < checked.size()) check_at.push_back(best);
  }
  std::sort(check_at.begin(), check_at.end());
  check_at.erase(std::unique(check_at.begin(), check_at.end()), check_at.end());
  // The trapezoid grid of spacing h with every radius moved by kRefineCheckShift h (weights n(r) h; n vanishes
  // at the range's ends) against the average `last` at the check's angles.
  const auto shifted_check = [&](double spacing, std::size_t count, const Intensities& last) {
    std::vector<double> at(check_at.size());
    for (std::size_t k = 0; k < at.size(); ++k) at[k] = checked[check_at[k]];
    const auto asked = [&](std::size_t k) { return k < theta_rad.size(); };
    const std::size_t asked_here = std::size_t(std::count_if(check_at.begin(), check_at.end(), asked));
    WeightedSums shifted(at.size());
    std::vector<Complex> s1, s2;
    std::vector<double> r;
    for (std::size_t b0 = 0; b0 < count; b0 += kBlock) {
      const std::size_t nb = std::min(kBlock, count - b0);
      r.resize(nb);
      for (std::size_t j = 0; j < nb; ++j) r[j] = r_min + (double(b0 + j) + kRefineCheckShift) * spacing;
      solve(r, at, s1, s2);
      for (std::size_t j = 0; j < nb; ++j)
        shifted.add(d.number_density(r[j]), std::span(s1).subspan(j * at.size(), at.size()),
                    std::span(s2).subspan(j * at.size(), at.size()));
      work_done += cost(nb, at.size());
      report(b0 + nb, count, "radii of a shifted grid");
    }
    Intensities before;
    for (const std::size_t k : check_at) {
      before.i1.push_back(last.i1[k]);
      before.i2.push_back(last.i2[k]);
      before.s2_s1conj.push_back(last.s2_s1conj[k]);
    }
    return changes(before, shifted.mean(), asked_here);
  };

  // The work foreseen once a grid of `new_radii` more radii and `n` intervals is begun, `halvings` halvings
  // from the first: its radii, the halvings still needed (two at least) and, for Mie, the shifted check.
  const auto foresee = [&](std::size_t new_radii, std::size_t n, int halvings) {
    double w = work_done + cost(new_radii, angles);
    for (; halvings < 2; ++halvings, n *= 2) w += cost(n, angles);
    if (!check_at.empty()) w += cost(n, check_at.size());
    work_foreseen = w;
  };

  double h = (r_max - r_min) / double(intervals);
  foresee(intervals + 1, intervals, 0);
  add(h, 0, 1, intervals + 1, intervals + 1);
  if (!(sums.weight > 0)) throw Error("size distribution: no drops in the range averaged over");
  RefinedIntensities out;
  out.averaged = sums.mean();
  out.last_change = INFINITY;
  std::optional<Changes> previous;  // the halving before
  bool check_failed = false;        // a shifted grid differed: the grids before it were off
  for (int halvings = 1; 2 * intervals + 1 <= kMaxRefinedRadii; ++halvings) {
    // Halve the spacing: the new radii are the midpoints, odd multiples of the new step.
    h /= 2;
    stage = halvings <= 2 ? fmt::format("halving {}: ", halvings)
                          : fmt::format("halving {} ({}): ", halvings,
                                        check_failed ? "the shifted grid differed" : "the last two grids differed");
    foresee(intervals, 2 * intervals, halvings);
    add(h, 1, 2, intervals, 2 * intervals + 1);
    intervals *= 2;
    Intensities next = sums.mean();
    const Changes now = changes(out.averaged, next, theta_rad.size());
    out.averaged = std::move(next);
    out.last_change = now.largest;
    if (previous) {
      // The error left: the changes to come, were each halving to shrink them by the ratio r of the last
      // two (root mean square over every angle checked, steadier than the largest: a change at one angle
      // can vanish or grow by chance), a geometric series, r / (1 - r) times the last; r capped at
      // kErrorRatioCap where halving no longer shrinks the change (resonances the spacing still misses).
      const double ratio = previous->sum_squares > 0 ? std::sqrt(now.sum_squares / previous->sum_squares) : 0.0;
      const double r = std::min(ratio, kErrorRatioCap), factor = r / (1 - r);
      out.error = {now.element.s11 * factor, now.element.s12 * factor, now.element.s33 * factor,
                   now.element.s34 * factor};
    }
    previous = now;
    if (halvings < 2) continue;
    if (check_at.empty()) {
      if (out.last_change < tolerance / 2) {
        out.converged = true;
        break;
      }
      continue;
    }
    // The shifted grid checks the last grid (kRefineCheckShift) where the halvings agree, and after it once
    // found them off at every grid: then the last halving's change measures the grid before, whose error
    // the check found, and the shifted grid, whose radii are none of the last grid's, is the measure.
    if (out.last_change < tolerance / 2 || check_failed) {
      stage = "checking the halvings: ";
      const Changes shifted = shifted_check(h, intervals, out.averaged);
      out.shifted_change = shifted.largest;
      // Two grids whose errors are alike and independent differ by sqrt(2) times either's.
      const MuellerErrors e = shifted.element;
      const MuellerErrors from_shift{e.s11 / std::numbers::sqrt2, e.s12 / std::numbers::sqrt2,
                                     e.s33 / std::numbers::sqrt2, e.s34 / std::numbers::sqrt2};
      if (check_failed)
        out.error = from_shift;
      else
        out.error = {std::max(out.error.s11, from_shift.s11), std::max(out.error.s12, from_shift.s12),
                     std::max(out.error.s33, from_shift.s33), std::max(out.error.s34, from_shift.s34)};
      if (shifted.largest < tolerance) {
        out.converged = true;
        break;
      }
      check_failed = true;
    }
  }
  // The angles asked, without the probes.
  out.averaged.i1.resize(theta_rad.size());
  out.averaged.i2.resize(theta_rad.size());
  out.averaged.s2_s1conj.resize(theta_rad.size());
  // The last grid's radii and weights, ascending (the weights summed so that they add up to the number
  // the trapezoid rule gives, n(r) h).
  std::sort(radii.begin(), radii.end());
  out.quadrature.radius_m = radii;
  out.quadrature.weight.resize(radii.size());
  for (std::size_t j = 0; j < radii.size(); ++j)
    out.quadrature.weight[j] = d.number_density(radii[j]) * h * (j == 0 || j + 1 == radii.size() ? 0.5 : 1.0);
  return out;
}

RefinedBulkOptics refine_bulk_optics(std::span<const Complex> m, std::span<const double> wavenumber_per_m,
                                     const SizeDistribution& d, double r_min, double r_max, double scale,
                                     double tolerance, int threads) {
  if (!(r_min > 0) || !(r_max > r_min) || !(tolerance > 0) || m.size() != wavenumber_per_m.size() || m.empty())
    throw std::logic_error("refine_bulk_optics: needs 0 < r_min < r_max, a tolerance > 0 and one k per m");
  const std::size_t waves = m.size();
  // Per wavelength, sums of n(r) scale times each radius's cross sections (mie_bulk_optics on the new
  // radii, weighted n(r) scale, half at the range's ends); the trapezoid rule is h times them.
  struct Sums {
    double ext = 0, sca = 0, abs = 0, back = 0, gsca = 0;
  };
  std::vector<Sums> sums(waves);
  std::size_t intervals = kMinRefinedRadii - 1;
  double h = (r_max - r_min) / double(intervals);
  RefinedBulkOptics out;
  const auto add = [&](std::size_t first, std::size_t stride, std::size_t count) {
    RadiusQuadrature q;
    for (std::size_t j = 0; j < count; ++j) {
      const std::size_t i = first + j * stride;
      const double r = r_min + double(i) * h;
      q.radius_m.push_back(r);
      q.weight.push_back(d.number_density(r) * scale * (i == 0 || i == intervals ? 0.5 : 1.0));
    }
    for (std::size_t w = 0; w < waves; ++w) {
      const MieBulkOptics b = mie_bulk_optics(m[w], wavenumber_per_m[w], q, threads);
      Sums& s = sums[w];
      s.ext += b.extinction_per_m, s.sca += b.scattering_per_m, s.abs += b.absorption_per_m;
      s.back += b.backscatter_per_m, s.gsca += b.g * b.scattering_per_m;
    }
    out.radii += count;
  };
  const auto optics = [&] {
    std::vector<MieBulkOptics> all(waves);
    for (std::size_t w = 0; w < waves; ++w) {
      const Sums& s = sums[w];
      MieBulkOptics& b = all[w];
      b.extinction_per_m = h * s.ext, b.scattering_per_m = h * s.sca, b.absorption_per_m = h * s.abs;
      b.backscatter_per_m = h * s.back, b.g = s.sca > 0 ? s.gsca / s.sca : 0.0;
    }
    return all;
  };
  add(0, 1, intervals + 1);
  for (const Sums& s : sums)
    if (!(s.ext > 0)) throw Error("size distribution: no drops in the range averaged over");
  out.optics = optics();
  out.last_change = INFINITY;
  double previous = 0;  // the halving before's sum of squared changes
  for (int halvings = 1; 2 * intervals + 1 <= kMaxRefinedRadii; ++halvings) {
    h /= 2;
    intervals *= 2;
    add(1, 2, intervals / 2);
    const std::vector<MieBulkOptics> next = optics();
    double largest = 0, squares = 0, d_ext_max = 0, d_g_max = 0;
    for (std::size_t w = 0; w < waves; ++w) {
      const MieBulkOptics &a = out.optics[w], &b = next[w];
      const double ext = b.extinction_per_m;
      const double d_ext = std::abs(b.extinction_per_m - a.extinction_per_m) / ext,
                   d_sca = std::abs(b.scattering_per_m - a.scattering_per_m) / ext,
                   d_abs = std::abs(b.absorption_per_m - a.absorption_per_m) / ext,
                   d_g = b.g != 0 ? std::abs(b.g - a.g) / std::abs(b.g) : 0.0;
      largest = std::max({largest, d_ext, d_sca, d_abs, d_g});
      squares += d_ext * d_ext + d_sca * d_sca + d_abs * d_abs + d_g * d_g;
      d_ext_max = std::max({d_ext_max, d_ext, d_sca, d_abs});
      d_g_max = std::max(d_g_max, d_g);
    }
    out.optics = next;
    out.last_change = largest;
    if (halvings >= 2) {
      const double ratio = previous > 0 ? std::sqrt(squares / previous) : 0.0;
      const double r = std::min(ratio, kErrorRatioCap), factor = r / (1 - r);
      out.error_extinction = d_ext_max * factor;
      out.error_g = d_g_max * factor;
    }
    previous = squares;
    if (halvings >= 2 && out.last_change < tolerance / 2) {
      out.converged = true;
      break;
    }
  }
  return out;
}

}  // namespace hydrolux::scatter
