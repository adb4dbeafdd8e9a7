// Claims of docs/sky.md checked against formulas written out here and textbook identities.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <vector>

#include "hydrolux/core/math.hpp"
#include "hydrolux/scatter/geometric.hpp"
#include "hydrolux/scatter/mie.hpp"

namespace hydrolux {
namespace {

constexpr double kPi = hydrolux::kPi<double>;
constexpr double kDeg = kPi / 180;

// docs/sky.md l. 84-85: the corona table is not used beyond its 1-50 um, because the first dark
// ring of the corona of rain drops (radius 0.1 mm and more) lies within 0.2 degrees of the sun at
// 550 nm. Reference: Fraunhofer diffraction by the drop's disk, intensity (2 J1(u) / u)^2 with
// u = x sin theta, whose first zero is u = 3.831706 (the first zero of J1: Abramowitz & Stegun
// Table 9.5): 0.19 degrees for 0.1 mm at 550 nm (larger drops have it nearer; at 700 nm drops from
// 0.125 mm). The library's Fraunhofer amplitude vanishes there (1e-6 of its forward value).
TEST(SkyClaims, CoronaOfRainDropsLiesWithinTwoTenthsOfADegree) {
  const double j1_zero = 3.831706;
  const auto first_ring_deg = [&](double radius_um, double nm) {
    const double x = 2 * kPi * radius_um / (nm * 1e-3);
    return std::asin(j1_zero / x) / kDeg;
  };
  EXPECT_LT(first_ring_deg(100, 550), 0.2);
  EXPECT_GT(first_ring_deg(100, 550), 0.18);  // the bound is not loose
  EXPECT_LT(first_ring_deg(125, 700), 0.2);
  const double x = 2 * kPi * 100 / 0.55;
  const double zero = std::asin(j1_zero / x);
  EXPECT_LT(std::abs(scatter::fraunhofer_amplitude(x, zero)), 1e-6 * std::abs(scatter::fraunhofer_amplitude(x, 0)));
}

// docs/sky.md l. 138-139: the rain's extinction is the same for both polarisations, so the sky
// seen through the curtain keeps its polarisation. Reference: a sphere's forward amplitudes are
// equal, S1(0) = S2(0) (Bohren & Huffman 1983, eq. 4.75: at theta = 0, pi_n = tau_n), and the
// extinction of each polarisation is 4 pi / k^2 Re S_j(0) (the optical theorem, B&H 3.25), so the
// two extinctions are equal. Checked on the library's Mie amplitudes at rain and drizzle sizes
// (x = 1e3-2e4, water), to 1e-10 of |S(0)|.
TEST(SkyClaims, RainExtinguishesBothPolarisationsAlike) {
  for (const double x : {1000.0, 5000.0, 20000.0}) {
    const scatter::MieCoefficients c = scatter::mie_coefficients({1.333, 1e-8}, x);
    const std::vector<double> mu{1.0};
    std::vector<std::complex<double>> s1(1), s2(1);
    scatter::mie_amplitudes_reference(c, mu, s1, s2);
    EXPECT_LT(std::abs(s1[0] - s2[0]), 1e-10 * std::abs(s1[0])) << "x " << x;
    // And Re S(0) is the extinction: 4 / x^2 Re S(0) = Q_ext, about 2 for such drops.
    EXPECT_NEAR(4 / (x * x) * s1[0].real(), scatter::mie_efficiencies(c).qext, 1e-9);
  }
}

}  // namespace
}  // namespace hydrolux
