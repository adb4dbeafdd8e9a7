// Cross-theory checks (issue: "Airy close to Mie (Debye p = 2) near the primary rainbow for large
// x; geometric-optics rainbow at the minimum deviation angle; Debye sum over p -> Mie"), through
// the single entry point scatter/theories.hpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "hydrolux/core/error.hpp"
#include "hydrolux/core/math.hpp"
#include "hydrolux/scatter/amplitudes.hpp"
#include "hydrolux/scatter/debye.hpp"
#include "hydrolux/scatter/geometric.hpp"
#include "hydrolux/scatter/theories.hpp"

namespace hydrolux::scatter {
namespace {

std::vector<double> grid_rad(double from_deg, double to_deg, double step_deg) {
  std::vector<double> t;
  for (double a = from_deg; a <= to_deg + 1e-9; a += step_deg) t.push_back(deg_to_rad(a));
  return t;
}

std::vector<double> intensity(const Theory& th, Complex m, double x, const std::vector<double>& theta,
                              bool perpendicular) {
  std::vector<Complex> s1(theta.size()), s2(theta.size());
  amplitudes(th, m, x, theta, s1, s2);
  std::vector<double> i(theta.size());
  for (std::size_t k = 0; k < theta.size(); ++k) i[k] = std::norm(perpendicular ? s1[k] : s2[k]);
  return i;
}

// Airy theory against the exact Debye p = 2 term near the primary rainbow, perpendicular
// polarisation (the strong one), x = 5000, n = 1.333. Airy theory is the large-x asymptote of the
// p = 2 term: van de Hulst section 13.23 and Wang & van de Hulst (1991, Appl. Opt. 30, 106) put its
// error in the main peak at a few per cent for x of a few thousand. Tolerances: main-peak angle
// within 0.01 degrees (the grid step is 0.002), peak height within 5 per cent.
TEST(Theories, AiryMatchesDebyeTwoAtThePrimaryRainbow) {
  const Complex m(1.333, 0);
  const double x = 5000;
  const double theta_r = rad_to_deg(rainbow_angle(1.333, 2));
  const auto theta = grid_rad(theta_r - 0.5, theta_r + 1.0, 0.002);
  const auto debye = intensity(parse_theory("debye:2"), m, x, theta, true);
  const auto airy = intensity(parse_theory("airy"), m, x, theta, true);
  const auto peak_d = std::max_element(debye.begin(), debye.end()) - debye.begin();
  const auto peak_a = std::max_element(airy.begin(), airy.end()) - airy.begin();
  EXPECT_NEAR(rad_to_deg(theta[std::size_t(peak_d)]), rad_to_deg(theta[std::size_t(peak_a)]), 0.01);
  EXPECT_NEAR(airy[std::size_t(peak_a)] / debye[std::size_t(peak_d)], 1.0, 0.05);
  // The peak lies inside the bow: on the lit side of the geometric rainbow angle, where the
  // scattering angle is larger (the rainbow radius 180 - theta smaller).
  EXPECT_GT(rad_to_deg(theta[std::size_t(peak_d)]), theta_r);
}

// The geometric rainbow angle is where the p = 2 light ends: the lit side inside the bow (theta >
// theta_R: the sky inside a rainbow is brighter) carries the two rays, while Alexander's dark side
// (theta < theta_R) has only the Airy tail. Exact Debye p = 2 at x = 5000: mean intensity 1-3
// degrees inside exceeds 1-3 degrees outside a hundredfold (the tail decays as
// exp(-(2/3) z^(3/2)); z ~ 30 at 1 degree here).
TEST(Theories, GeometricRainbowAngleSeparatesLitAndDarkSides) {
  const Complex m(1.333, 0);
  const double theta_r = rad_to_deg(rainbow_angle(1.333, 2));
  EXPECT_NEAR(180.0 - theta_r, 42.08, 0.005);  // the published 42.08-degree radius for n = 1.333
  const auto inside = grid_rad(theta_r + 1, theta_r + 3, 0.01);
  const auto outside = grid_rad(theta_r - 3, theta_r - 1, 0.01);
  const auto mean = [](const std::vector<double>& v) {
    double s = 0;
    for (double e : v) s += e;
    return s / double(v.size());
  };
  const auto th = parse_theory("debye:2");
  const double lit = mean(intensity(th, m, 5000, inside, true));
  const double dark = mean(intensity(th, m, 5000, outside, true));
  EXPECT_GT(lit, 100 * dark);
}

// Debye orders 0..P plus the closed-form remainder give the Mie amplitudes back (x = 300, 1 degree
// grid): the amplitude sums are linear in the coefficients, so only rounding separates them
// (1e-9 relative to the largest |S|).
TEST(Theories, DebyeOrdersSumToMie) {
  const Complex m(1.333, 1e-4);
  const double x = 300;
  const auto theta = grid_rad(0, 180, 1);
  std::vector<double> mu(theta.size());
  for (std::size_t k = 0; k < mu.size(); ++k) mu[k] = std::cos(theta[k]);
  std::vector<Complex> sum1(mu.size()), sum2(mu.size()), s1(mu.size()), s2(mu.size());
  const auto add = [&](const MieCoefficients& c) {
    mie_amplitudes(c, mu, s1, s2);
    for (std::size_t k = 0; k < mu.size(); ++k) sum1[k] += s1[k], sum2[k] += s2[k];
  };
  for (int p = 0; p <= 4; ++p) add(debye_coefficients(m, x, p));
  add(debye_remainder(m, x, 4));
  std::vector<Complex> mie1(mu.size()), mie2(mu.size());
  mie_amplitudes(mie_coefficients(m, x), mu, mie1, mie2);
  const double scale = std::abs(mie1[0]);
  for (std::size_t k = 0; k < mu.size(); ++k) {
    EXPECT_LT(std::abs(sum1[k] - mie1[k]) / scale, 1e-9) << k;
    EXPECT_LT(std::abs(sum2[k] - mie2[k]) / scale, 1e-9) << k;
  }
}

// The intensity quadrature keeps the r^2 and r^4 moments of wide distributions (where a fixed
// multiple of the mean drops 8% of r^2 for log-normal width 1): against the closed-form moments
// (size_distribution.hpp), 1e-6 relative with 400 nodes; the number within the documented cut
// (1e-3 of the drops for the width-1 gamma, 1e-15 for log-normal: 8 sigma).
TEST(Theories, IntensityQuadratureKeepsTheTails) {
  for (const auto& d : {SizeDistribution::log_normal(100e-6, 1.0), SizeDistribution::log_normal(100e-6, 0.3),
                        SizeDistribution::gamma(100e-6, 1.0), SizeDistribution::gamma(100e-6, 0.1)}) {
    const auto q = intensity_quadrature(d, 400);
    for (double k : {0.0, 2.0, 4.0}) {
      double m = 0;
      for (std::size_t i = 0; i < q.size(); ++i) m += q.weight[i] * std::pow(q.radius_m[i], k);
      EXPECT_NEAR(m / d.moment(k), 1.0, k == 0 ? 1.1e-3 : 1e-6) << "k " << k;
    }
  }
}

TEST(Theories, NamesAndErrors) {
  EXPECT_EQ(theory_name(parse_theory("mie")), "mie");
  EXPECT_EQ(theory_name(parse_theory("debye:3")), "debye:3");
  EXPECT_EQ(theory_name(parse_theory("airy")), "airy:2");
  EXPECT_EQ(theory_name(parse_theory("geometric")), "geometric:3");
  for (const char* bad : {"", "mie:2", "debye", "debye:x", "foo", "airy:2.5"})
    EXPECT_THROW((void)parse_theory(bad), UnknownNameError) << bad;
  EXPECT_THROW((void)parse_theory("debye:-1"), DomainError);
  EXPECT_THROW((void)parse_theory("airy:1"), DomainError);
  std::vector<double> theta{2.4};
  std::vector<Complex> s1(1), s2(1);
  EXPECT_THROW(amplitudes(parse_theory("airy"), {2.5, 0}, 100, theta, s1, s2), DomainError);  // no p=2 bow
}

}  // namespace
}  // namespace hydrolux::scatter
