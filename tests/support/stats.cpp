#include "support/stats.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "hydrolux/core/math.hpp"

namespace hydrolux::test {

// ------------------------------------------------------------------------------------------------
// Special functions
// ------------------------------------------------------------------------------------------------

namespace {

constexpr int kMaxIterations = 1'000'000;
constexpr double kEps = std::numeric_limits<double>::epsilon();

// x^a e^-x / Gamma(a), the common prefactor of both expansions, in logs.
double gamma_prefactor(double a, double x) {
  return std::exp(a * std::log(x) - x - std::lgamma(a));
}

// P(a, x) by its series: x^a e^-x / Gamma(a + 1) * sum_n x^n / ((a + 1) ... (a + n))
// (A&S 6.5.29 rearranged). Converges for all x; used for x < a + 1, where it is fast.
double gamma_p_series(double a, double x) {
  double term = 1.0 / a;
  double sum = term;
  for (int n = 1; n < kMaxIterations; ++n) {
    term *= x / (a + n);
    sum += term;
    if (std::abs(term) < std::abs(sum) * kEps) break;
  }
  return sum * gamma_prefactor(a, x);
}

// Q(a, x) by Legendre's continued fraction (A&S 6.5.31)
//   Q = x^a e^-x / Gamma(a) * 1/(x + 1 - a - 1 (1 - a)/(x + 3 - a - 2 (2 - a)/(x + 5 - a - ...)))
// evaluated with the modified Lentz algorithm; used for x >= a + 1.
double gamma_q_continued_fraction(double a, double x) {
  constexpr double kTiny = 1e-300;
  double b = x + 1.0 - a;
  double c = 1.0 / kTiny;
  double d = 1.0 / b;
  double h = d;
  for (int i = 1; i < kMaxIterations; ++i) {
    const double an = -i * (i - a);
    b += 2.0;
    d = an * d + b;
    if (std::abs(d) < kTiny) d = kTiny;
    c = b + an / c;
    if (std::abs(c) < kTiny) c = kTiny;
    d = 1.0 / d;
    const double delta = d * c;
    h *= delta;
    if (std::abs(delta - 1.0) < kEps) break;
  }
  return gamma_prefactor(a, x) * h;
}

}  // namespace

double regularized_gamma_p(double a, double x) {
  if (!(a > 0) || !(x >= 0)) return std::numeric_limits<double>::quiet_NaN();
  if (x == 0) return 0.0;
  if (std::isinf(x)) return 1.0;
  if (x < a + 1.0) return gamma_p_series(a, x);
  return 1.0 - gamma_q_continued_fraction(a, x);
}

double regularized_gamma_q(double a, double x) {
  if (!(a > 0) || !(x >= 0)) return std::numeric_limits<double>::quiet_NaN();
  if (x == 0) return 1.0;
  if (std::isinf(x)) return 0.0;
  if (x < a + 1.0) return 1.0 - gamma_p_series(a, x);
  return gamma_q_continued_fraction(a, x);
}

double chi_square_survival(double x, double dof) {
  if (!(x > 0)) return 1.0;
  return regularized_gamma_q(dof / 2.0, x / 2.0);
}

double sidak_alpha(double alpha, int runs) {
  return 1.0 - std::pow(1.0 - alpha, 1.0 / std::max(1, runs));
}

Quadrature gauss_legendre(int n, double a, double b) {
  Quadrature q;
  q.x.resize(n);
  q.w.resize(n);
  const double mid = (a + b) / 2, half = (b - a) / 2;
  for (int i = 0; i < (n + 1) / 2; ++i) {
    // Newton on P_n from Tricomi's initial guess for the i-th root.
    double z = std::cos(kPi<double> * (i + 0.75) / (n + 0.5));
    double dp = 0;
    for (int it = 0; it < 100; ++it) {
      double p0 = 1.0, p1 = 0.0;
      for (int k = 1; k <= n; ++k) {  // Bonnet's recursion
        const double p2 = p1;
        p1 = p0;
        p0 = ((2.0 * k - 1.0) * z * p1 - (k - 1.0) * p2) / k;
      }
      dp = n * (z * p0 - p1) / (z * z - 1.0);
      const double dz = p0 / dp;
      z -= dz;
      if (std::abs(dz) < 1e-16) break;
    }
    const double w = 2.0 / ((1.0 - z * z) * dp * dp);
    q.x[i] = mid - half * z;
    q.x[n - 1 - i] = mid + half * z;
    q.w[i] = q.w[n - 1 - i] = half * w;
  }
  return q;
}

// ------------------------------------------------------------------------------------------------
// Chi-square test
// ------------------------------------------------------------------------------------------------

std::string ChiSquareResult::describe() const {
  return fmt::format(
      "X^2 = {:.2f}, dof = {}, p = {:.3g}, samples = {}, failures = {}, "
      "int pdf = {:.6f}, pooled cells = {}",
      statistic, dof, p_value, samples, failures, pdf_integral, pooled_cells);
}

Histogram sample_histogram(const DirectionSampler& sampler, const ChiSquareConfig& config) {
  Histogram h;
  h.counts.assign(static_cast<std::size_t>(config.theta_bins) * config.phi_bins, 0);
  Rng rng(config.seed);
  const double to_theta_bin = config.theta_bins / kPi<double>;
  const double to_phi_bin = config.phi_bins / (2.0 * kPi<double>);
  for (std::int64_t i = 0; i < config.samples; ++i) {
    const auto w = sampler(rng);
    if (!w) {
      ++h.failures;
      continue;
    }
    const double theta = std::atan2(std::hypot(w->x, w->y), w->z);
    double phi = std::atan2(w->y, w->x);
    if (phi < 0) phi += 2.0 * kPi<double>;
    const int tb = std::clamp(static_cast<int>(theta * to_theta_bin), 0, config.theta_bins - 1);
    const int pb = std::clamp(static_cast<int>(phi * to_phi_bin), 0, config.phi_bins - 1);
    ++h.counts[static_cast<std::size_t>(tb) * config.phi_bins + pb];
  }
  return h;
}

std::vector<double> expected_counts(const DirectionPdf& pdf, const ChiSquareConfig& config) {
  const int T = config.theta_bins, P = config.phi_bins;
  const int m = 2 * config.subdivisions;  // Simpson intervals per cell and axis (even)
  const int nt = T * m, np = P * m;
  const double ht = kPi<double> / nt, hp = 2.0 * kPi<double> / np;
  // Composite Simpson weight of local node j in [0, m] (before the h/3 factor).
  const auto simpson = [m](int j) { return (j == 0 || j == m) ? 1.0 : (j % 2 ? 4.0 : 2.0); };

  std::vector<double> cells(static_cast<std::size_t>(T) * P, 0.0);
  std::vector<double> row(np + 1);
  std::vector<double> row_cells(P);
  std::vector<double> cos_phi(np + 1), sin_phi(np + 1);
  for (int j = 0; j <= np; ++j) {
    cos_phi[j] = std::cos(j * hp);
    sin_phi[j] = std::sin(j * hp);
  }
  // Integrates the row of pdf values at polar angle theta over each phi cell.
  const auto integrate_row = [&](double theta) {
    const double st = std::sin(theta), ct = std::cos(theta);
    for (int j = 0; j < np; ++j) row[j] = pdf(Vec3(st * cos_phi[j], st * sin_phi[j], ct));
    row[np] = row[0];  // periodic in phi
    for (int pb = 0; pb < P; ++pb) {
      double s = 0;
      for (int j = 0; j <= m; ++j) s += simpson(j) * row[pb * m + j];
      row_cells[pb] = s * hp / 3.0;
    }
  };
  const auto add = [&](int cell_row, double weight, double sin_theta) {
    if (cell_row < 0 || cell_row >= T) return;
    const double f = weight * sin_theta * ht / 3.0;
    double* out = &cells[static_cast<std::size_t>(cell_row) * P];
    for (int pb = 0; pb < P; ++pb) out[pb] += f * row_cells[pb];
  };
  // A theta node on the boundary between two cell rows is evaluated twice, just inside each row
  // (1e-9 rad in): a pdf that jumps there (at the horizon, typically: D = 0 below it) is then
  // integrated with its one-sided limits instead of a value that belongs to one side only.
  constexpr double kInside = 1e-9;
  for (int i = 1; i < nt; ++i) {  // theta = 0 and pi carry sin theta = 0
    const double theta = i * ht;
    const int local = i % m;
    const int tb = i / m;
    if (local == 0) {
      integrate_row(theta - kInside);
      add(tb - 1, 1.0, std::sin(theta));
      integrate_row(theta + kInside);
      add(tb, 1.0, std::sin(theta));
    } else {
      integrate_row(theta);
      add(tb, simpson(local), std::sin(theta));
    }
  }
  const double n = static_cast<double>(config.samples);
  for (double& c : cells) c *= n;
  return cells;
}

ChiSquareResult chi_square_from_counts(const std::vector<std::int64_t>& observed,
                                       const std::vector<double>& expected, double min_expected) {
  ChiSquareResult r;
  const std::size_t n = std::min(observed.size(), expected.size());
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return expected[a] < expected[b]; });
  // Samples in a cell whose pdf integrates to exactly zero: impossible directions. Like pbrt-v4,
  // allow a trace (1e-5 of all samples per cell) for a sliver of support the quadrature misses.
  const double total_observed =
      static_cast<double>(std::accumulate(observed.begin(), observed.end(), std::int64_t{0}));
  for (std::size_t i = 0; i < n; ++i) {
    if (expected[i] == 0 && static_cast<double>(observed[i]) > 1e-5 * total_observed) {
      r.statistic = std::numeric_limits<double>::infinity();
      r.p_value = 0;
      r.dof = 1;
      return r;
    }
  }
  double pooled_e = 0;
  std::int64_t pooled_o = 0;
  std::size_t k = 0;
  // Every cell below the threshold, then (if the pool is still short of it) the next smallest.
  while (k < n && expected[order[k]] < min_expected) {
    pooled_e += expected[order[k]];
    pooled_o += observed[order[k]];
    ++k;
  }
  while (k < n && k > 0 && pooled_e < min_expected) {
    pooled_e += expected[order[k]];
    pooled_o += observed[order[k]];
    ++k;
  }
  r.pooled_cells = static_cast<int>(k);
  double chi2 = 0;
  int cells = 0;
  for (std::size_t i = k; i < n; ++i) {
    const double e = expected[order[i]];
    const double d = static_cast<double>(observed[order[i]]) - e;
    chi2 += d * d / e;
    ++cells;
  }
  if (pooled_e > 0) {
    const double d = static_cast<double>(pooled_o) - pooled_e;
    chi2 += d * d / pooled_e;
    ++cells;
  } else if (pooled_o > 0) {
    chi2 = std::numeric_limits<double>::infinity();  // samples where the pdf integrates to zero
  }
  r.statistic = chi2;
  r.dof = std::max(1, cells - 1);
  r.p_value = std::isinf(chi2) ? 0.0 : chi_square_survival(chi2, r.dof);
  return r;
}

ChiSquareResult chi_square_test(const DirectionSampler& sampler, const DirectionPdf& pdf,
                                const ChiSquareConfig& config) {
  const Histogram h = sample_histogram(sampler, config);
  const std::vector<double> e = expected_counts(pdf, config);
  ChiSquareResult r = chi_square_from_counts(h.counts, e, config.min_expected);
  r.samples = config.samples;
  r.failures = h.failures;
  r.pdf_integral = std::accumulate(e.begin(), e.end(), 0.0) / static_cast<double>(config.samples);
  return r;
}

ChiSquareResult chi_square_bxdf(const optics::BxDF& bxdf, const Vec3& wo,
                                const ChiSquareConfig& config) {
  const DirectionSampler sampler = [&](Rng& rng) -> std::optional<Vec3> {
    const double uc = rng.uniform();
    const double u1 = rng.uniform();
    const double u2 = rng.uniform();
    const auto s = bxdf.sample(wo, uc, {u1, u2}, optics::TransportMode::Radiance);
    if (!s || s->is_delta) return std::nullopt;
    return s->wi;
  };
  const DirectionPdf pdf = [&](const Vec3& wi) { return bxdf.pdf(wo, wi); };
  return chi_square_test(sampler, pdf, config);
}

// ------------------------------------------------------------------------------------------------
// Monte Carlo
// ------------------------------------------------------------------------------------------------

Estimate monte_carlo(std::int64_t n, std::uint64_t seed, const std::function<double(Rng&)>& g) {
  Rng rng(seed);
  double mean = 0, m2 = 0;
  for (std::int64_t i = 0; i < n; ++i) {
    const double v = g(rng);
    const double d = v - mean;
    mean += d / static_cast<double>(i + 1);
    m2 += d * (v - mean);
  }
  Estimate e;
  e.n = n;
  e.mean = mean;
  e.std_error = n > 1 ? std::sqrt(m2 / static_cast<double>(n - 1) / static_cast<double>(n)) : 0;
  return e;
}

namespace {
bool counts(Hemisphere which, const Vec3& wo, const Vec3& wi) {
  switch (which) {
    case Hemisphere::All:
      return true;
    case Hemisphere::Reflection:
      return wo.z * wi.z > 0;
    case Hemisphere::Transmission:
      return wo.z * wi.z < 0;
  }
  return true;
}
}  // namespace

Estimate integrate_f_cos(const optics::BxDF& bxdf, const Vec3& wo, optics::TransportMode mode,
                         std::int64_t n, std::uint64_t seed, Hemisphere which) {
  return monte_carlo(n, seed, [&](Rng& rng) {
    const double uc = rng.uniform();
    const double u1 = rng.uniform();
    const double u2 = rng.uniform();
    const auto s = bxdf.sample(wo, uc, {u1, u2}, mode);
    if (!s || !counts(which, wo, s->wi)) return 0.0;
    return s->f * std::abs(s->wi.z) / s->pdf;
  });
}

Vec3 uniform_sphere(double u1, double u2) {
  const double z = 1.0 - 2.0 * u1;
  const double r = safe_sqrt(1.0 - z * z);
  const double phi = 2.0 * kPi<double> * u2;
  return {r * std::cos(phi), r * std::sin(phi), z};
}

Vec3 uniform_sphere(Rng& rng) {
  const double u1 = rng.uniform();
  const double u2 = rng.uniform();
  return uniform_sphere(u1, u2);
}

Estimate integrate_f_cos_uniform(const optics::BxDF& bxdf, const Vec3& wo,
                                 optics::TransportMode mode, std::int64_t n, std::uint64_t seed,
                                 Hemisphere which) {
  return monte_carlo(n, seed, [&](Rng& rng) {
    const double u1 = rng.uniform();
    const double u2 = rng.uniform();
    const Vec3 wi = uniform_sphere(u1, u2);
    if (!counts(which, wo, wi)) return 0.0;
    return bxdf.f(wo, wi, mode) * std::abs(wi.z) * 4.0 * kPi<double>;
  });
}

}  // namespace hydrolux::test
