// Rain drop physics: terminal velocity, the paper's fit against Gunn & Kinzer's measurements.
#include <gtest/gtest.h>

#include "hydrolux/core/embedded_data.hpp"
#include "hydrolux/core/error.hpp"
#include "hydrolux/core/table.hpp"
#include "hydrolux/drop/physics.hpp"

namespace hydrolux::drop {
namespace {

// Gunn & Kinzer (1949): at their tabulated drops the interpolation returns the measurement, e.g.
// 2.0 mm diameter -> 6.49 m/s and 5.8 mm -> 9.17 m/s; between them it is linear in diameter.
TEST(TerminalVelocity, GunnKinzerTable) {
  const auto t = parse_table(embedded_file("drop/gunn_kinzer_1949.csv"), "gk");
  const auto d = t.column("diameter_mm"), v = t.column("velocity_mps");
  ASSERT_GE(t.rows(), 30u);
  for (std::size_t i = 0; i < t.rows(); ++i) EXPECT_DOUBLE_EQ(terminal_velocity_gunn_kinzer_mps(d[i] * 0.5e-3), v[i]);
  EXPECT_DOUBLE_EQ(terminal_velocity_gunn_kinzer_mps(1.0e-3), 6.49);
  EXPECT_DOUBLE_EQ(terminal_velocity_gunn_kinzer_mps(2.9e-3), 9.17);
  EXPECT_NEAR(terminal_velocity_gunn_kinzer_mps(1.05e-3), (6.49 + 6.90) / 2, 1e-12);
  // Terminal velocity grows with size and saturates near 9.2 m/s (drops flatten and break up).
  for (std::size_t i = 1; i < t.rows(); ++i) EXPECT_GT(v[i], v[i - 1]);
  const auto range = gunn_kinzer_radius_range_m();
  EXPECT_THROW((void)terminal_velocity_gunn_kinzer_mps(range[1] * 1.01), DomainError);
  EXPECT_THROW((void)terminal_velocity_gunn_kinzer_mps(range[0] * 0.99), DomainError);
}

// The paper's fit v = 200 sqrt(a): 6.32 m/s at a = 1 mm. Where it holds, as documented in the
// header: within 11% of the measurements for radii 0.5-2.5 mm, within 6% for 0.6-2.2 mm, and not
// for small drops (+54% at 0.25 mm) or the largest (+17% at 2.9 mm).
TEST(TerminalVelocity, PapersFitAndWhereItHolds) {
  EXPECT_NEAR(terminal_velocity_fit_mps(1e-3), 6.3246, 1e-4);
  const auto rel = [](double a) { return terminal_velocity_fit_mps(a) / terminal_velocity_gunn_kinzer_mps(a) - 1; };
  for (double a = 0.5e-3; a <= 2.5e-3 + 1e-12; a += 0.05e-3) EXPECT_LT(std::abs(rel(a)), 0.11) << a;
  for (double a = 0.6e-3; a <= 2.2e-3 + 1e-12; a += 0.05e-3) EXPECT_LT(std::abs(rel(a)), 0.06) << a;
  EXPECT_NEAR(rel(0.25e-3), 0.535, 0.01);
  EXPECT_NEAR(rel(2.9e-3), 0.175, 0.01);
  EXPECT_THROW((void)terminal_velocity_fit_mps(-1.0), DomainError);
}

}  // namespace
}  // namespace hydrolux::drop
