// Snell's law: vector and scalar forms, total internal reflection, critical and Brewster angles.
#include <gtest/gtest.h>

#include "hydrolux/core/random.hpp"
#include "hydrolux/optics/snell.hpp"
#include "support/stats.hpp"

namespace hydrolux::optics {
namespace {

TEST(Snell, ReflectionKeepsAngleAndPlane) {
  Rng rng(1);
  for (int i = 0; i < 1000; ++i) {
    const Vec3 n = test::uniform_sphere(rng), wo = test::uniform_sphere(rng);
    const Vec3 wr = reflect(wo, n);
    EXPECT_NEAR(glm::length(wr), 1.0, 1e-14);
    EXPECT_NEAR(glm::dot(wr, n), glm::dot(wo, n), 1e-14);              // same angle, same side
    EXPECT_NEAR(glm::dot(glm::cross(wo, n), wr), 0.0, 1e-14);           // plane of incidence
  }
}

// n_i sin(theta_i) = n_t sin(theta_t), the transmitted ray on the far side, in the plane of
// incidence, unit length; for incidence from either side.
TEST(Snell, VectorFormObeysSnellsLawFromBothSides) {
  Rng rng(2);
  for (double eta : {1.333, 1.5, 1 / 1.333, 2.4}) {
    for (int i = 0; i < 2000; ++i) {
      const Vec3 n = test::uniform_sphere(rng), wi = test::uniform_sphere(rng);
      const double cos_i = glm::dot(wi, n);
      const double n_i = cos_i >= 0 ? 1.0 : eta, n_t = cos_i >= 0 ? eta : 1.0;
      const double sin_i = std::sqrt(std::max(0.0, 1 - cos_i * cos_i));
      const auto r = refract(wi, n, eta);
      if (n_i * sin_i >= n_t) {  // beyond the critical angle: TIR is reported, not hidden
        EXPECT_FALSE(r.has_value());
        continue;
      }
      ASSERT_TRUE(r.has_value());
      EXPECT_NEAR(glm::length(r->wt), 1.0, 1e-13);
      EXPECT_LT(glm::dot(r->wt, n) * cos_i, 0.0);  // far side
      const double cos_t = std::abs(glm::dot(r->wt, n));
      EXPECT_NEAR(cos_t, r->cos_t, 1e-13);
      EXPECT_NEAR(n_i * sin_i, n_t * std::sqrt(std::max(0.0, 1 - cos_t * cos_t)), 1e-12);
      EXPECT_NEAR(glm::dot(glm::cross(wi, n), r->wt), 0.0, 1e-13);
      EXPECT_DOUBLE_EQ(r->eta, n_t / n_i);
    }
  }
}

TEST(Snell, RefractionIsReversible) {
  Rng rng(3);
  for (int i = 0; i < 1000; ++i) {
    const Vec3 n{0, 0, 1}, wi = test::uniform_sphere(rng);
    const auto r = refract(wi, n, 1.333);
    if (!r) continue;
    const auto back = refract(r->wt, n, 1.333);
    ASSERT_TRUE(back.has_value());
    EXPECT_NEAR(glm::length(back->wt - wi), 0.0, 1e-12);
  }
}

// The critical angle of water into air is 48.6 degrees (e.g. pbrt-v4 section 9.3; Hecht, Optics,
// section 4.7): TIR just above it, transmission just below.
TEST(Snell, TotalInternalReflectionPastCriticalAngleOfWater) {
  const double crit = *critical_angle(1.333, 1.0);
  EXPECT_NEAR(rad_to_deg(crit), 48.6, 0.01);
  EXPECT_FALSE(critical_angle(1.0, 1.333).has_value());
  const Vec3 n{0, 0, 1};
  for (double deg : {48.0, 48.6}) {
    const double t = deg_to_rad(deg);
    EXPECT_TRUE(refract(Vec3{std::sin(t), 0, -std::cos(t)}, n, 1.333).has_value()) << deg;
    EXPECT_TRUE(refraction_angle(t, 1.333, 1.0).has_value());
  }
  for (double deg : {48.62, 60.0, 89.9}) {
    const double t = deg_to_rad(deg);
    EXPECT_FALSE(refract(Vec3{std::sin(t), 0, -std::cos(t)}, n, 1.333).has_value()) << deg;
    EXPECT_FALSE(refraction_angle(t, 1.333, 1.0).has_value());
  }
}

// Brewster's angle: 56.31 deg for n = 1.5 and 53.1 deg for water (Hecht, Optics, section 4.6.3);
// there the reflected and refracted rays are perpendicular: theta_B + theta_t = 90 deg.
TEST(Snell, BrewsterAngle) {
  EXPECT_NEAR(rad_to_deg(brewster_angle(1.0, 1.5)), 56.31, 0.005);
  EXPECT_NEAR(rad_to_deg(brewster_angle(1.0, 1.333)), 53.12, 0.005);
  for (double n : {1.2, 1.333, 1.5, 2.4}) {
    const double tb = brewster_angle(1.0, n);
    EXPECT_NEAR(tb + *refraction_angle(tb, 1.0, n), kPi<> / 2, 1e-14);
  }
}

}  // namespace
}  // namespace hydrolux::optics
