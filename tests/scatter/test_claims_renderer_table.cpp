// Claims of docs/renderer-export.md about the phase table of `hydrolux medium` and how it is sized,
// checked against the L1 distance over the sphere of the table, as a renderer interpolates it (linear in
// mu between the values), written out here from its definition, E = 2 pi int |p_table - p| dmu, on a grid
// 8-16 times finer than the table, p being the same radii's phase summed here from the library's
// single-radius Mie (checked against mpmath and MIEV0 in tests/scatter/test_mie.cpp) and normalised here.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

#include "hydrolux/optics/media.hpp"
#include "hydrolux/scatter/amplitudes.hpp"
#include "hydrolux/scatter/mie.hpp"
#include "hydrolux/scatter/renderer_export.hpp"
#include "hydrolux/scatter/sphere.hpp"
#include "support/asan.hpp"

namespace hydrolux::scatter {
namespace {

constexpr double kPi = std::numbers::pi;

MediumJob fog_job(double radius_um, const std::string& distribution) {
  MediumJob job;
  job.radius_um = radius_um;
  job.size_distribution = distribution;
  job.medium = optics::find_medium("water");
  job.surrounding = optics::find_medium("air");
  job.numbers.number_per_cm3 = 100;
  return job;
}

// The phase per steradian of the quadrature's drops at 550 nm on `n` points uniform in mu (from -1 to 1),
// normalised here so that 2 pi times its trapezoid integral is 1.
std::vector<double> fine_phase(const RadiusQuadrature& q, int n) {
  const SphereProblem sp = sphere_problem(1.0, 550, *optics::find_medium("water"), *optics::find_medium("air"));
  const double k = sp.x * 1e6;  // per m
  std::vector<double> mu(static_cast<std::size_t>(n)), p(mu.size(), 0.0);
  for (int j = 0; j < n; ++j) mu[static_cast<std::size_t>(j)] = -1 + 2.0 * j / (n - 1);
  std::vector<Complex> s1(mu.size()), s2(mu.size());
  MieCoefficients c;
  for (std::size_t i = 0; i < q.size(); ++i) {
    mie_coefficients(sp.m, k * q.radius_m[i], c);
    mie_amplitudes(c, mu, s1, s2, 1);
    for (std::size_t j = 0; j < mu.size(); ++j) p[j] += q.weight[i] * (std::norm(s1[j]) + std::norm(s2[j]));
  }
  double integral = 0;
  const double h = 2.0 / (n - 1);
  for (std::size_t j = 0; j + 1 < mu.size(); ++j) integral += h * (p[j] + p[j + 1]) / 2;
  for (double& v : p) v /= 2 * kPi * integral;
  return p;
}

// L1 over the sphere, 2 pi int |f - p| dmu, of f linear in mu between the table's values (written here)
// against the fine phase (trapezoid rule on its points; (n_fine - 1) a multiple of the table's intervals).
double table_l1(const std::vector<double>& values, const std::vector<double>& fine) {
  const std::size_t intervals = values.size() - 1, per = (fine.size() - 1) / intervals;
  const double h = 2.0 / double(fine.size() - 1);
  double sum = 0, prev = std::abs(values[0] - fine[0]);
  for (std::size_t j = 1; j < fine.size(); ++j) {
    const std::size_t cell = std::min((j - 1) / per, intervals - 1);
    const double t = double(j - cell * per) / double(per);
    const double line = values[cell] * (1 - t) + values[cell + 1] * t;
    const double d = std::abs(line - fine[j]);
    sum += h * (prev + d) / 2;
    prev = d;
  }
  return 2 * kPi * sum;
}

// docs/renderer-export.md l. 133-135 and 147-149: without --values the table grows 257, 513, ... values
// until its error meets --max-error less the size average's own (for a count given, at most half of
// --max-error); with 24 radii (2 um gamma:0.2 fog, whose size average is far more than half off) the
// default 0.05 takes 2049 values and 0.01 takes 4097. Independently: the true L1 distance of each table
// (from its definition, against the same 24 radii's phase on 16 times 4096 intervals): the 2049-value
// table within its aim 0.025 but not within 0.01's aim 0.005, and the 4097-value table within 0.005.
// Measured: 0.0065 and 0.0016 (stated 0.0124 and 0.0031).
TEST(ClaimsRendererTable, TheTableAimsAtWhatTheSizeAverageLeaves) {
  if (HYDROLUX_TEST_ASAN) GTEST_SKIP() << "24 Mie solutions at 65,537 angles and two media: slow under ASan";
  MediumJob job = fog_job(2, "gamma:0.2");
  job.numbers.nodes = 24;
  MediumJob tight = job;
  tight.numbers.max_error = 0.01;
  const MediumPlan plan = plan_medium(job);
  const MediumOptics a = compute_medium(plan), b = run_medium_job(tight);
  ASSERT_TRUE(a.phase_size_l1 && b.phase_size_l1);
  EXPECT_GT(*a.phase_size_l1, 0.025);  // the size average takes its capped half of either target
  const std::vector<double> fine = fine_phase(plan.phase.quadrature, 16 * 4096 + 1);
  const double true_a = table_l1(a.phase.values, fine), true_b = table_l1(b.phase.values, fine);
  std::printf("0.05: %zu values, L1 %.4f (stated %.4f); 0.01: %zu values, L1 %.4f (stated %.4f)\n", a.phase.size(),
              true_a, a.phase.l1_error, b.phase.size(), true_b, b.phase.l1_error);
  EXPECT_EQ(a.phase.size(), 2049u);
  EXPECT_EQ(b.phase.size(), 4097u);
  EXPECT_LE(true_a, 0.05 - 0.025);
  EXPECT_GT(true_a, 0.01 - 0.005);  // 2049 values would not do for 0.01
  EXPECT_LE(true_b, 0.01 - 0.005);
}

// docs/renderer-export.md l. 137-141, the table's 2 um row: 512 radii chosen, 2049 values and the table's
// stated L1 error 0.011. The true distance of that table (its definition, against the 512 radii's phase
// on 8 times 2048 intervals) is below what is stated and above 0.4 times it (measured 0.006: the estimate
// is conservative, about 1.9 times).
TEST(ClaimsRendererTable, TheTwoMicronFogsTable) {
  if (HYDROLUX_TEST_ASAN) GTEST_SKIP() << "512 Mie solutions at 16,385 angles: slow under ASan";
  const MediumPlan plan = plan_medium(fog_job(2, "gamma:0.2"));
  const MediumOptics o = compute_medium(plan);
  ASSERT_TRUE(o.phase_size_l1);
  EXPECT_EQ(o.phase_radii, 512u);
  EXPECT_EQ(o.phase.size(), 2049u);
  EXPECT_NEAR(o.phase.l1_error, 0.011, 0.0005);
  // The radii chosen are the Gauss-Legendre radii in ln r of that count (what `--nodes 512` gives).
  MediumJob given = fog_job(2, "gamma:0.2");
  given.numbers.nodes = static_cast<int>(o.phase_radii);
  const double l1 = table_l1(o.phase.values, fine_phase(plan_medium(given).phase.quadrature, 8 * 2048 + 1));
  std::printf("2 um: %zu radii, %zu values, L1 %.4f (stated %.4f)\n", o.phase_radii, o.phase.size(), l1,
              o.phase.l1_error);
  EXPECT_LT(l1, o.phase.l1_error);
  EXPECT_GT(l1, 0.4 * o.phase.l1_error);
}

}  // namespace
}  // namespace hydrolux::scatter
