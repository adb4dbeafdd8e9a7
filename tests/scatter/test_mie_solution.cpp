// scatter::solve_mie, the sphere `hydrolux mie` solves (io/mie_job.hpp prints it): checked against
// Bohren & Huffman's (1983) Appendix A example (r = 0.525 um, m = 1.55, lambda = 0.6328 um: Qext =
// Qsca = 3.10543, Qback = 2.92534, g = 0.63314; S11 / S11(0) = 0.785390 at 9 degrees and 0.124601e-1 at
// 90, pol = -S12 / S11 = 0.230462 at 90, 6 significant digits, as tests/scatter/test_mie.cpp reads them)
// and the optical theorem (Qext = 4 / x^2 Re S(0), S1(0) = S2(0)).
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <vector>

#include "hydrolux/core/math.hpp"
#include "hydrolux/scatter/mie_solution.hpp"

namespace hydrolux::scatter {
namespace {

const double kX = 2 * kPi<> * 0.525 / 0.6328;
const Complex kM(1.55, 0);

// Half a unit in the last of `digits` significant digits of `v`.
double half_unit(double v, int digits) {
  return 0.5 * std::pow(10.0, std::floor(std::log10(std::abs(v))) - (digits - 1));
}

void expect_bohren_huffman_efficiencies(const MieEfficiencies& q) {
  EXPECT_NEAR(q.qext, 3.10543, half_unit(3.10543, 6));
  EXPECT_NEAR(q.qsca, 3.10543, half_unit(3.10543, 6));
  EXPECT_NEAR(q.qback, 2.92534, half_unit(2.92534, 6));
  EXPECT_NEAR(q.g, 0.63314, half_unit(0.63314, 5));
  EXPECT_EQ(q.qabs, 0.0);
}

std::vector<double> cosines(std::vector<double> deg) {
  for (double& d : deg) d = std::cos(deg_to_rad(d));
  return deg;
}

TEST(SolveMie, EfficienciesAloneWithoutAngles) {
  const MieSolution s = solve_mie(kM, kX, {});
  expect_bohren_huffman_efficiencies(s.q);
  EXPECT_GT(s.terms, 0);
  EXPECT_TRUE(s.s1.empty());
  EXPECT_TRUE(s.s2.empty());
}

TEST(SolveMie, AmplitudesMatchBohrenHuffmanAppendixA) {
  const std::vector<double> mu = cosines({0, 9, 90});
  const MieSolution s = solve_mie(kM, kX, mu, {}, 1);
  expect_bohren_huffman_efficiencies(s.q);
  ASSERT_EQ(s.s1.size(), 3u);
  ASSERT_EQ(s.s2.size(), 3u);
  const auto s11 = [&](int j) { return 0.5 * (std::norm(s.s1[j]) + std::norm(s.s2[j])); };
  EXPECT_NEAR(s11(1) / s11(0), 0.785390, half_unit(0.785390, 6) + 1e-6);
  EXPECT_NEAR(s11(2) / s11(0), 0.124601e-1, half_unit(0.124601e-1, 6) + 1e-6);
  const double pol90 = -0.5 * (std::norm(s.s2[2]) - std::norm(s.s1[2])) / s11(2);
  EXPECT_NEAR(pol90, 0.230462, half_unit(0.230462, 6) + 1e-6);
  // Forward: S1 = S2, and the optical theorem.
  EXPECT_NEAR(std::abs(s.s1[0] - s.s2[0]), 0.0, 1e-12 * std::abs(s.s1[0]));
  EXPECT_NEAR(4 / (kX * kX) * s.s1[0].real(), 3.10543, half_unit(3.10543, 6));
}

// A Debye order restricts the amplitudes, not the efficiencies (of the whole sphere); the terms are the
// sphere's too.
TEST(SolveMie, DebyeOrderKeepsTheWholeSpheresEfficiencies) {
  const std::vector<double> mu = cosines({0, 138});
  const MieSolution whole = solve_mie(kM, kX, mu);
  const MieSolution p1 = solve_mie(kM, kX, mu, 1);
  expect_bohren_huffman_efficiencies(p1.q);
  EXPECT_EQ(p1.terms, whole.terms);
  ASSERT_EQ(p1.s1.size(), 2u);
  // Diffraction and reflection (p = 0) carry the forward peak: one order's S(0) is not the whole's.
  EXPECT_GT(std::abs(p1.s1[0] - whole.s1[0]), 1e-3 * std::abs(whole.s1[0]));
}

}  // namespace
}  // namespace hydrolux::scatter
