// Rendering a drop from an environment: the camera's geometry, anti-aliased coverage, the photometry
// of eq. 19 on a uniform environment, dispersion, and the environments themselves.
#include <gtest/gtest.h>

#include <cmath>

#include "hydrolux/core/error.hpp"
#include "hydrolux/core/math.hpp"
#include "hydrolux/drop/model.hpp"
#include "hydrolux/drop/render.hpp"
#include "hydrolux/drop/trace.hpp"
#include "hydrolux/optics/fresnel.hpp"
#include "hydrolux/optics/media.hpp"
#include "hydrolux/scene/environment.hpp"

namespace hydrolux::drop {
namespace {

struct Uniform final : scene::Environment {
  scene::Rgb radiance(const Vec3&) const override { return {1, 1, 1}; }
};

// Radiance that depends only on the polar angle from +z (the scene straight behind the drop).
struct PolarRamp final : scene::Environment {
  scene::Rgb radiance(const Vec3& d) const override {
    const double t = std::acos(std::clamp(d.z, -1.0, 1.0)) / kPi<>;
    return {t, t, t};
  }
};

// The sum of alpha over the image (the drop's coverage in pixels) over the disk's area pi r^2.
double coverage_over_disk(const Image& img, const DropCamera& c) {
  double area = 0;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) area += img.at(x, y, 3);
  return area / (kPi<> * sqr(c.drop_radius_px()));
}

DropCamera small_camera() {
  DropCamera c;
  c.radius_m = 1e-3;
  c.distance_m = 2.0;
  c.frame_m = 3e-3;
  c.width = c.height = 96;
  return c;
}

// The camera's ray and projection are inverse maps; pixel centres are at half-integers; the image
// centre looks straight down the axis.
TEST(DropCamera, RayAndProjectionInvert) {
  const auto c = small_camera();
  for (double px : {0.0, 10.5, 47.25, 95.9})
    for (double py : {0.3, 48.0, 80.75}) {
      const Ray r = c.ray(px, py);
      const auto back = c.project(r.origin + 3.7 * r.direction);
      EXPECT_NEAR(back[0], px, 1e-9);
      EXPECT_NEAR(back[1], py, 1e-9);
    }
  const Ray axis = c.ray(48, 48);
  EXPECT_NEAR(axis.direction.z, 1.0, 1e-15);
  // Image y grows downwards, world y upwards.
  EXPECT_GT(c.ray(48, 10).direction.y, 0);
  EXPECT_GT(c.ray(80, 48).direction.x, 0);
}

// The silhouette: a ray through the drop's apparent rim grazes the sphere (the discriminant of the
// ray-sphere equation vanishes), one a little inside hits and one a little outside misses; also
// for a 1 mm drop kilometres away, where the textbook discriminant b^2 - c cancels to noise.
TEST(DropCamera, ApparentRadiusIsTheSilhouette) {
  for (double d : {0.005, 0.05, 2.0, 1e3, 1e4}) {
    auto c = small_camera();
    c.distance_m = d;
    c.frame_m = 4 * c.radius_m;
    const auto centre = c.drop_center_px();
    const double r = c.drop_radius_px();
    const SphereSurface sphere({0, 0, d}, c.radius_m);
    const auto inside = sphere.intersect(c.ray(centre[0] + r * (1 - 1e-6), centre[1]), 0.0);
    ASSERT_TRUE(inside.has_value()) << d;
    EXPECT_NEAR(glm::length(inside->normal), 1.0, 1e-12);
    EXPECT_FALSE(sphere.intersect(c.ray(centre[0] + r * (1 + 1e-6), centre[1]), 0.0).has_value()) << d;
  }
}

// A drop far away renders (no grazing normal facing away from the camera) with the right coverage:
// the disk-area check of the test below, at 10 km.
TEST(Render, FarAwayDrop) {
  auto c = small_camera();
  c.distance_m = 1e4;
  RenderOptions opt;
  opt.samples_per_axis = 8;
  opt.background = false;
  const Image img = render_model(c, Uniform{}, {1.333, 1.333, 1.333}, opt);
  EXPECT_NEAR(coverage_over_disk(img, c), 1.0, 2e-3);
}

// Anti-aliasing: with the background off, alpha is the fraction of each pixel covered by the drop,
// so it sums to the disk's area pi r^2 in pixels. 8 x 8 jittered samples per pixel estimate each rim
// pixel's coverage to about +-1/64 with independent errors over the ~2 pi r rim pixels: the sum's
// error is ~ sqrt(2 pi r) / 64 / (pi r^2) ~ 1e-4 relative for r = 32 px, so 2e-3 is safe. The area
// alone would also pass for a one-sample (aliased) render, whose coverage is unbiased too; the
// per-pixel check is the one that needs real anti-aliasing: a rim pixel's alpha is its covered
// fraction (to 0.08: 1/64 sampling plus the rim's curvature across one pixel, ~1/(8 r)), where an
// aliased render gives 0 or 1.
TEST(Render, CoverageIsTheDiskArea) {
  const auto c = small_camera();
  RenderOptions opt;
  opt.samples_per_axis = 8;
  opt.background = false;
  const Image img = render_model(c, Uniform{}, {1.333, 1.333, 1.333}, opt);
  EXPECT_NEAR(coverage_over_disk(img, c), 1.0, 2e-3);
  const double r = c.drop_radius_px();
  // A pixel centred on the rim's right edge is about half covered (the rim's curvature across one
  // pixel is ~1/(8 r) of a pixel).
  const int xr = int(std::floor(c.drop_center_px()[0] + r)), yc = 48;
  const double frac_left = c.drop_center_px()[0] + r - xr;  // covered part of pixel xr along x
  EXPECT_NEAR(img.at(xr, yc, 3), frac_left, 0.08);
}

// Eq. 19 on a uniform environment Le = 1: every pixel inside the drop shows
// R + S + P1 + P2 = (1 - k)^2 + k + k (1 - k)^2 + k^2 (1 - k)^2 for its own incidence angle; at the
// image centre i ~ 0, k = ((mu - 1) / (mu + 1))^2. The background is 1.
TEST(Render, UniformEnvironmentGivesTheModelsTransfer) {
  const auto c = small_camera();
  RenderOptions opt;
  opt.samples_per_axis = 1;
  const double mu = 1.333;
  const Image img = render_model(c, Uniform{}, {mu, mu, mu}, opt);
  const double k = sqr((mu - 1) / (mu + 1));
  const double expected = sqr(1 - k) + k + k * sqr(1 - k) + k * k * sqr(1 - k);
  // Pixel (48, 48) has its centre exactly on the axis; with one sample per axis it is sampled there
  // up to the jitter of half a pixel: i < 0.5 px / 32 px, where k changes by < 1e-5 relative.
  EXPECT_NEAR(img.at(48, 48, 0), expected, 1e-5);
  EXPECT_NEAR(img.at(0, 0, 1), 1.0, 1e-7);
  EXPECT_FLOAT_EQ(img.at(0, 0, 3), 1.f);
  // Energy: the model drops the paths beyond two internal reflections, so it is below 1 but by no
  // more than their share, sum_{N>=3} k^N (1 - k)^2 < k^3 / (1 - k) (0.02% at the centre).
  EXPECT_LT(expected, 1.0);
  EXPECT_GT(expected, 1.0 - k * k * k / (1 - k) - 1e-12);
}

// Dispersion: red is refracted less than blue, so at a pixel off the centre the red channel's
// refracted ray is deflected less and sees a smaller polar angle from the axis than the blue one. On
// a radiance that grows with that angle, red < blue at the same pixel.
TEST(Render, DispersionSeparatesChannels) {
  const auto c = small_camera();
  RenderOptions opt;
  opt.samples_per_axis = 2;
  opt.n_internal = 0;
  const Image img = render_model(c, PolarRamp{}, {1.331, 1.335, 1.340}, opt);
  const Image grey = render_model(c, PolarRamp{}, {1.335, 1.335, 1.335}, opt);
  const int x = 48 + int(0.6 * c.drop_radius_px()), y = 48;
  EXPECT_LT(img.at(x, y, 0), img.at(x, y, 1));
  EXPECT_LT(img.at(x, y, 1), img.at(x, y, 2));
  EXPECT_FLOAT_EQ(grey.at(x, y, 0), grey.at(x, y, 2));
  EXPECT_FLOAT_EQ(img.at(x, y, 1), grey.at(x, y, 1));  // the same index in green
}

TEST(Render, RejectsBadInput) {
  auto c = small_camera();
  c.distance_m = c.radius_m;  // camera inside the drop
  EXPECT_THROW(render_model(c, Uniform{}, {1.333, 1.333, 1.333}, {}), DomainError);
  c = small_camera();
  EXPECT_THROW(render_model(c, Uniform{}, {1.333, 0.9, 1.333}, {}), DomainError);
  RenderOptions opt;
  opt.samples_per_axis = 0;
  EXPECT_THROW(render_model(c, Uniform{}, {1.333, 1.333, 1.333}, opt), DomainError);
}

// The equirectangular convention: (u, v) <-> direction invert; the centre column looks along +z,
// u grows towards +x, row 0 is the zenith.
TEST(Environment, EquirectConvention) {
  for (double u : {0.01, 0.25, 0.5, 0.8})
    for (double v : {0.02, 0.3, 0.5, 0.97}) {
      const auto uv = scene::equirect_uv(scene::equirect_direction(u, v));
      EXPECT_NEAR(uv.u, u, 1e-12);
      EXPECT_NEAR(uv.v, v, 1e-12);
    }
  const Vec3 ahead = scene::equirect_direction(0.5, 0.5);
  EXPECT_NEAR(ahead.z, 1, 1e-15);
  EXPECT_NEAR(scene::equirect_direction(0.75, 0.5).x, 1, 1e-15);
  EXPECT_NEAR(scene::equirect_direction(0.3, 0.0).y, 1, 1e-15);
}

// A smooth environment baked to an equirectangular map and looked up again agrees with the analytic
// one to the bilinear interpolation error, ~ (h^2 / 8) |f''| with h the pixel size in radians:
// for f = (1 + d.x + d.y^2) / 3 on a 512 x 256 map, h = 0.0123 and |f''| <= 2, so < 4e-5 (plus the
// bake's own 2 x 2 box filter, of the same order).
TEST(Environment, BakedMapMatchesTheFunction) {
  struct Smooth final : scene::Environment {
    scene::Rgb radiance(const Vec3& d) const override {
      const double f = (1 + d.x + d.y * d.y) / 3;
      return {f, 1 - f, 0.5};
    }
  } smooth;
  const scene::EquirectEnvironment map(scene::bake_equirect(smooth, 512, 2));
  double worst = 0;
  for (int k = 0; k < 2000; ++k) {
    const double u = std::fmod(k * 0.6180339887, 1.0), v = 0.05 + 0.9 * std::fmod(k * 0.7548776662, 1.0);
    const Vec3 d = scene::equirect_direction(u, v);
    worst = std::max(worst, std::abs(map.radiance(d)[0] - smooth.radiance(d)[0]));
  }
  EXPECT_LT(worst, 1e-4);
  EXPECT_THROW(scene::EquirectEnvironment(Image(10, 10, 3)), IoError);
  EXPECT_THROW(scene::EquirectEnvironment(Image(20, 10, 1)), IoError);
}

// The builtin environment is finite and non-negative everywhere, has its sun where documented
// (35 degrees up, 40 degrees left of straight ahead) and is brighter in the sky than on the ground.
TEST(Environment, BuiltinSkyIsSane) {
  const scene::BuiltinSky sky;
  const Image map = scene::bake_equirect(sky, 256, 1);
  for (float v : map.pixels) {
    ASSERT_TRUE(std::isfinite(v));
    ASSERT_GE(v, 0.f);
  }
  const double e = deg_to_rad(35.0), l = deg_to_rad(-40.0);
  const Vec3 sun{std::cos(e) * std::sin(l), std::sin(e), std::cos(e) * std::cos(l)};
  EXPECT_GT(sky.radiance(sun)[0], 1000);
  EXPECT_LT(sky.radiance(glm::normalize(sun + Vec3{0, 0.02, 0}))[0], 10);
  const Vec3 up_ahead = glm::normalize(Vec3{0.3, 0.8, 0.5}), down = glm::normalize(Vec3{0.3, -0.8, 0.5});
  EXPECT_GT(sky.radiance(up_ahead)[2], sky.radiance(down)[2]);
}

}  // namespace
}  // namespace hydrolux::drop

namespace hydrolux::drop {
namespace {

// The dispersive render's channel wavelengths run red to blue, so water's index rises from the red
// channel to the blue one (normal dispersion: 1.3320, 1.3334, 1.3365 at 20 C relative to vacuum,
// IAPWS R9-97), and the red channel's rays bend least.
TEST(Render, ChannelWavelengthsRunRedToBlue) {
  EXPECT_GT(kChannelWavelengthsNm[0], 590.0);  // red: beyond orange
  EXPECT_GT(kChannelWavelengthsNm[1], 500.0);  // green
  EXPECT_LT(kChannelWavelengthsNm[1], 570.0);
  EXPECT_LT(kChannelWavelengthsNm[2], 490.0);  // blue
  const auto water = optics::find_medium("water");
  EXPECT_LT(water->n(kChannelWavelengthsNm[0]), water->n(kChannelWavelengthsNm[1]));
  EXPECT_LT(water->n(kChannelWavelengthsNm[1]), water->n(kChannelWavelengthsNm[2]));
}

// Thin-lens defocus of the background: a 50 mm f/2.8 lens focused at 2 m spreads a point at
// infinity over a disk of angular radius A / (2 D) = (50 mm / 2.8) / 4 m = 4.46 mrad. Check against
// the sensor-side derivation: blur diameter A f / (D - f) on the sensor at v = f D / (D - f).
TEST(Render, DefocusBlurOfTheBackground) {
  const double f = 0.05, n = 2.8, d = 2.0;
  EXPECT_NEAR(defocus_blur_radius_rad(f, n, d), 0.05 / 2.8 / 4.0, 1e-15);
  const double a = f / n, v = f * d / (d - f), blur_diameter = a * f / (d - f);
  EXPECT_NEAR(defocus_blur_radius_rad(f, n, d), 0.5 * blur_diameter / v, 1e-15);
  EXPECT_THROW((void)defocus_blur_radius_rad(f, n, 0.04), DomainError);  // focused inside the focal length
}

}  // namespace
}  // namespace hydrolux::drop
