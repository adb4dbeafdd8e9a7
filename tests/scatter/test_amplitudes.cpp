// The fast amplitude path (Highway SIMD, parity-split +-mu sums, oneTBB) against the scalar
// reference summation.
#include <gtest/gtest.h>
#include <hwy/targets.h>

#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "hydrolux/core/math.hpp"
#include "hydrolux/core/random.hpp"
#include "hydrolux/core/simd.hpp"
#include "hydrolux/scatter/amplitudes.hpp"
#include "hydrolux/scatter/mie.hpp"
#include "support/stats.hpp"

namespace hydrolux::scatter {
namespace {

std::vector<double> grid_deg(double from, double to, int n) {
  std::vector<double> mu(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) mu[std::size_t(i)] = std::cos(deg_to_rad(from + (to - from) * i / (n - 1)));
  return mu;
}

// Largest relative difference |S_fast - S_ref| / |S_ref| over the angles.
double worst_relative(const std::vector<Complex>& fast, const std::vector<Complex>& ref) {
  double worst = 0;
  for (std::size_t i = 0; i < ref.size(); ++i)
    worst = std::max(worst, std::abs(fast[i] - ref[i]) / std::abs(ref[i]));
  return worst;
}

// The requirement: SIMD and scalar paths agree to 1e-9 relative. Both sum the same terms
// in the same order per angle; they differ only in rounding (FMA contraction, the recurrence's
// operation order), ~1e-13 even at x = 1e4 with ~1e4 terms.
TEST(MieAmplitudes, MatchReferenceAcrossSizes) {
  for (double x : {0.01, 1.0, 10.0, 100.0, 1000.0, 10000.0}) {
    for (Complex m : {Complex(1.333, 0), Complex(1.333, 1e-3), Complex(1.5, 0.1)}) {
      const auto c = mie_coefficients(m, x);
      const auto mu = grid_deg(0, 180, x > 1000 ? 361 : 181);
      std::vector<Complex> s1(mu.size()), s2(mu.size()), r1(mu.size()), r2(mu.size());
      mie_amplitudes(c, mu, s1, s2);
      mie_amplitudes_reference(c, mu, r1, r2);
      EXPECT_LT(worst_relative(s1, r1), 1e-9) << "x " << x << " m " << m;
      EXPECT_LT(worst_relative(s2, r2), 1e-9) << "x " << x << " m " << m;
    }
  }
}

// Backscatter at the largest x: S(180) ~ x while the parity partial sums reach x^2, so exactly
// 180 degrees and the angles just off it must still meet 1e-9 (they are summed directly); mu outside
// [-1, 1] or NaN is an error.
TEST(MieAmplitudes, BackscatterAtLargestX) {
  const double x = 1e5;
  const auto c = mie_coefficients({1.333, 0}, x);
  const std::vector<double> mu = {-1.0, -std::cos(10.0 / x), -std::cos(29.0 / x), -std::cos(31.0 / x),
                                  -std::cos(100.0 / x), -0.5, 1.0};
  std::vector<Complex> s1(mu.size()), s2(mu.size()), r1(mu.size()), r2(mu.size());
  mie_amplitudes(c, mu, s1, s2);
  mie_amplitudes_reference(c, mu, r1, r2);
  EXPECT_LT(worst_relative(s1, r1), 1e-9);
  EXPECT_LT(worst_relative(s2, r2), 1e-9);
  std::vector<Complex> one1(1), one2(1);
  EXPECT_THROW(mie_amplitudes(c, std::vector<double>{1.5}, one1, one2), std::invalid_argument);
  EXPECT_THROW(mie_amplitudes(c, std::vector<double>{std::nan("")}, one1, one2), std::invalid_argument);
}

// Any angle list: unsorted, asymmetric, duplicated, -0.0, exactly +-1.
TEST(MieAmplitudes, ArbitraryAngleLists) {
  const auto c = mie_coefficients({1.333, 1e-8}, 250.0);
  Rng rng(5);
  std::vector<double> mu = {1.0, -1.0, 0.0, -0.0, 0.5, 0.5, -0.25};
  for (int i = 0; i < 37; ++i) mu.push_back(2 * rng.uniform() - 1);
  std::vector<Complex> s1(mu.size()), s2(mu.size()), r1(mu.size()), r2(mu.size());
  mie_amplitudes(c, mu, s1, s2);
  mie_amplitudes_reference(c, mu, r1, r2);
  EXPECT_LT(worst_relative(s1, r1), 1e-9);
  EXPECT_LT(worst_relative(s2, r2), 1e-9);
  // Forward: S1(0) = S2(0) = S(0) = 1/2 sum (2n+1)(a_n + b_n) (B&H eq. 4.75).
  Complex s0 = 0;
  for (int n = 1; n <= c.terms(); ++n) s0 += 0.5 * (2 * n + 1) * (c.a[std::size_t(n - 1)] + c.b[std::size_t(n - 1)]);
  EXPECT_LT(std::abs(s1[0] - s0) / std::abs(s0), 1e-12);
  EXPECT_LT(std::abs(s2[0] - s0) / std::abs(s0), 1e-12);
  // Backward: S2(180) = -S1(180) (B&H section 4.4.4).
  EXPECT_LT(std::abs(s2[1] + s1[1]) / std::abs(s1[1]), 1e-12);
  EXPECT_THROW(mie_amplitudes(c, mu, std::span<Complex>(s1).first(3), s2), std::invalid_argument);
}

// Every way the angles are organised gives the reference: a grid symmetric about 90 degrees
// (written straight into the result, its last partial vector through scratch) in both
// directions, with an odd and an even count, counts below, at and around the lane count; a
// monotone grid that is not symmetric (two runs merged); a symmetric grid that is not monotone.
TEST(MieAmplitudes, EveryGridShape) {
  const auto c = mie_coefficients({1.5, 0.01}, 40.0);
  std::vector<std::vector<double>> grids;
  for (int n : {2, 3, 7, 8, 9, 15, 16, 17, 33, 181, 1801}) {
    grids.push_back(grid_deg(0, 180, n));    // descending mu, symmetric
    grids.push_back(grid_deg(180, 0, n));    // ascending mu, symmetric
    grids.push_back(grid_deg(10, 150, n));   // descending, not symmetric
  }
  grids.push_back({0.3});                                 // one angle
  grids.push_back({0.0});                                 // one angle, its own mirror
  grids.push_back({0.5, -0.2, 0.2, -0.5});                // symmetric, not monotone
  grids.push_back({0.9, 0.1, 0.0, -0.1, -0.9});           // symmetric with a middle 0
  for (const auto& mu : grids) {
    std::vector<Complex> s1(mu.size()), s2(mu.size()), r1(mu.size()), r2(mu.size());
    mie_amplitudes(c, mu, s1, s2, 1);
    mie_amplitudes_reference(c, mu, r1, r2);
    EXPECT_LT(worst_relative(s1, r1), 1e-9) << mu.size() << " angles from " << mu.front();
    EXPECT_LT(worst_relative(s2, r2), 1e-9) << mu.size() << " angles from " << mu.front();
  }
}

// The result does not depend on the number of threads (each angle block is summed alone).
TEST(MieAmplitudes, ThreadCountDoesNotChangeResults) {
  const auto c = mie_coefficients({1.333, 0}, 3000.0);
  const auto mu = grid_deg(0, 180, 1801);
  std::vector<Complex> a1(mu.size()), a2(mu.size()), b1(mu.size()), b2(mu.size());
  mie_amplitudes(c, mu, a1, a2, 1);
  mie_amplitudes(c, mu, b1, b2, 0);
  EXPECT_EQ(a1, b1);
  EXPECT_EQ(a2, b2);
  EXPECT_FALSE(simd_target().empty());
}

// The phase function is normalised: (1/4pi) int p dOmega = (1/2) int_{-1}^{1} p dmu = 1. p is a
// polynomial of degree 2N in mu, so Gauss-Legendre with N + 1 nodes integrates it exactly; the
// tolerance covers rounding in sums whose terms reach x^2 times the result: 1e-12 + 2e-16 x^2
// (as test_mie's invariants).
TEST(MieAmplitudes, PhaseFunctionIsNormalised) {
  for (double x : {0.5, 30.0, 700.0}) {
    const auto c = mie_coefficients({1.333, 1e-3}, x);
    const auto q = test::gauss_legendre(c.terms() + 1, -1.0, 1.0);
    const auto p = mie_phase_function(c, q.x);
    double integral = 0;
    for (std::size_t i = 0; i < p.size(); ++i) integral += q.w[i] * p[i];
    EXPECT_NEAR(integral / 2, 1.0, 1e-12 + 2e-16 * x * x) << x;
  }
}

// Every SIMD target compiled in and supported by this CPU (AVX-512, AVX2, SSE4, ... and the
// emulated fallback) gives the reference result: the build runs correctly on CPUs without
// AVX-512. hydrolux::simd::set_targets_for_test selects one target at a time.
TEST(MieAmplitudes, EveryDispatchTargetMatchesReference) {
  const auto c = mie_coefficients({1.333, 1e-6}, 2000.0);
  const auto mu = grid_deg(0, 180, 361);
  std::vector<Complex> r1(mu.size()), r2(mu.size()), s1(mu.size()), s2(mu.size());
  mie_amplitudes_reference(c, mu, r1, r2);
  std::vector<std::int64_t> targets;
  const std::int64_t both = simd::supported_targets() & HWY_TARGETS;
  for (std::int64_t bits = both; bits != 0; bits &= bits - 1) targets.push_back(bits & -bits);
  ASSERT_FALSE(targets.empty());
  std::string names;
  for (const auto target : targets) {
    simd::set_targets_for_test(target);
    EXPECT_EQ(simd_target(), hwy::TargetName(target));
    mie_amplitudes(c, mu, s1, s2);
    EXPECT_LT(worst_relative(s1, r1), 1e-9) << hwy::TargetName(target);
    EXPECT_LT(worst_relative(s2, r2), 1e-9) << hwy::TargetName(target);
    names += std::string(hwy::TargetName(target)) + " ";
  }
  simd::set_targets_for_test(0);
  RecordProperty("targets", names);
  std::printf("dispatch targets tested: %s\n", names.c_str());
}

}  // namespace
}  // namespace hydrolux::scatter
