// The model's picture of a drop against the exact tracer's (the ground truth of issue #4), on the
// builtin environment, by zones of the drop's image radius rho = sin(i).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "hydrolux/core/math.hpp"
#include "hydrolux/drop/render.hpp"
#include "hydrolux/drop/trace.hpp"
#include "hydrolux/optics/fresnel.hpp"
#include "hydrolux/scene/environment.hpp"

namespace hydrolux::drop {
namespace {

struct Uniform final : scene::Environment {
  scene::Rgb radiance(const Vec3&) const override { return {1, 1, 1}; }
};

DropCamera camera() {
  DropCamera c;  // a 1 mm drop 2 m away, filling most of a 128 px image
  c.frame_m = 2.2e-3;
  c.width = c.height = 128;
  return c;
}

// The model against the exact tracer for a sphere, on the builtin environment (sky, road,
// landmarks). For a sphere and a scene at infinity the model's directions are exact (tested in
// test_model.cpp against a vector trace), so what separates the pictures is photometric:
// - the model multiplies unpolarised reflectances, k^N (1 - k)^2, where the exact transfer is
//   (R_s^N T_s^2 + R_p^N T_p^2) / 2: the refraction weight is low by ((T_s - T_p) / 2)^2, 9e-5 at
//   rho 0.5, 1.5e-3 at 0.8, 4.5e-3 at 0.9 and 1.1e-2 at 0.99 (test_trace.cpp);
// - it stops at N = 2 internal reflections, which at small i carry < k^3 ~ 1e-5 of the light.
// Measured (128 px, 3 x 3 samples, printed by the test): 0.147% RMS of the mean radiance for
// rho <= 0.9, as the polarisation deficit averaged over the zone predicts, and 0.86% on the rim
// (0.9 < rho < 1). Bounds: 0.3% and 2%, twice the measured values. With the sun's disk (radiance
// 2000, smaller than a pixel where the drop images it) the rim's figure is 2.2%: it depends on
// whether jittered samples land on the sun's sub-pixel image, so it is reported, bounded only
// loosely (5%), and the pixel-by-pixel bounds use the scene without the disk. A model with its
// index 1% off fails the inner bound by more than tenfold (its mapping moves the road's edges).
ZoneDifference model_vs_exact(bool sun_disk, double mu_scale = 1) {
  const auto cam = camera();
  RenderOptions opt;
  opt.samples_per_axis = 3;
  opt.background = false;
  const double mu = 1.333;
  const scene::BuiltinSky sky(sun_disk);
  const auto sphere = make_drop_surface(cam, DropShapeKind::sphere);
  const Image exact = render_exact(cam, sky, {mu, mu, mu}, *sphere, opt, TraceOptions{});
  const double m = mu * mu_scale;
  const Image model = render_model(cam, sky, {m, m, m}, opt);
  return compare_by_zone(model, exact, cam);
}

TEST(ModelVsExact, BuiltinEnvironmentByZone) {
  const auto err = model_vs_exact(false);
  const auto sun = model_vs_exact(true);
  std::printf("model vs exact, RMS / mean radiance: no sun disk: inner %.4g%%, rim %.4g%%; "
              "with the sun disk: inner %.4g%%, rim %.4g%%\n",
              100 * err.inner, 100 * err.rim, 100 * sun.inner, 100 * sun.rim);
  EXPECT_LT(err.inner, 3e-3);
  EXPECT_LT(err.rim, 0.02);
  EXPECT_LT(sun.inner, 3e-3);
  EXPECT_LT(sun.rim, 0.05);
  EXPECT_GT(model_vs_exact(false, 1.01).inner, 10 * 3e-3);
}

// Energy at the image level: in a uniform environment (Le = 1) every exact pixel inside the drop
// is 1 minus the light still inside after 8 interactions (lossless drop); the model's pixels are
// R + S + P1 + P2 < 1 (eq. 19), short of 1 by the paths it omits.
TEST(ModelVsExact, UniformEnvironmentEnergy) {
  auto cam = camera();
  cam.width = cam.height = 48;
  RenderOptions opt;
  opt.samples_per_axis = 1;
  opt.background = false;
  const auto sphere = make_drop_surface(cam, DropShapeKind::sphere);
  const Image exact = render_exact(cam, Uniform{}, {1.333, 1.333, 1.333}, *sphere, opt, TraceOptions{});
  const Image model = render_model(cam, Uniform{}, {1.333, 1.333, 1.333}, opt);
  const auto c = cam.drop_center_px();
  const double r = cam.drop_radius_px();
  for (int y = 0; y < cam.height; ++y)
    for (int x = 0; x < cam.width; ++x) {
      if (std::hypot(x + 0.5 - c[0], y + 0.5 - c[1]) > r - 1.5) continue;
      // After 8 interactions the light left inside is at most R^6 of the internal ray's power,
      // < 0.02 even at rho = 0.95 (R ~ 0.5 there); at the centre ~ 1e-11.
      EXPECT_GT(exact.at(x, y, 0), 0.98f);
      EXPECT_LE(exact.at(x, y, 0), 1.0f + 1e-6f);
      EXPECT_LE(model.at(x, y, 0), exact.at(x, y, 0) + 1e-6f);
    }
}

}  // namespace
}  // namespace hydrolux::drop
