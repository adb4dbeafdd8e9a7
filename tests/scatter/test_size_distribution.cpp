// Drop size distributions: normalisation, moments against closed forms, Marshall-Palmer as in
// Garg & Nayar (seed 000), and the accuracy of the quadratures used to average over drops.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <functional>
#include <vector>

#include "hydrolux/core/error.hpp"
#include "hydrolux/core/math.hpp"
#include "hydrolux/scatter/size_distribution.hpp"
#include "hydrolux/scatter/theories.hpp"
#include "support/stats.hpp"

namespace hydrolux::scatter {
namespace {

// Composite 8-point Gauss-Legendre on [a, b] (tests/support), independent of the library's
// Golub-Welsch rules: 2000 panels resolve every density here to ~1e-14.
double integrate(const std::function<double(double)>& f, double a, double b, int panels = 2000) {
  const auto q = test::gauss_legendre(8, 0.0, 1.0);
  const double h = (b - a) / panels;
  double sum = 0;
  for (int k = 0; k < panels; ++k)
    for (std::size_t i = 0; i < q.x.size(); ++i) sum += h * q.w[i] * f(a + h * (k + q.x[i]));
  return sum;
}

// A range that holds all but ~1e-16 of the drops of a gamma or Marshall-Palmer distribution.
double upper_radius(const SizeDistribution& d) {
  if (d.kind() == SizeDistributionKind::marshall_palmer) return 45 / d.lambda();
  return 2 * d.mean_radius() * (1 + 40 * std::sqrt(d.radius_variance()) / d.mean_radius());
}

// int f(r) n(r) dr by the independent composite rule: over r for gamma and Marshall-Palmer, over
// u = ln r in mu +- 12 s for the log-normal (whose tail in r is too long for a uniform grid).
double integrate_density(const SizeDistribution& d, const std::function<double(double)>& f) {
  if (d.kind() == SizeDistributionKind::log_normal) {
    return integrate(
        [&](double u) {
          const double r = std::exp(u);
          return f(r) * d.number_density(r) * r;
        },
        d.mu() - 12 * d.sigma(), d.mu() + 12 * d.sigma());
  }
  return integrate([&](double r) { return f(r) * d.number_density(r); }, 0, upper_radius(d));
}

std::vector<SizeDistribution> continuous_cases() {
  std::vector<SizeDistribution> v;
  for (double w : {0.05, 0.3, 1.0}) {
    v.push_back(SizeDistribution::gamma(1e-3, w, 250.0));
    v.push_back(SizeDistribution::log_normal(1e-3, w, 250.0));
  }
  for (double h : {1.0, 10.0, 50.0}) v.push_back(SizeDistribution::marshall_palmer(h));
  return v;
}

// ---------------------------------------------------------------------------------------------
// Normalisation and moments
// ---------------------------------------------------------------------------------------------

// int n(r) dr = N: the density integrates to the number concentration, for every shape. Tolerance
// 1e-10 relative: the independent quadrature's error.
TEST(SizeDistribution, DensityIntegratesToTheNumberConcentration) {
  for (const auto& d : continuous_cases()) {
    const double total = integrate_density(d, [](double) { return 1.0; });
    EXPECT_NEAR(total, d.number_concentration(), 1e-10 * d.number_concentration());
    // and its first two moments agree with moment() (the closed forms below)
    const double m1 = integrate_density(d, [](double r) { return r; });
    const double m2 = integrate_density(d, [](double r) { return r * r; });
    EXPECT_NEAR(m1, d.moment(1), 1e-10 * d.moment(1));
    EXPECT_NEAR(m2, d.moment(2), 1e-10 * d.moment(2));
  }
}

// Gamma: <r> = alpha beta and var = alpha beta^2, so with alpha = 1/w^2, beta = mean w^2 the mean
// is the given one and sigma/<r> = w; r_eff = M3/M2 = beta (alpha + 2) = mean (1 + 2 w^2)
// (Hansen & Travis 1974 eq. 2.56 family). Log-normal: <r> = exp(mu + s^2/2), var = <r>^2
// (exp(s^2) - 1) = (w <r>)^2, r_eff = <r> (1 + w^2)^2. Closed forms: 1e-13 relative.
TEST(SizeDistribution, MeansAndVariancesMatchClosedForms) {
  for (double w : {0.01, 0.1, 0.5, 1.0}) {
    const double mean = 2.5e-4;
    const auto g = SizeDistribution::gamma(mean, w, 10.0);
    EXPECT_NEAR(g.mean_radius(), mean, 1e-13 * mean);
    EXPECT_NEAR(g.radius_variance(), sqr(w * mean), 1e-13 * sqr(w * mean));
    EXPECT_NEAR(g.moment(2) / g.moment(0) - sqr(g.mean_radius()), sqr(w * mean),
                1e-9 * sqr(mean));  // the same from raw moments (cancellation for small w)
    EXPECT_NEAR(g.effective_radius(), mean * (1 + 2 * w * w), 1e-13 * mean);
    EXPECT_NEAR(g.number_concentration(), 10.0, 1e-13);
    const auto l = SizeDistribution::log_normal(mean, w, 10.0);
    EXPECT_NEAR(l.mean_radius(), mean, 1e-13 * mean);
    EXPECT_NEAR(l.radius_variance(), sqr(w * mean), 1e-13 * sqr(w * mean));
    EXPECT_NEAR(l.effective_radius(), mean * sqr(1 + w * w), 1e-13 * mean);
  }
  // Non-integer moments of a narrow gamma (alpha = 1e4: the Stirling path) against its quadrature.
  const auto g = SizeDistribution::gamma(1e-3, 0.01);
  const auto q = g.quadrature(40);
  double m = 0;
  for (std::size_t i = 0; i < q.size(); ++i) m += q.weight[i] * std::sqrt(q.radius_m[i]);
  EXPECT_NEAR(g.moment(0.5), m, 1e-12 * m);
  // M_-1.5 M_1.5 / N^2 = Gamma(alpha - 1.5) Gamma(alpha + 1.5) / Gamma(alpha)^2 (lgamma's
  // rounding at 1e4, ~1e-11, sets the tolerance 1e-9)
  const double a = g.alpha();
  EXPECT_NEAR(g.moment(-1.5) * g.moment(1.5),
              std::exp(std::lgamma(a - 1.5) + std::lgamma(a + 1.5) - 2 * std::lgamma(a)), 1e-9);
}

// Marshall & Palmer as Garg & Nayar write it (seed 000, eq. 2): N(a) = 8e6 exp(-8200 h^-0.21 a)
// per m^3 per m of radius. Its mean radius is 1/Lambda, Lambda = 8200 h^-0.21 m^-1 (0.20 mm at
// 10 mm/h), its number concentration N0/Lambda (1582 drops per m^3 at 10 mm/h), and
// M_k = N0 k! / Lambda^(k+1). Closed forms: 1e-13 relative.
TEST(SizeDistribution, MarshallPalmerMeanRadiusIsOneOverLambda) {
  for (double h : {0.5, 1.0, 5.0, 10.0, 25.0, 100.0}) {
    const auto d = SizeDistribution::marshall_palmer(h);
    const double lambda = 8200 * std::pow(h, -0.21);
    EXPECT_NEAR(d.lambda(), lambda, 1e-12 * lambda);
    EXPECT_NEAR(d.mean_radius(), 1 / lambda, 1e-13 / lambda);
    EXPECT_NEAR(d.number_concentration(), 8e6 / lambda, 1e-13 * 8e6 / lambda);
    EXPECT_NEAR(d.radius_variance(), 1 / sqr(lambda), 1e-13 / sqr(lambda));
    EXPECT_NEAR(d.moment(3), 8e6 * 6 / std::pow(lambda, 4), 1e-13 * 8e6 * 6 / std::pow(lambda, 4));
    EXPECT_NEAR(d.number_density(1e-3), 8e6 * std::exp(-lambda * 1e-3), 1e-6);
  }
  const auto d10 = SizeDistribution::marshall_palmer(10);
  EXPECT_NEAR(d10.mean_radius(), 1.978e-4, 1e-7);
  EXPECT_NEAR(d10.number_concentration(), 1582.3, 0.1);
  // Marshall and Palmer's own N0 (per diameter) doubles the count, not the shape.
  const auto mp = SizeDistribution::marshall_palmer(10, 1.6e7);
  EXPECT_NEAR(mp.number_concentration(), 2 * d10.number_concentration(), 1e-9);
  EXPECT_NEAR(mp.mean_radius(), d10.mean_radius(), 1e-18);
}

TEST(SizeDistribution, Monodisperse) {
  const auto d = SizeDistribution::monodisperse(5e-4, 3.0);
  EXPECT_EQ(d.moment(0), 3.0);
  EXPECT_NEAR(d.moment(2), 3.0 * 25e-8, 1e-20);
  EXPECT_EQ(d.mean_radius(), 5e-4);
  EXPECT_EQ(d.radius_variance(), 0.0);
  EXPECT_EQ(d.number_density(4e-4), 0.0);
  EXPECT_TRUE(std::isinf(d.number_density(5e-4)));
  const auto q = d.quadrature(16);
  ASSERT_EQ(q.size(), 1u);
  EXPECT_EQ(q.radius_m[0], 5e-4);
  EXPECT_EQ(q.weight[0], 3.0);
  EXPECT_EQ(d.quadrature(16, 1e-4, 1e-3).size(), 1u);
  EXPECT_EQ(d.quadrature(16, 6e-4, 1e-3).size(), 0u);
}

// ---------------------------------------------------------------------------------------------
// Quadratures
// ---------------------------------------------------------------------------------------------

// Golub-Welsch on the Legendre recurrence reproduces the 5-point Gauss-Legendre rule of A&S
// Table 25.4 (15 digits printed there): tolerance 1e-14.
TEST(Quadrature, GolubWelschReproducesGaussLegendre) {
  std::vector<double> diag(5, 0.0), off(4), nodes, weights;
  for (int k = 1; k < 5; ++k) off[k - 1] = k / std::sqrt(4.0 * k * k - 1);
  gauss_from_jacobi(diag, off, 2.0, nodes, weights);
  const double x[5] = {-0.906179845938664, -0.538469310105683, 0, 0.538469310105683,
                       0.906179845938664};
  const double w[5] = {0.236926885056189, 0.478628670499366, 0.568888888888889, 0.478628670499366,
                       0.236926885056189};
  for (int i = 0; i < 5; ++i) {
    EXPECT_NEAR(nodes[i], x[i], 1e-14);
    EXPECT_NEAR(weights[i], w[i], 1e-14);
  }
}

// An n-node Gaussian rule integrates polynomials of degree <= 2n - 1 exactly against its weight:
// for gamma and Marshall-Palmer the moments M_0..M_(2n-1) of r, for the log-normal those of ln r
// (normal moments: E[(ln r - mu)^k] = s^k (k - 1)!! for even k, 0 for odd). Relative 1e-11: the
// eigen-solver's rounding, amplified by the spread of the high moments; for the log-normal
// relative to the sum of the terms' magnitudes, as odd moments are zero.
TEST(Quadrature, GaussianRulesAreExactForPolynomials) {
  for (int nodes : {1, 3, 8, 16}) {
    for (const auto& d : continuous_cases()) {
      const auto q = d.quadrature(nodes);
      ASSERT_EQ(static_cast<int>(q.size()), nodes);
      for (std::size_t i = 1; i < q.size(); ++i) EXPECT_LT(q.radius_m[i - 1], q.radius_m[i]);
      for (int k = 0; k <= 2 * nodes - 1; ++k) {
        double sum = 0;
        if (d.kind() == SizeDistributionKind::log_normal) {
          double scale = 0;  // sum of |terms|: odd moments cancel among terms this large
          for (std::size_t i = 0; i < q.size(); ++i) {
            const double t = (std::log(q.radius_m[i]) - d.mu()) / d.sigma();
            sum += q.weight[i] * std::pow(t, k);
            scale += q.weight[i] * std::pow(std::abs(t), k);
          }
          double expected = 0;
          if (k % 2 == 0) {
            expected = d.number_concentration();
            for (int j = k - 1; j > 0; j -= 2) expected *= j;
          }
          // t = (ln r - mu) / s is recovered from r with an error ~eps |mu| / s
          const double tolerance = 1e-11 * scale * (1 + std::abs(d.mu()) / d.sigma());
          EXPECT_NEAR(sum, expected, tolerance) << nodes << " " << k;
        } else {
          for (std::size_t i = 0; i < q.size(); ++i)
            sum += q.weight[i] * std::pow(q.radius_m[i], k);
          EXPECT_NEAR(sum, d.moment(k), 1e-11 * d.moment(k)) << nodes << " " << k;
        }
      }
    }
  }
}

// Smooth, non-polynomial integrands converge fast. Laplace transforms in closed form:
// gamma E[exp(-s r)] = (1 + s beta)^(-alpha); Marshall-Palmer int N0 exp(-(Lambda + s) r) dr =
// N0 / (Lambda + s); log-normal E[r^k] = exp(k mu + k^2 s^2 / 2) for non-integer k (smooth in
// ln r). 24 nodes: relative 1e-10.
TEST(Quadrature, SmoothFunctionsConverge) {
  for (const auto& d : continuous_cases()) {
    const auto q = d.quadrature(24);
    const double s = 1 / d.mean_radius();
    double sum = 0, pw = 0;
    for (std::size_t i = 0; i < q.size(); ++i) {
      sum += q.weight[i] * std::exp(-s * q.radius_m[i]);
      pw += q.weight[i] * std::pow(q.radius_m[i], 2.5);
    }
    if (d.kind() == SizeDistributionKind::gamma) {
      EXPECT_NEAR(sum, d.number_concentration() * std::pow(1 + s * d.beta(), -d.alpha()),
                  1e-10 * sum);
    } else if (d.kind() == SizeDistributionKind::marshall_palmer) {
      EXPECT_NEAR(sum, d.n0() / (d.lambda() + s), 1e-10 * sum);
    }
    if (d.kind() == SizeDistributionKind::log_normal) {
      EXPECT_NEAR(pw, d.moment(2.5), 1e-10 * pw);
    } else {
      // r^2.5 has a branch point at r = 0, inside the Laguerre weight's support: the rule converges
      // only algebraically there (~1e-6 at 24 nodes); a caution, not an accuracy claim.
      EXPECT_NEAR(pw, d.moment(2.5), 1e-5 * pw);
    }
  }
}

// Oscillating integrands (a size-averaged Mie intensity oscillates with r on the scale of the
// wavelength) need the dense Gauss-Legendre rule on a range: the characteristic functions
// E[exp(i k r)] = (1 - i k beta)^(-alpha) (gamma) and N0 / (Lambda - i k) (Marshall-Palmer), with
// k chosen so that cos(k r) goes through ~60 periods across the drops. The range holds all but
// ~1e-16 of the drops; 600 nodes: relative 1e-9 of N.
TEST(Quadrature, OscillatingFunctionsOnARange) {
  const auto g = SizeDistribution::gamma(1e-3, 0.3, 5.0);
  const double k = 2 * kPi<double> * 60 / upper_radius(g);
  const auto qg = g.quadrature(600, 0.0, upper_radius(g));
  std::complex<double> sum = 0;
  for (std::size_t i = 0; i < qg.size(); ++i)
    sum += qg.weight[i] * std::exp(std::complex<double>(0, k * qg.radius_m[i]));
  const auto expected = 5.0 * std::pow(std::complex<double>(1, -k * g.beta()), -g.alpha());
  EXPECT_NEAR(std::abs(sum - expected), 0.0, 1e-9 * 5.0);

  const auto mp = SizeDistribution::marshall_palmer(20);
  const double r_max = 45 / mp.lambda(), kk = 2 * kPi<double> * 60 / r_max;
  const auto qm = mp.quadrature(600, 0.0, r_max);
  std::complex<double> s2 = 0;
  for (std::size_t i = 0; i < qm.size(); ++i)
    s2 += qm.weight[i] * std::exp(std::complex<double>(0, kk * qm.radius_m[i]));
  const auto e2 = mp.n0() / std::complex<double>(mp.lambda(), -kk);
  EXPECT_NEAR(std::abs(s2 - e2), 0.0, 1e-9 * mp.number_concentration());
}

// The averaging helper: number-weighted means of scalar and vector-valued per-drop quantities
// (e.g. |S1|^2 and |S2|^2 at several angles), and integrals per m^3.
TEST(Quadrature, AverageOverDrops) {
  const auto d = SizeDistribution::gamma(2e-4, 0.2, 100.0);
  const std::vector<double> mean = average_over(d, 12, [](double r) {
    return std::vector<double>{1.0, r, r * r};
  });
  ASSERT_EQ(mean.size(), 3u);
  EXPECT_NEAR(mean[0], 1.0, 1e-13);
  EXPECT_NEAR(mean[1], d.mean_radius(), 1e-13 * d.mean_radius());
  EXPECT_NEAR(mean[2], d.moment(2) / d.moment(0), 1e-12 * d.moment(2) / d.moment(0));
  const double area = average_over(d, 12, [](double r) { return kPi<double> * r * r; });
  EXPECT_NEAR(area, kPi<double> * d.moment(2) / d.moment(0), 1e-12 * area);
  const double total = integrate_over(d, 12, [](double) { return 1.0; });
  EXPECT_NEAR(total, 100.0, 1e-11);
  // A truncated rule averages over the drops it holds.
  const auto q = d.quadrature(200, 0.0, 1e-2);
  EXPECT_NEAR(average_over(q, [](double r) { return r; }), d.mean_radius(),
              1e-12 * d.mean_radius());
  const auto mono = SizeDistribution::monodisperse(1e-4);
  EXPECT_EQ(average_over(mono, 5, [](double r) { return r; }), 1e-4);
}

TEST(SizeDistribution, DomainErrors) {
  EXPECT_THROW(SizeDistribution::monodisperse(0.0), DomainError);
  EXPECT_THROW(SizeDistribution::monodisperse(-1e-3), DomainError);
  EXPECT_THROW(SizeDistribution::gamma(1e-3, 0.0), DomainError);
  EXPECT_THROW(SizeDistribution::gamma(1e-3, 1.5), DomainError);
  EXPECT_THROW(SizeDistribution::gamma(0.0, 0.5), DomainError);
  EXPECT_THROW(SizeDistribution::log_normal(1e-3, 0.0), DomainError);
  EXPECT_THROW(SizeDistribution::log_normal(1e-3, std::nan("")), DomainError);
  EXPECT_THROW(SizeDistribution::log_normal(1e-3, 0.5, -2.0), DomainError);
  EXPECT_THROW(SizeDistribution::marshall_palmer(0.0), DomainError);
  EXPECT_THROW(SizeDistribution::marshall_palmer(-3.0), DomainError);
  EXPECT_THROW(SizeDistribution::marshall_palmer(10.0, 0.0), DomainError);
  // Issue 38: one upper limit for the rain rate, kMaxRainRateMmh (core/params.hpp), named rain_rate_mmh
  // as every job names it; 1000 mm/h, taken before, is refused. Any positive rate below it is taken
  // (the rain and the sky render 0.005 mm/h as before; the doors' distributions floor at 0.01).
  EXPECT_NO_THROW(SizeDistribution::marshall_palmer(kMaxRainRateMmh));
  EXPECT_NO_THROW(SizeDistribution::marshall_palmer(0.005));
  for (const double h : {600.0, 1000.0}) {
    try {
      (void)SizeDistribution::marshall_palmer(h);
      ADD_FAILURE() << h << " mm/h accepted";
    } catch (const DomainError& e) {
      EXPECT_EQ(e.quantity(), "rain_rate_mmh");
      EXPECT_EQ(e.hi(), 500);
      EXPECT_NE(std::string(e.what()).find("500"), std::string::npos) << e.what();
    }
  }
  const auto d = SizeDistribution::gamma(1e-3, 0.5);
  EXPECT_THROW(d.quadrature(0), DomainError);
  EXPECT_THROW(d.quadrature(8, 1e-3, 1e-4), DomainError);
  EXPECT_THROW(d.moment(-5.0), DomainError);  // diverges for k <= -alpha = -4
  EXPECT_THROW(SizeDistribution::marshall_palmer(5).moment(-1.0), DomainError);
}

// The text forms (the CLI's --size-distribution): valid ones parse to their kind and parameter;
// anything else is an error that names the valid forms and ranges, and never yields NaN.
TEST(SizeDistribution, SpecsParseWithTheirRanges) {
  EXPECT_EQ(parse_size_distribution("mono").kind, SizeDistributionKind::monodisperse);
  const auto g = parse_size_distribution("gamma:0.1");
  EXPECT_EQ(g.kind, SizeDistributionKind::gamma);
  EXPECT_EQ(g.parameter, 0.1);
  EXPECT_EQ(parse_size_distribution("lognormal:1e-4").kind, SizeDistributionKind::log_normal);
  EXPECT_EQ(parse_size_distribution("marshall-palmer:25").parameter, 25.0);
  for (const char* bad : {"", "mono:1", "gamma", "gamma:", "gamma:0", "gamma:1e-300", "gamma:9e-5", "gamma:1.01",
                          "gamma:nan", "lognormal:-0.1", "marshall-palmer:0", "marshall-palmer:0.009",
                          "marshall-palmer:1001", "marshall-palmer:600", "marshall-palmer", "foo:1", "gamma:1,2"}) {
    try {
      (void)parse_size_distribution(bad);
      ADD_FAILURE() << bad;
    } catch (const Error& e) {
      const std::string m = e.what();
      EXPECT_NE(m.find("valid: mono, gamma:W, lognormal:W (W the relative width in [0.0001, 1])"), std::string::npos)
          << m;
      EXPECT_EQ(m.find("-nan"), std::string::npos) << m;  // what the CLI once printed
    }
  }
  EXPECT_THROW(SizeDistribution::gamma(1e-3, 0.5 * kMinRelativeWidth), DomainError);
  // The rain rate's one range (issue 38): marshall-palmer:H as marshall_palmer() takes it, said with H.
  EXPECT_EQ(parse_size_distribution("marshall-palmer:500").parameter, 500.0);
  try {
    (void)parse_size_distribution("marshall-palmer:600");
    ADD_FAILURE() << "marshall-palmer:600 accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("H = 600 is outside [0.01, 500] mm/h"), std::string::npos) << e.what();
  }
}

// Narrow distributions. The average of a Mie-like ripple (period 0.25 um at a mean radius of 10 um)
// over a normal spread s = w r0 is the ripple damped by exp(-k^2 s^2 / 2); gamma and log-normal
// approach the normal as w shrinks (skewness 2w and about 3w). Before the gamma range followed the
// width, 64 nodes spread over [1e-3, 1.01] of the mean missed a peak of relative width 1e-3 (7%
// off through the CLI) and found no weight at all at 1e-5. Bounds: about 10x the measured
// departures (1e-9, 8e-6, 3e-3 at w = 1e-4, 1e-3, 1e-2), which are the skewness terms, of order
// (k s)^3 w.
TEST(Quadrature, NarrowDistributionsAreMonodisperse) {
  const double r0 = 10e-6;
  const auto f = [&](double r) { return 2 + std::sin(2 * kPi<> * r / 0.25e-6); };  // ripple every 0.25 um
  for (double w : {kMinRelativeWidth, 1e-3, 1e-2}) {
    for (const auto& d : {SizeDistribution::gamma(r0, w), SizeDistribution::log_normal(r0, w)}) {
      const auto q = intensity_quadrature(d, 64);
      double sum = 0, weight = 0;
      for (std::size_t i = 0; i < q.size(); ++i) sum += q.weight[i] * f(q.radius_m[i]), weight += q.weight[i];
      ASSERT_GT(weight, 0) << w;
      // The exact average of sin over a normal spread s: e^(-k^2 s^2 / 2) damps the ripple.
      const double k = 2 * kPi<> / 0.25e-6, s = w * r0;
      const double expected = 2 + std::sin(k * r0) * std::exp(-0.5 * k * k * s * s);
      EXPECT_NEAR(sum / weight, expected, w < 1e-3 ? 1e-8 : w < 1e-2 ? 5e-5 : 2e-2) << "width " << w;
    }
  }
}

}  // namespace
}  // namespace hydrolux::scatter
