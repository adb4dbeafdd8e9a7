// Drop size distributions and their quadratures; the equations are in the header.
#include "hydrolux/scatter/size_distribution.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <mutex>
#include <numeric>

#include "hydrolux/core/error.hpp"
#include "hydrolux/core/math.hpp"
#include "hydrolux/core/parse.hpp"

namespace hydrolux::scatter {

namespace {

constexpr double kMaxRadius = 1.0;          // m
constexpr double kMaxConcentration = 1e30;  // m^-3
constexpr double kMaxN0 = 1e12;             // m^-4
constexpr double kTiny = std::numeric_limits<double>::min();

void check_radius(const char* name, double r) { require_in_range(name, r, kTiny, kMaxRadius); }
void check_width(double w) { require_in_range("relative_width", w, kMinRelativeWidth, 1.0); }
void check_number(double n) { require_in_range("number_per_m3", n, kTiny, kMaxConcentration); }
// The arguments of a spread of radii around a mean (gamma, log-normal).
void check_spread(double mean_radius_m, double relative_width, double number_per_m3) {
  check_radius("mean_radius_m", mean_radius_m);
  check_width(relative_width);
  check_number(number_per_m3);
}
void check_nodes(int nodes) { require_in_range("quadrature_nodes", nodes, 1, kMaxQuadratureNodes); }

// ln(Gamma(a + k) / Gamma(a)) for a > 0, a + k > 0, accurate also for large a: lgamma for small a,
// the difference of Stirling series (A&S 6.1.41) otherwise, with log1p for the leading term.
double log_gamma_ratio(double a, double k) {
  if (a < 50 || a + k < 50) return std::lgamma(a + k) - std::lgamma(a);
  const double b = a + k;
  auto tail = [](double z) {  // ln Gamma(z) - [(z - 1/2) ln z - z + ln(2 pi)/2]
    const double z2 = z * z;
    return 1 / (12 * z) - 1 / (360 * z * z2) + 1 / (1260 * z * z2 * z2);
  };
  // (b - 1/2) ln b - (a - 1/2) ln a - k = (a - 1/2) ln(b / a) + k ln b - k
  return (a - 0.5) * std::log1p(k / a) + k * std::log(b) - k + tail(b) - tail(a);
}

// Gamma(a + k) / Gamma(a): a product for small non-negative integer k, exact to rounding.
double gamma_ratio(double a, double k) {
  if (k >= 0 && k <= 64 && k == std::floor(k)) {
    double prod = 1;
    for (int j = 0; j < static_cast<int>(k); ++j) prod *= a + j;
    return prod;
  }
  return std::exp(log_gamma_ratio(a, k));
}

// Gauss rule of `nodes` nodes for the normalised weight t^(alpha-1) e^-t / Gamma(alpha) on
// [0, inf): generalised Laguerre, a = alpha - 1, with monic recurrence coefficients
// a_k = 2k + a + 1 and b_k^2 = k (k + a) (Golub & Welsch 1969, table).
void gauss_laguerre(int nodes, double alpha, std::vector<double>& t, std::vector<double>& w) {
  std::vector<double> diag(nodes), off(nodes > 0 ? nodes - 1 : 0);
  for (int k = 0; k < nodes; ++k) diag[k] = 2.0 * k + alpha;
  for (int k = 1; k < nodes; ++k) off[k - 1] = std::sqrt(k * (k + alpha - 1));
  gauss_from_jacobi(std::move(diag), std::move(off), 1.0, t, w);
}

// Gauss rule for the standard normal weight: probabilists' Hermite, a_k = 0, b_k^2 = k.
void gauss_hermite(int nodes, std::vector<double>& t, std::vector<double>& w) {
  std::vector<double> diag(nodes, 0.0), off(nodes > 0 ? nodes - 1 : 0);
  for (int k = 1; k < nodes; ++k) off[k - 1] = std::sqrt(static_cast<double>(k));
  gauss_from_jacobi(std::move(diag), std::move(off), 1.0, t, w);
}

// Gauss-Legendre on [-1, 1]: a_k = 0, b_k = k / sqrt(4k^2 - 1), mu0 = 2. The rule depends on the count
// alone, and the eigenvalue problem is quadratic in it (4096 nodes: about half a second), so each count's
// rule is computed once per process and kept: the last kKeptRules counts (at most 8 x 64 kB at
// kMaxQuadratureNodes).
void gauss_legendre(int nodes, std::vector<double>& t, std::vector<double>& w) {
  struct Rule {
    std::vector<double> t, w;
  };
  constexpr std::size_t kKeptRules = 8;
  static std::mutex mutex;
  static std::map<int, Rule> rules;
  {
    const std::lock_guard lock(mutex);
    if (const auto it = rules.find(nodes); it != rules.end()) {
      t = it->second.t;
      w = it->second.w;
      return;
    }
  }
  std::vector<double> diag(nodes, 0.0), off(nodes > 0 ? nodes - 1 : 0);
  for (int k = 1; k < nodes; ++k) off[k - 1] = k / std::sqrt(4.0 * k * k - 1);
  gauss_from_jacobi(std::move(diag), std::move(off), 2.0, t, w);
  const std::lock_guard lock(mutex);
  if (rules.size() >= kKeptRules && !rules.contains(nodes)) rules.erase(rules.begin());
  rules.try_emplace(nodes, Rule{t, w});
}

}  // namespace

void gauss_from_jacobi(std::vector<double> d, std::vector<double> e, double mu0,
                       std::vector<double>& nodes, std::vector<double>& weights) {
  const int n = static_cast<int>(d.size());
  e.resize(d.size(), 0.0);               // e[i] joins rows i and i + 1; e[n - 1] = 0
  std::vector<double> z(d.size(), 0.0);  // first components of the eigenvectors
  if (n > 0) z[0] = 1.0;
  const double eps = std::numeric_limits<double>::epsilon();
  for (int l = 0; l < n; ++l) {
    int iterations = 0;
    while (true) {
      int m = l;  // the first negligible off-diagonal element at or after l
      for (; m < n - 1; ++m) {
        if (std::abs(e[m]) <= eps * (std::abs(d[m]) + std::abs(d[m + 1]))) break;
      }
      if (m == l) break;
      if (++iterations > 200) throw Error("gauss_from_jacobi: QL iteration did not converge");
      // Wilkinson shift from the leading 2x2 block, then a chain of plane rotations from m up to l
      // that chases the bulge (the implicit QL step).
      double g = (d[l + 1] - d[l]) / (2 * e[l]);
      double r = std::hypot(g, 1.0);
      g = d[m] - d[l] + e[l] / (g + std::copysign(r, g));
      double s = 1, c = 1, p = 0;
      bool deflated = false;
      for (int i = m - 1; i >= l; --i) {
        const double f = s * e[i], b = c * e[i];
        r = std::hypot(f, g);
        e[i + 1] = r;
        if (r == 0) {  // the matrix split: restart with the smaller block
          d[i + 1] -= p;
          e[m] = 0;
          deflated = true;
          break;
        }
        s = f / r;
        c = g / r;
        g = d[i + 1] - p;
        r = (d[i] - g) * s + 2 * c * b;
        p = s * r;
        d[i + 1] = g + p;
        g = c * r - b;
        const double zi1 = z[i + 1];  // the same rotation on the eigenvectors' first row
        z[i + 1] = s * z[i] + c * zi1;
        z[i] = c * z[i] - s * zi1;
      }
      if (deflated) continue;
      d[l] -= p;
      e[l] = g;
      e[m] = 0;
    }
  }
  std::vector<int> order(d.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) { return d[a] < d[b]; });
  nodes.resize(d.size());
  weights.resize(d.size());
  for (int i = 0; i < n; ++i) {
    nodes[i] = d[order[i]];
    weights[i] = mu0 * z[order[i]] * z[order[i]];
  }
}

SizeDistribution SizeDistribution::monodisperse(double radius_m, double number_per_m3) {
  check_radius("radius_m", radius_m);
  check_number(number_per_m3);
  SizeDistribution d;
  d.kind_ = SizeDistributionKind::monodisperse;
  d.r0_ = radius_m;
  d.number_ = number_per_m3;
  return d;
}

SizeDistribution SizeDistribution::gamma(double mean_radius_m, double relative_width,
                                         double number_per_m3) {
  check_spread(mean_radius_m, relative_width, number_per_m3);
  SizeDistribution d;
  d.kind_ = SizeDistributionKind::gamma;
  d.alpha_ = 1 / (relative_width * relative_width);
  d.beta_ = mean_radius_m * relative_width * relative_width;
  d.number_ = number_per_m3;
  d.mean_ = mean_radius_m;
  return d;
}

SizeDistribution SizeDistribution::log_normal(double mean_radius_m, double relative_width,
                                              double number_per_m3) {
  check_spread(mean_radius_m, relative_width, number_per_m3);
  SizeDistribution d;
  d.kind_ = SizeDistributionKind::log_normal;
  const double s2 = std::log1p(relative_width * relative_width);
  d.s_ = std::sqrt(s2);
  d.mu_ = std::log(mean_radius_m) - s2 / 2;
  d.number_ = number_per_m3;
  d.mean_ = mean_radius_m;
  return d;
}

SizeDistribution SizeDistribution::marshall_palmer(double rain_rate_mmh, double n0_per_m4) {
  // Any positive rate up to the one upper limit: the rain and the sky take rates below the doors'
  // floor for a size distribution (kMinDistributionRainRateMmh), as they did before issue 38.
  if (!(rain_rate_mmh > 0 && rain_rate_mmh <= kMaxRainRateMmh))
    throw DomainError("rain_rate_mmh", rain_rate_mmh, 0, kMaxRainRateMmh, "Marshall-Palmer");
  require_in_range("n0_per_m4", n0_per_m4, kTiny, kMaxN0, "Marshall-Palmer");
  SizeDistribution d;
  d.kind_ = SizeDistributionKind::marshall_palmer;
  d.lambda_ = 8200.0 * std::pow(rain_rate_mmh, -0.21);  // Garg & Nayar eq. 2
  d.n0_ = n0_per_m4;
  d.number_ = n0_per_m4 / d.lambda_;
  return d;
}

double SizeDistribution::number_density(double r) const {
  if (std::isnan(r)) return r;
  if (r < 0) return 0.0;
  switch (kind_) {
    case SizeDistributionKind::monodisperse:
      return r == r0_ ? std::numeric_limits<double>::infinity() : 0.0;
    case SizeDistributionKind::gamma: {
      if (r == 0) return alpha_ > 1 ? 0.0 : (alpha_ == 1 ? number_ / beta_ : 0.0);
      const double t = r / beta_;
      return number_ / beta_ * std::exp((alpha_ - 1) * std::log(t) - t - std::lgamma(alpha_));
    }
    case SizeDistributionKind::log_normal: {
      if (r == 0) return 0.0;
      const double u = (std::log(r) - mu_) / s_;
      return number_ / (r * s_ * std::sqrt(2 * kPi<double>)) * std::exp(-0.5 * u * u);
    }
    case SizeDistributionKind::marshall_palmer:
      return n0_ * std::exp(-lambda_ * r);
  }
  return 0.0;
}

double SizeDistribution::moment(double k) const {
  if (std::isnan(k)) return k;
  switch (kind_) {
    case SizeDistributionKind::monodisperse:
      return number_ * std::pow(r0_, k);
    case SizeDistributionKind::gamma:
      require_in_range("moment_order", k, -alpha_ + 1e-12, 1e6, "this gamma distribution");
      return number_ * std::pow(beta_, k) * gamma_ratio(alpha_, k);
    case SizeDistributionKind::log_normal:
      return number_ * std::exp(k * mu_ + 0.5 * k * k * s_ * s_);
    case SizeDistributionKind::marshall_palmer:
      require_in_range("moment_order", k, -1 + 1e-12, 170, "Marshall-Palmer");
      return n0_ * std::exp(std::lgamma(k + 1) - (k + 1) * std::log(lambda_));
  }
  return 0.0;
}

double SizeDistribution::radius_variance() const {
  switch (kind_) {
    case SizeDistributionKind::monodisperse:
      return 0.0;
    case SizeDistributionKind::gamma:
      return alpha_ * beta_ * beta_;
    case SizeDistributionKind::log_normal:
      return sqr(mean_) * std::expm1(s_ * s_);
    case SizeDistributionKind::marshall_palmer:
      return 1 / sqr(lambda_);
  }
  return 0.0;
}

RadiusQuadrature SizeDistribution::quadrature(int nodes) const {
  check_nodes(nodes);
  RadiusQuadrature q;
  std::vector<double> t, w;
  switch (kind_) {
    case SizeDistributionKind::monodisperse:
      q.radius_m = {r0_};
      q.weight = {number_};
      return q;
    case SizeDistributionKind::gamma:
    case SizeDistributionKind::marshall_palmer: {
      const double alpha = kind_ == SizeDistributionKind::gamma ? alpha_ : 1.0;
      const double beta = kind_ == SizeDistributionKind::gamma ? beta_ : 1 / lambda_;
      gauss_laguerre(nodes, alpha, t, w);
      for (double& v : t) v *= beta;
      break;
    }
    case SizeDistributionKind::log_normal:
      gauss_hermite(nodes, t, w);
      for (double& v : t) v = std::exp(mu_ + s_ * v);
      break;
  }
  for (double& v : w) v *= number_;
  q.radius_m = std::move(t);
  q.weight = std::move(w);
  return q;
}

RadiusQuadrature SizeDistribution::quadrature(int nodes, double r_min, double r_max, bool log_spaced) const {
  check_nodes(nodes);
  require_in_range("r_min_m", r_min, 0.0, kMaxRadius);
  require_in_range("r_max_m", r_max, std::nextafter(r_min, 2 * kMaxRadius), 2 * kMaxRadius);
  RadiusQuadrature q;
  if (kind_ == SizeDistributionKind::monodisperse) {
    if (r0_ >= r_min && r0_ <= r_max) {
      q.radius_m = {r0_};
      q.weight = {number_};
    }
    return q;
  }
  std::vector<double> t, w;
  gauss_legendre(nodes, t, w);
  if (log_spaced) {
    require_in_range("r_min_m", r_min, std::numeric_limits<double>::min(), kMaxRadius);
    const double l0 = std::log(r_min), half = 0.5 * (std::log(r_max) - l0);
    for (std::size_t i = 0; i < t.size(); ++i) {
      t[i] = std::exp(l0 + half * (t[i] + 1));
      w[i] *= half * number_density(t[i]) * t[i];
    }
  } else {
    const double half = 0.5 * (r_max - r_min), mid = 0.5 * (r_max + r_min);
    for (std::size_t i = 0; i < t.size(); ++i) {
      t[i] = mid + half * t[i];
      w[i] *= half * number_density(t[i]);
    }
  }
  q.radius_m = std::move(t);
  q.weight = std::move(w);
  return q;
}

SizeDistributionSpec parse_size_distribution(std::string_view text) {
  const auto colon = text.find(':');
  const std::string_view name = text.substr(0, colon);
  const auto fail = [&](const std::string& why) {
    return Error(fmt::format("'{}': {}; valid: mono, gamma:W, lognormal:W (W the relative width in [{:g}, 1]), "
                             "marshall-palmer:H (H the rain rate in [{:g}, {:g}] mm/h)",
                             text, why, kMinRelativeWidth, kMinDistributionRainRateMmh, kMaxRainRateMmh));
  };
  if (name == "mono") {
    if (colon != std::string_view::npos) throw fail("mono takes no parameter");
    return {SizeDistributionKind::monodisperse, 0};
  }
  SizeDistributionSpec spec;
  if (name == "gamma")
    spec.kind = SizeDistributionKind::gamma;
  else if (name == "lognormal" || name == "log-normal")
    spec.kind = SizeDistributionKind::log_normal;
  else if (name == "marshall-palmer")
    spec.kind = SizeDistributionKind::marshall_palmer;
  else
    throw fail("unknown distribution");
  const bool rain = spec.kind == SizeDistributionKind::marshall_palmer;
  if (colon == std::string_view::npos) throw fail(rain ? "give the rain rate H" : "give the relative width W");
  const auto value = parse::number(text.substr(colon + 1));
  if (!value) throw fail(fmt::format("'{}' is not a number", text.substr(colon + 1)));
  spec.parameter = *value;
  if (rain && !(*value >= kMinDistributionRainRateMmh && *value <= kMaxRainRateMmh))
    throw fail(fmt::format("H = {:g} is outside [{:g}, {:g}] mm/h", *value, kMinDistributionRainRateMmh,
                           kMaxRainRateMmh));
  if (!rain && !(*value >= kMinRelativeWidth && *value <= 1))
    throw fail(fmt::format("W = {:g} is outside [{:g}, 1]{}", *value, kMinRelativeWidth,
                           *value < kMinRelativeWidth && *value > 0 ? " (use mono for narrower)" : ""));
  return spec;
}

}  // namespace hydrolux::scatter
