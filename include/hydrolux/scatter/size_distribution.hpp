#pragma once
// Drop size distributions: the number density n(r) (drops per m^3 per m of radius), its moments,
// and quadratures over the radius for averaging any r-dependent quantity (an intensity, an
// efficiency, a Lee-diagram column) over the drops.
//
// Distributions (r the radius in metres; N the number concentration in m^-3):
// - monodisperse(r0): n(r) = N delta(r - r0).
// - gamma(mean, w): n(r) = N r^(alpha-1) exp(-r/beta) / (Gamma(alpha) beta^alpha), with
//   alpha = 1 / w^2 and beta = mean w^2, so <r> = mean and the relative standard deviation
//   sigma_r / <r> = w (Hansen & Travis 1974, Space Sci. Rev. 16, 527, section 2.1.3, write the same
//   family with an effective radius and variance).
// - log_normal(mean, w): ln r normal with s^2 = ln(1 + w^2), mu = ln(mean) - s^2 / 2, so again
//   <r> = mean and sigma_r / <r> = w.
// - marshall_palmer(h): n(r) = N0 exp(-Lambda r), Lambda = 8200 h^-0.21 m^-1, h the rain rate in
//   mm/h, N0 = 8e6 m^-4 (Marshall & Palmer 1948, J. Meteor. 5, 165, as used by Garg & Nayar 2004,
//   eq. 2: seed 000). Marshall and Palmer's N0 = 8e6 m^-4 is per metre of DIAMETER; Garg & Nayar
//   keep it with the radius, which halves the drop count (their Lambda is converted correctly:
//   4.1 mm^-1 per diameter = 8200 m^-1 per radius). The default follows the seed; pass
//   n0 = 1.6e7 for Marshall and Palmer's own count. <r> = 1 / Lambda, N = N0 / Lambda,
//   M_k = N0 Gamma(k + 1) / Lambda^(k + 1).
//
// Quadratures (nodes r_i and weights w_i with sum_i w_i f(r_i) ~ int f(r) n(r) dr, so that
// sum_i w_i = N):
// - quadrature(nodes): Gaussian for the distribution's own weight, by the Golub-Welsch method
//   (G. H. Golub and J. H. Welsch, Math. Comp. 23, 221, 1969): generalised Gauss-Laguerre for
//   gamma and Marshall-Palmer (exact for polynomials in r of degree <= 2 nodes - 1), Gauss-Hermite
//   in ln r for the log-normal (exact for polynomials in ln r of that degree), one node for the
//   monodisperse. Converges fast for smooth f; its nodes run into the far tail.
// - quadrature(nodes, r_min, r_max): Gauss-Legendre on [r_min, r_max] with weights w_i n(r_i):
//   a truncated range (physical drop sizes) and dense nodes for integrands that oscillate with r,
//   as Mie intensities do.
#include <cstddef>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include "hydrolux/core/params.hpp"  // kMinDistributionRainRateMmh, kMaxRainRateMmh

namespace hydrolux::scatter {

struct RadiusQuadrature {
  std::vector<double> radius_m;  // nodes, ascending
  std::vector<double> weight;    // drops per m^3 represented by each node
  std::size_t size() const { return radius_m.size(); }
};

// Marshall and Palmer's own N0 per metre of radius (their 8e6 m^-4 is per metre of diameter):
// the count that hydrolux sky's rain curtain and hydrolux rain's drops use.
inline constexpr double kMarshallPalmerN0PerRadius = 1.6e7;

enum class SizeDistributionKind { monodisperse, gamma, log_normal, marshall_palmer };

// Valid domain (DomainError outside): radii in (0, 1] m (mean_radius_m, radius_m), relative widths
// in [1e-4, 1] (narrower is monodisperse to 1e-8 in any average a drop's optics can resolve: use
// monodisperse), number concentrations in (0, 1e30] m^-3, rain rates in (0, kMaxRainRateMmh] = (0, 500]
// mm/h (core/params.hpp: the one upper limit; the doors' size distributions take at least
// kMinDistributionRainRateMmh), N0 in (0, 1e12] m^-4,
// quadrature nodes in [1, 4096].
inline constexpr int kMaxQuadratureNodes = 4096;
inline constexpr double kMinRelativeWidth = 1e-4;

class SizeDistribution {
 public:
  static SizeDistribution monodisperse(double radius_m, double number_per_m3 = 1.0);
  static SizeDistribution gamma(double mean_radius_m, double relative_width,
                                double number_per_m3 = 1.0);
  static SizeDistribution log_normal(double mean_radius_m, double relative_width,
                                     double number_per_m3 = 1.0);
  // DomainError naming rain_rate_mmh outside (0, kMaxRainRateMmh] mm/h.
  static SizeDistribution marshall_palmer(double rain_rate_mmh, double n0_per_m4 = 8e6);

  SizeDistributionKind kind() const { return kind_; }

  // n(r) in m^-4 for r >= 0 (0 for r < 0). Monodisperse: 0 away from r0 and +inf at r0 (a delta;
  // use its moments or quadrature).
  double number_density(double radius_m) const;
  // M_k = int r^k n(r) dr (m^(k-3)); k > -alpha for gamma, k > -1 for Marshall-Palmer.
  double moment(double k) const;
  double number_concentration() const { return moment(0); }  // N, m^-3
  double mean_radius() const { return moment(1) / moment(0); }
  double radius_variance() const;                                    // <r^2> - <r>^2
  double effective_radius() const { return moment(3) / moment(2); }  // Hansen & Travis r_eff

  RadiusQuadrature quadrature(int nodes) const;
  // log_spaced: Gauss-Legendre in ln r (weights w_i n(r_i) r_i; needs r_min > 0), for ranges that
  // span decades, where a rule linear in r cannot resolve the small end.
  RadiusQuadrature quadrature(int nodes, double r_min, double r_max, bool log_spaced = false) const;

  // Parameters: gamma alpha and beta (m); log-normal mu (ln m) and s; Marshall-Palmer Lambda (m^-1)
  // and N0 (m^-4); monodisperse r0 (m). Those of other kinds are 0.
  double alpha() const { return alpha_; }
  double beta() const { return beta_; }
  double mu() const { return mu_; }
  double sigma() const { return s_; }
  double lambda() const { return lambda_; }
  double n0() const { return n0_; }
  double radius() const { return r0_; }

 private:
  SizeDistributionKind kind_ = SizeDistributionKind::monodisperse;
  double number_ = 1;            // N (monodisperse, gamma, log-normal)
  double r0_ = 0;                // monodisperse
  double mean_ = 0;              // gamma, log-normal: the mean radius they were given
  double alpha_ = 0, beta_ = 0;  // gamma
  double mu_ = 0, s_ = 0;        // log-normal
  double lambda_ = 0, n0_ = 0;   // Marshall-Palmer
};

// A distribution written as text: "mono", "gamma:W", "lognormal:W" (W the relative width,
// sigma_r / <r>, in [1e-4, 1]) or "marshall-palmer:H" (H the rain rate in
// [kMinDistributionRainRateMmh, kMaxRainRateMmh] mm/h, as SizeDistribution::marshall_palmer takes it).
// The mean radius comes separately.
struct SizeDistributionSpec {
  SizeDistributionKind kind = SizeDistributionKind::monodisperse;
  double parameter = 0;  // W for gamma and log-normal, H for Marshall-Palmer
};
// Throws hydrolux::Error with the reason and the valid forms (naming no flag).
SizeDistributionSpec parse_size_distribution(std::string_view text);

// Gauss quadrature from the three-term recurrence of the orthonormal polynomials: nodes are the
// eigenvalues of the symmetric tridiagonal Jacobi matrix (diagonal a, off-diagonal b, b[k] joining
// rows k and k+1, b.size() = a.size() - 1) and the weights mu0 v_0^2 (Golub & Welsch 1969),
// by implicit QL iterations with Wilkinson shifts. Nodes ascending.
void gauss_from_jacobi(std::vector<double> a, std::vector<double> b, double mu0,
                       std::vector<double>& nodes, std::vector<double>& weights);

namespace detail {
template <class R>
inline constexpr bool kScalarResult = std::is_convertible_v<R, double>;
}

// sum_i w_i f(r_i): the integral of f over the drops (per m^3). f returns a double, or a
// std::vector<double> (every call the same length), summed element by element.
template <class F>
auto integrate_over(const RadiusQuadrature& q, F&& f) {
  using R = std::decay_t<decltype(f(0.0))>;
  if constexpr (detail::kScalarResult<R>) {
    double sum = 0;
    for (std::size_t i = 0; i < q.size(); ++i)
      sum += q.weight[i] * static_cast<double>(f(q.radius_m[i]));
    return sum;
  } else {
    std::vector<double> sum;
    for (std::size_t i = 0; i < q.size(); ++i) {
      const R v = f(q.radius_m[i]);
      if (sum.empty()) sum.assign(v.size(), 0.0);
      for (std::size_t j = 0; j < sum.size() && j < v.size(); ++j) sum[j] += q.weight[i] * v[j];
    }
    return sum;
  }
}

// The number-weighted mean <f> = sum_i w_i f(r_i) / sum_i w_i: what a volume of drops with this
// distribution scatters per drop, when f is a per-drop quantity (an intensity |S|^2, a cross
// section). Same result types as integrate_over.
template <class F>
auto average_over(const RadiusQuadrature& q, F&& f) {
  double total = 0;
  for (double w : q.weight) total += w;
  auto sum = integrate_over(q, std::forward<F>(f));
  if constexpr (std::is_same_v<decltype(sum), double>) {
    return total > 0 ? sum / total : 0.0;
  } else {
    for (double& v : sum) v = total > 0 ? v / total : 0.0;
    return sum;
  }
}

// The same with the distribution's Gaussian quadrature of `nodes` nodes.
template <class F>
auto average_over(const SizeDistribution& d, int nodes, F&& f) {
  return average_over(d.quadrature(nodes), std::forward<F>(f));
}
template <class F>
auto integrate_over(const SizeDistribution& d, int nodes, F&& f) {
  return integrate_over(d.quadrature(nodes), std::forward<F>(f));
}

}  // namespace hydrolux::scatter
