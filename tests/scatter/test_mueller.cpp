// Mueller matrix elements of a sphere (scatter/mueller.hpp): the identity of a single sphere, the
// Rayleigh limit, Bohren & Huffman's published BHMIE table, and size averages.
//
// Reference table (data/reference/, compiled into the library):
//   bhmie_appendix_a_published.csv  Bohren & Huffman (1983) Appendix A sample output (m = 1.55,
//                               x = 5.213): S11 / S11(0), POL = -S12/S11, S33/S11, S34/S11 at 0..180
//                               degrees in 9-degree steps, 6 digits, as transcribed in miepython's
//                               tests (S. Prahl); the same table tests/scatter/test_mie.cpp checks
//                               from the amplitudes directly.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <stdexcept>
#include <vector>

#include "hydrolux/core/embedded_data.hpp"
#include "hydrolux/core/math.hpp"
#include "hydrolux/core/table.hpp"
#include "hydrolux/optics/media.hpp"
#include "hydrolux/scatter/amplitudes.hpp"
#include "hydrolux/scatter/mie.hpp"
#include "hydrolux/scatter/mueller.hpp"
#include "hydrolux/scatter/size_distribution.hpp"
#include "hydrolux/scatter/sphere.hpp"
#include "hydrolux/scatter/theories.hpp"

namespace hydrolux::scatter {
namespace {

std::vector<double> mu_grid(int n) {
  std::vector<double> mu(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) mu[std::size_t(i)] = std::cos(kPi<> * i / (n - 1));
  return mu;
}

MuellerElements sphere_elements(Complex m, double x, const std::vector<double>& mu) {
  std::vector<Complex> s1(mu.size()), s2(mu.size());
  mie_amplitudes(mie_coefficients(m, x), mu, s1, s2);
  return mueller_elements(s1, s2);
}

double half_unit(double v, int digits) {
  if (v == 0) return 0;
  return 0.5 * std::pow(10.0, std::floor(std::log10(std::abs(v))) - (digits - 1));
}

// B&H eq. 4.77 written out against the definitions, including the sign of S34 (BHMIE, Appendix
// A: S34 = AIMAG(S2 * CONJG(S1))).
TEST(Mueller, ElementsFromAmplitudes) {
  const Complex s1(1, 2), s2(3, -1);
  const MuellerElement e = mueller_element(s1, s2);
  EXPECT_DOUBLE_EQ(e.s11, 0.5 * (10 + 5));
  EXPECT_DOUBLE_EQ(e.s12, 0.5 * (10 - 5));
  // S2 S1* = (3 - i)(1 - 2i) = 1 - 7i.
  EXPECT_DOUBLE_EQ(e.s33, 1);
  EXPECT_DOUBLE_EQ(e.s34, -7);
  const std::vector<Complex> a(3), b(2);
  EXPECT_THROW(mueller_elements(a, b), std::invalid_argument);
}

// For one sphere the matrix is pure: S11^2 = S12^2 + S33^2 + S34^2 (B&H eq. 4.78 holds exactly
// for any S1, S2). Each element carries a few ulps of rounding, so the difference of squares is
// within a few 1e-16 of S11^2; 1e-13 leaves room over 1801 angles of an absorbing sphere whose
// intensities span many decades (the relative check is against S11^2 at that angle).
TEST(Mueller, PureForOneSphere) {
  const auto mu = mu_grid(1801);
  for (const auto& [m, x] : {std::pair{Complex(1.33, 0), 50.0}, {Complex(1.5, 0.1), 20.0}, {Complex(1.33, 1e-8), 500.0}}) {
    const MuellerElements e = sphere_elements(m, x, mu);
    for (std::size_t i = 0; i < mu.size(); ++i) {
      const double lhs = e.s11[i] * e.s11[i];
      const double rhs = e.s12[i] * e.s12[i] + e.s33[i] * e.s33[i] + e.s34[i] * e.s34[i];
      EXPECT_NEAR(lhs, rhs, 1e-13 * lhs) << "x " << x << " angle " << i;
    }
  }
}

// Rayleigh's limit (B&H section 5.2, eq. 5.11 ff.): as x -> 0, S12/S11 = -sin^2 / (1 + cos^2),
// S33/S11 = 2 cos / (1 + cos^2), S34/S11 -> 0. The Mie corrections are O(x^2) relative (the
// magnetic dipole and electric quadrupole terms, of order x^5 against the dipole's x^3): x^2 =
// 1e-6 at x = 1e-3, the tolerance (measured at most 1e-7). S34 needs a phase difference between
// the terms, which for a real index is of still higher order (measured 2e-17); bound 1e-9.
TEST(Mueller, RayleighLimit) {
  const auto mu = mu_grid(37);
  const MuellerElements e = sphere_elements(Complex(1.5, 0), 1e-3, mu);
  for (std::size_t i = 0; i < mu.size(); ++i) {
    const double c = mu[i], s2 = 1 - c * c;
    EXPECT_NEAR(e.s12[i] / e.s11[i], -s2 / (1 + c * c), 1e-6) << "mu " << c;
    EXPECT_NEAR(e.s33[i] / e.s11[i], 2 * c / (1 + c * c), 1e-6) << "mu " << c;
    EXPECT_NEAR(e.s34[i] / e.s11[i], 0, 1e-9) << "mu " << c;
  }
  // At 90 degrees the scattered light is polarised perpendicular to the scattering plane: S12 < 0.
  EXPECT_LT(e.s12[18], 0);
}

// Bohren & Huffman (1983) Appendix A, BHMIE for r = 0.525 um, m = 1.55, lambda = 0.6328 um
// (x = 5.213): the printed S11 / S11(0), POL = -S12/S11, S33/S11, S34/S11. Tolerance as in
// test_mie.cpp's BohrenHuffmanAppendixMatrix: the printed half unit of 6 significant digits plus
// 1e-6 absolute for BHMIE's single-precision arithmetic. Here through mueller_elements and the
// fast amplitude path, so the sign convention of S34 is the library's own.
TEST(Mueller, BohrenHuffmanAppendixTable) {
  const Table t = parse_table(embedded_file("reference/bhmie_appendix_a_published.csv"),
                              "bhmie_appendix_a_published.csv");
  ASSERT_EQ(t.rows(), 21u);
  std::vector<double> mu;
  for (double deg : t.column("theta_deg")) mu.push_back(std::cos(deg_to_rad(deg)));
  const MuellerElements e = sphere_elements(Complex(1.55, 0), 2 * kPi<> * 0.525 / 0.6328, mu);
  for (std::size_t j = 0; j < mu.size(); ++j) {
    const double got[4] = {e.s11[j] / e.s11[0], -e.s12[j] / e.s11[j], e.s33[j] / e.s11[j], e.s34[j] / e.s11[j]};
    const char* names[4] = {"s11", "pol", "s33", "s34"};
    for (int i = 0; i < 4; ++i) {
      const double want = t.column(names[i])[j];
      EXPECT_NEAR(got[i], want, half_unit(want, 6) + 1e-6) << names[i] << " at " << t.column("theta_deg")[j];
    }
  }
}

// The size-averaged elements are the number-weighted means of each drop's elements: recomputed
// here drop by drop from the same quadrature (to rounding, 1e-12 relative to S11). A spread of
// sizes depolarises: S11^2 >= S12^2 + S33^2 + S34^2, strictly somewhere away from 0 and 180 deg.
// A monodisperse "average" is the sphere's own matrix.
TEST(Mueller, SizeAverage) {
  const auto water = optics::find_medium("water");
  const auto air = optics::find_medium("air");
  const double wavelength_nm = 550;
  std::vector<double> theta;
  for (int i = 0; i <= 36; ++i) theta.push_back(kPi<> * i / 36);
  const auto q = intensity_quadrature(SizeDistribution::gamma(2e-6, 0.2), 12);
  const Theory mie{};
  const Intensities avg = average_intensities(mie, q, wavelength_nm, *water, *air, {}, theta, 1);
  const MuellerElements e = mueller_elements(avg);

  MuellerElements want{std::vector<double>(theta.size()), std::vector<double>(theta.size()),
                       std::vector<double>(theta.size()), std::vector<double>(theta.size())};
  double total = 0;
  std::vector<Complex> s1(theta.size()), s2(theta.size());
  for (std::size_t k = 0; k < q.size(); ++k) {
    const auto sp = sphere_problem(q.radius_m[k] * 1e6, wavelength_nm, *water, *air);
    amplitudes(mie, sp.m, sp.x, theta, s1, s2, 1);
    for (std::size_t i = 0; i < theta.size(); ++i) {
      const MuellerElement one = mueller_element(s1[i], s2[i]);
      want.s11[i] += q.weight[k] * one.s11, want.s12[i] += q.weight[k] * one.s12;
      want.s33[i] += q.weight[k] * one.s33, want.s34[i] += q.weight[k] * one.s34;
    }
    total += q.weight[k];
  }
  double most_depolarised = 0;
  for (std::size_t i = 0; i < theta.size(); ++i) {
    const double tol = 1e-12 * e.s11[i];
    EXPECT_NEAR(e.s11[i], want.s11[i] / total, tol) << i;
    EXPECT_NEAR(e.s12[i], want.s12[i] / total, tol) << i;
    EXPECT_NEAR(e.s33[i], want.s33[i] / total, tol) << i;
    EXPECT_NEAR(e.s34[i], want.s34[i] / total, tol) << i;
    const double pure = std::sqrt(e.s12[i] * e.s12[i] + e.s33[i] * e.s33[i] + e.s34[i] * e.s34[i]);
    EXPECT_LE(pure, e.s11[i] * (1 + 1e-13)) << i;
    most_depolarised = std::max(most_depolarised, 1 - pure / e.s11[i]);
  }
  EXPECT_GT(most_depolarised, 0.01);

  const auto mono = SizeDistribution::monodisperse(2e-6).quadrature(1);
  const MuellerElements one = mueller_elements(average_intensities(mie, mono, wavelength_nm, *water, *air, {}, theta, 1));
  const auto sp = sphere_problem(2.0, wavelength_nm, *water, *air);
  amplitudes(mie, sp.m, sp.x, theta, s1, s2, 1);
  const MuellerElements direct = mueller_elements(s1, s2);
  for (std::size_t i = 0; i < theta.size(); ++i) {
    EXPECT_NEAR(one.s33[i], direct.s33[i], 1e-13 * direct.s11[i]) << i;
    EXPECT_NEAR(one.s34[i], direct.s34[i], 1e-13 * direct.s11[i]) << i;
  }
}

// Airy theory and geometric optics give S1 and S2 separately (theories.hpp), so their elements are
// a pure matrix too; and geometric optics polarises the primary rainbow strongly perpendicular
// (Fresnel: at the internal Brewster-near incidence of the rainbow ray R_p << R_s), S12/S11 near -1.
TEST(Mueller, ApproximateTheories) {
  std::vector<double> theta;
  for (int i = 0; i <= 40; ++i) theta.push_back(deg_to_rad(130 + 0.25 * i));
  std::vector<Complex> s1(theta.size()), s2(theta.size());
  for (const auto& name : {"airy", "geometric"}) {
    amplitudes(parse_theory(name), Complex(1.333, 0), 2000, theta, s1, s2);
    const MuellerElements e = mueller_elements(s1, s2);
    for (std::size_t i = 0; i < theta.size(); ++i) {
      const double lhs = e.s11[i] * e.s11[i];
      EXPECT_NEAR(lhs, e.s12[i] * e.s12[i] + e.s33[i] * e.s33[i] + e.s34[i] * e.s34[i], 1e-13 * lhs) << name;
    }
  }
  // The rainbow of m = 1.333 is near 137.9 deg: index 32 is 138 deg.
  amplitudes(parse_theory("airy"), Complex(1.333, 0), 2000, theta, s1, s2);
  const MuellerElement peak = mueller_element(s1[32], s2[32]);
  EXPECT_LT(peak.s12 / peak.s11, -0.8);
}

}  // namespace
}  // namespace hydrolux::scatter
