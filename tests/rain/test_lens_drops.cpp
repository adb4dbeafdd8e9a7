// Drops on the lens or windshield (rain/lens_drops.hpp; docs/lens-drops.md): a hemispherical cap
// against an independent exact ray-sphere computation (the exact tracer's SphereSurface and
// optics::refract) and a closed form; a small cap as a plano-convex lens (focal length R / (n - 1),
// Hecht, Optics, 5th ed., eq. 5.16 with R1 = infinity; the principal plane of a plano-convex lens
// t / n inside its flat face, Hecht sec. 6.1), inverting the scene; the thin-lens circle of
// confusion (Potmesil & Chakravarty 1981, eq. 1); flux conservation of the disk kernel;
// determinism; the coverage mask.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <string>

#include "hydrolux/core/error.hpp"
#include "hydrolux/drop/trace.hpp"
#include "hydrolux/optics/fresnel.hpp"
#include "hydrolux/optics/snell.hpp"
#include "hydrolux/rain/lens_drops.hpp"

namespace hydrolux::rain {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kWater = 1.333, kGlass = 1.52;

// Contact angle 90 degrees: the cap is a hemisphere whose centre lies on the glass. A camera ray
// through the footprint's centre travels radially in the water and leaves at normal incidence:
// its exit angle to the glass normal is asin(sin(alpha) / n), and its transmittance the two plane
// faces' at alpha times (1 - ((n - 1) / (n + 1))^2).
TEST(LensDrops, HemisphereThroughItsCentreMatchesTheClosedForm) {
  const double d = 0.1, a = 2e-3;
  for (double alpha_deg : {0.0, 5.0, 20.0, 40.0}) {
    const double alpha = alpha_deg * kPi / 180;
    // The cap's centre on the glass where the ray meets it.
    const LensCap cap{d * std::tan(alpha), 0, a, kPi / 2};
    const CapRay r = trace_cap(cap, d, Vec3(std::sin(alpha), 0, std::cos(alpha)), kWater, kGlass);
    ASSERT_TRUE(r.through);
    ASSERT_FALSE(r.tir);
    const double beta = std::atan2(r.direction.x, r.direction.z);
    EXPECT_NEAR(beta, std::asin(std::sin(alpha) / kWater), 1e-12) << alpha_deg;
    EXPECT_NEAR(glm::length(r.exit - Vec3(cap.x, 0, d)), a, 1e-15);
    const auto f1 = optics::fresnel_dielectric(std::cos(alpha), 1.0, kGlass);
    const auto f2 = optics::fresnel_dielectric(f1.cos_t, kGlass, kWater);
    const double normal = 1 - std::pow((kWater - 1) / (kWater + 1), 2);
    const double plane = (f1.T_s * f2.T_s + f1.T_p * f2.T_p) / 2;
    EXPECT_NEAR(r.transmittance, plane * normal, 1e-12) << alpha_deg;
  }
}

// Any ray through a hemisphere, against the exact tracer's pieces: the far hit of
// drop::SphereSurface (Haines et al.'s stable roots) from the entry point and optics::refract there.
TEST(LensDrops, HemisphereMatchesTheExactTracersSphere) {
  const double d = 0.05, a = 1.5e-3;
  const LensCap cap{0.004, -0.002, a, kPi / 2};
  const drop::SphereSurface sphere(Vec3(cap.x, cap.y, d), a);
  int checked = 0, tir = 0;
  for (int i = -20; i <= 20; ++i)
    for (int j = -20; j <= 20; ++j) {
      const Vec3 onglass(cap.x + a * i / 20.5, cap.y + a * j / 20.5, d);
      const Vec3 u = glm::normalize(onglass);
      const CapRay r = trace_cap(cap, d, u, kWater, kGlass);
      if (std::hypot(onglass.x - cap.x, onglass.y - cap.y) >= a) {
        EXPECT_FALSE(r.through);
        continue;
      }
      ASSERT_TRUE(r.through);
      const Vec3 w = optics::refract(-u, Vec3(0, 0, -1), kWater)->wt;
      const auto hit = sphere.intersect(drop::Ray{onglass, w}, 0.0);
      ASSERT_TRUE(hit);
      EXPECT_LT(glm::length(hit->point - r.exit), 1e-15);
      const auto out = optics::refract(-w, hit->normal, kWater);
      if (!out) {
        EXPECT_TRUE(r.tir);
        ++tir;
        continue;
      }
      EXPECT_LT(glm::length(glm::normalize(out->wt) - r.direction), 1e-13);
      ++checked;
    }
  // Rays near the rim meet the sphere beyond the critical angle: nearly along the axis, those
  // entering farther than a / n from it, a fraction 1 - 1 / n^2 of the footprint.
  EXPECT_GT(checked, 600);
  EXPECT_NEAR(double(tir) / (tir + checked), 1 - 1 / (kWater * kWater), 0.03);
}

// A small, flat cap is a plano-convex lens of focal length f = R / (n - 1), R = a / sin(theta_c).
// A camera at distance d from its flat face sees, near the axis, the exit angle
// beta = alpha (1 - (d + h / n) / f): the principal plane of the plano-convex lens lies h / n
// inside the flat face (h the cap's height). With d >> f the factor is negative: the drop shows
// the scene behind it inverted and minified in angle, as a lens does.
TEST(LensDrops, SmallCapIsAPlanoConvexLens) {
  const double d = 0.1, a = 0.5e-3, theta = 20 * kPi / 180;
  const LensCap cap{0, 0, a, theta};
  const double R = cap.sphere_radius(), h = cap.height(), f = R / (kWater - 1);
  const double expected = 1 - (d + h / kWater) / f;
  // Paraxial rays: heights on the glass up to a / 50.
  for (double y : {2e-6, 5e-6, 1e-5}) {
    const double alpha = y / d;
    const CapRay r = trace_cap(cap, d, Vec3(std::tan(alpha), 0, 1), kWater, kGlass);
    ASSERT_TRUE(r.through);
    const double beta = std::atan2(r.direction.x, r.direction.z);
    // Measured: 1.3e-6, 8.1e-6, 3.2e-5 relative (falling as y^2); leaving out the principal plane's
    // h / n would be 7e-4 off.
    EXPECT_NEAR(beta / alpha, expected, 5e-5 * std::abs(expected)) << y;
  }
  EXPECT_LT(expected, -15);  // inverted: f = 4.4 mm against d = 100 mm
}

// The same in a rendered picture: over a horizontal ramp, the drop's pixels go the other way.
TEST(LensDrops, RenderedCapInvertsTheScene) {
  LensDropSettings s;
  s.f_number = 0;  // pinhole: the sharp layer
  s.contact_angle_deg = 30;
  const int W = 320, H = 240;
  Image ramp(W, H, 1);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) ramp.at(x, y, 0) = float(x) / W;
  const LensCap cap{0, 0, 4e-3, 30 * kPi / 180};
  const auto out = render_lens_drops(ramp, s, std::span<const LensCap>(&cap, 1));
  const double fpx = s.focal_mm / s.sensor_width_mm * W, rpx = fpx * cap.radius / s.glass_distance_m;
  ASSERT_GT(rpx, 8);
  // Along the row through the centre, inside 0.5 of the footprint's radius: values fall with x.
  const int y = H / 2, x0 = int(W / 2 - 0.5 * rpx), x1 = int(W / 2 + 0.5 * rpx);
  for (int x = x0; x < x1; ++x) EXPECT_GT(out.image.at(x, y, 0), out.image.at(x + 1, y, 0)) << x;
  // |1 - d / f| = 3.2 (f = 24 mm): the 12 pixels span about 39 of the scene, 0.12 of the ramp.
  EXPECT_GT(out.image.at(x0, y, 0) - out.image.at(x1, y, 0), 0.08);
}

TEST(LensDrops, CircleOfConfusionKnownValue) {
  // f = 50 mm at f/2 focused at 10 m, a point at 1 m: (25 mm)(50 / 9950)(9 / 1) = 1.13065 mm.
  EXPECT_NEAR(circle_of_confusion_mm(50, 2, 10, 1), 25.0 * 50 / 9950 * 9, 1e-12);
  EXPECT_EQ(circle_of_confusion_mm(50, 2, 10, 10), 0);
  EXPECT_EQ(circle_of_confusion_mm(50, 0, 10, 1), 0);
}

TEST(LensDrops, DiskBlurConservesFluxAndHasTheDisksSpread) {
  const int W = 96, H = 80;
  Image img(W, H, 2);
  std::uint64_t state = 12345;
  double sum0 = 0, sum1 = 0;
  for (int y = 20; y < H - 20; ++y)
    for (int x = 20; x < W - 20; ++x) {
      state = state * 6364136223846793005ull + 1442695040888963407ull;
      img.at(x, y, 0) = float((state >> 40) % 1000) / 1000.f;
      img.at(x, y, 1) = 1.f;
      sum0 += img.at(x, y, 0);
      sum1 += 1;
    }
  for (double r : {0.7, 3.0, 7.3, 12.5}) {
    const Image b = disk_blur(img, r);
    double s0 = 0, s1 = 0;
    for (int y = 0; y < H; ++y)
      for (int x = 0; x < W; ++x) {
        s0 += b.at(x, y, 0);
        s1 += b.at(x, y, 1);
      }
    EXPECT_NEAR(s0 / sum0, 1, 1e-6) << r;  // float pixels: ~1e-7 each
    EXPECT_NEAR(s1 / sum1, 1, 1e-6) << r;
  }
  // A point's spread: the disk's mean squared distance r^2 / 2 (plus the pixel's own 1/6).
  Image point(81, 81, 1);
  point.at(40, 40, 0) = 1;
  const double r = 15;
  const Image b = disk_blur(point, r);
  double m2 = 0, total = 0, outside = 0;
  for (int y = 0; y < 81; ++y)
    for (int x = 0; x < 81; ++x) {
      const double w = b.at(x, y, 0), q = double(x - 40) * (x - 40) + double(y - 40) * (y - 40);
      m2 += w * q;
      total += w;
      if (std::sqrt(q) > r + 1.5) outside += w;
    }
  EXPECT_NEAR(total, 1, 1e-6);
  EXPECT_EQ(outside, 0);
  EXPECT_NEAR(m2 / (r * r / 2), 1, 0.01);
  // Flat input stays flat (the borders repeat the edge).
  Image flat(30, 20, 1);
  for (auto& v : flat.pixels) v = 0.25f;
  for (float v : disk_blur(flat, 6).pixels) EXPECT_NEAR(v, 0.25f, 1e-6f);
}

Image test_scene(int W, int H) {
  Image img(W, H, 3);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      img.at(x, y, 0) = float(x) / W;
      img.at(x, y, 1) = float(y) / H;
      img.at(x, y, 2) = ((x / 16 + y / 16) % 2) ? 0.8f : 0.1f;
    }
  return img;
}

TEST(LensDrops, SameSeedSameBytesOtherSeedOtherDrops) {
  const Image img = test_scene(200, 150);
  LensDropSettings s;
  s.seed = 7;
  const auto a = render_lens_drops(img, s), b = render_lens_drops(img, s);
  EXPECT_EQ(a.image.pixels, b.image.pixels);
  EXPECT_EQ(a.mask.pixels, b.mask.pixels);
  s.seed = 8;
  const auto c = render_lens_drops(img, s);
  EXPECT_NE(a.mask.pixels, c.mask.pixels);
}

TEST(LensDrops, MaskIsZeroAwayFromDropsAndOneOnThem) {
  const Image img = test_scene(240, 180);
  for (double fnum : {0.0, 2.0}) {
    LensDropSettings s;
    s.f_number = fnum;
    s.drops = 8;
    s.min_radius_mm = 3;
    s.max_radius_mm = 5;
    const auto caps = place_lens_drops(s, img.width, img.height);
    const auto out = render_lens_drops(img, s, caps);
    const double fpx = out.focal_px, d = s.glass_distance_m, blur = out.blur_diameter_px / 2;
    if (fnum > 0) {
      EXPECT_GT(blur, 2);
    }
    int on = 0, off = 0;
    for (int y = 0; y < img.height; ++y)
      for (int x = 0; x < img.width; ++x) {
        double nearest = 1e9, inside = -1e9;  // distance past the nearest rim; depth inside the deepest
        for (const auto& c : caps) {
          const double dist = std::hypot(x + 0.5 - (img.width / 2.0 + fpx * c.x / d), y + 0.5 - (img.height / 2.0 + fpx * c.y / d));
          const double rpx = fpx * c.radius / d;
          nearest = std::min(nearest, dist - rpx);
          inside = std::max(inside, rpx - dist);
        }
        const float m = out.mask.at(x, y, 0);
        if (nearest > blur + 1.5) {
          EXPECT_EQ(m, 0.f);
          for (int k = 0; k < 3; ++k) EXPECT_EQ(out.image.at(x, y, k), img.at(x, y, k));
          ++off;
        } else if (inside > blur + 1.5) {
          EXPECT_NEAR(m, 1.f, 1e-5f);
          ++on;
        }
      }
    EXPECT_GT(on, 100) << fnum;
    EXPECT_GT(off, 1000) << fnum;
  }
}

// Trails: each drop that ran down leaves small drops above it (up the glass, -y), none overlapping.
TEST(LensDrops, TrailsLieAboveTheirDropsWithoutOverlap) {
  LensDropSettings s;
  s.drops = 10;
  s.trail_fraction = 1;
  s.trail_length_mm = 20;
  const auto caps = place_lens_drops(s, 320, 240);
  LensDropSettings plain = s;
  plain.trail_fraction = 0;
  const auto drops = place_lens_drops(plain, 320, 240);
  EXPECT_GT(caps.size(), 5 * drops.size());
  std::size_t small = 0;
  for (std::size_t i = 0; i < caps.size(); ++i) {
    if (caps[i].radius < 0.7 * s.min_radius_mm * 1e-3) ++small;
    for (std::size_t j = 0; j < i; ++j)
      EXPECT_GE(std::hypot(caps[i].x - caps[j].x, caps[i].y - caps[j].y), caps[i].radius + caps[j].radius);
  }
  EXPECT_GT(small, caps.size() / 2);
  // Without trails: the same drops for the same seed.
  LensDropSettings defaults;
  defaults.drops = 10;
  const auto again = place_lens_drops(defaults, 320, 240);
  ASSERT_EQ(again.size(), drops.size());
  for (std::size_t i = 0; i < again.size(); ++i) EXPECT_EQ(again[i].x, drops[i].x);
}

TEST(LensDrops, CoverageIsMetAndRangesAreChecked) {
  LensDropSettings s;
  s.coverage = 0.2;
  s.f_number = 0;
  const Image img = test_scene(320, 240);
  const auto out = render_lens_drops(img, s);
  EXPECT_NEAR(out.coverage, 0.2, 0.03);
  LensDropSettings bad;
  bad.contact_angle_deg = 120;
  EXPECT_THROW(render_lens_drops(img, bad), DomainError);
  bad = {};
  bad.min_radius_mm = 3;
  bad.max_radius_mm = 1;
  EXPECT_THROW(place_lens_drops(bad, 10, 10), DomainError);
}

// Issue 37: every flag in range, but a circle of confusion of ~30 mm on a 6.17 mm sensor (focus 1 cm,
// glass 10 m, f/0.3) widened the glass region ~40 times a side and its placement grid to ~2e8 cells
// (5.2 GB, 12 s at 64x48). A circle wider than the sensor is refused by the settings' check, naming
// f_number and the smallest f-number that would do; at that f-number the drops are placed.
TEST(LensDrops, CircleOfConfusionWiderThanTheSensorIsRefused) {
  LensDropSettings s;
  s.focus_m = 0.01;
  s.glass_distance_m = 10;
  s.f_number = 0.3;
  try {
    (void)place_lens_drops(s, 64, 48);
    ADD_FAILURE() << "no DomainError";
  } catch (const DomainError& e) {
    EXPECT_EQ(e.quantity(), "f_number");
    EXPECT_NE(std::string(e.what()).find("wider than the sensor"), std::string::npos) << e.what();
    // c scales as 1 / N: the smallest f-number allowed puts the circle at the sensor's width.
    const double c = circle_of_confusion_mm(s.focal_mm, s.f_number, s.focus_m, s.glass_distance_m);
    EXPECT_NEAR(e.lo(), s.f_number * c / s.sensor_width_mm, 1e-12);
    s.f_number = e.lo() * 1.001;
    EXPECT_NO_THROW((void)place_lens_drops(s, 64, 48));
  }
  s.f_number = 0;  // a pinhole: no blur at all
  EXPECT_NO_THROW((void)place_lens_drops(s, 64, 48));
}

// The placement grid's cells are widened where the glass region is large against the drops (here
// ~0.1 m cells for 4 mm drops), so its size follows the drops' count. The invariant the grid must keep,
// checked against all pairs: no two placed footprints overlap.
TEST(LensDrops, WideGridCellsPlaceNonOverlappingDrops) {
  LensDropSettings s;
  s.focus_m = 0.05;
  s.glass_distance_m = 5;
  s.f_number = 2;  // c = 0.4 mm: a 21 px blur at 320 px
  s.drops = 2000;
  const auto caps = place_lens_drops(s, 320, 240);
  ASSERT_GT(caps.size(), 2000u);
  for (std::size_t i = 0; i < caps.size(); ++i)
    for (std::size_t j = i + 1; j < caps.size(); ++j) {
      const double dx = caps[i].x - caps[j].x, dy = caps[i].y - caps[j].y, rr = caps[i].radius + caps[j].radius;
      ASSERT_GE(dx * dx + dy * dy, rr * rr) << i << " " << j;
    }
}

// Channels beyond the first three (alpha, depth, masks) are not light: they pass through unchanged, as
// rain and fog leave them; the three colour channels are the same as a 3-channel image's.
TEST(LensDrops, ChannelsBeyondTheColourPassThrough) {
  const Image rgb = test_scene(120, 90);
  Image five(120, 90, 5);
  for (int y = 0; y < 90; ++y)
    for (int x = 0; x < 120; ++x) {
      for (int c = 0; c < 3; ++c) five.at(x, y, c) = rgb.at(x, y, c);
      five.at(x, y, 3) = 1.f;
      five.at(x, y, 4) = float(x % 7) * 3.f;
    }
  LensDropSettings s;
  s.drops = 40;
  s.seed = 3;
  const auto a = render_lens_drops(rgb, s), b = render_lens_drops(five, s);
  ASSERT_EQ(b.image.channels, 5);
  EXPECT_EQ(a.mask.pixels, b.mask.pixels);
  for (int y = 0; y < 90; ++y)
    for (int x = 0; x < 120; ++x) {
      for (int c = 0; c < 3; ++c) ASSERT_EQ(b.image.at(x, y, c), a.image.at(x, y, c)) << x << "," << y;
      ASSERT_EQ(b.image.at(x, y, 3), 1.f);
      ASSERT_EQ(b.image.at(x, y, 4), float(x % 7) * 3.f);
    }
}

// Negative light reads as 0 in the output and is counted (rain and fog do the same and warn).
TEST(LensDrops, NegativeLightReadsAsZeroAndIsCounted) {
  Image img = test_scene(80, 60);
  img.at(5, 5, 0) = -0.5f;
  img.at(70, 50, 2) = -2.f;
  LensDropSettings s;
  s.drops = 10;
  const auto out = render_lens_drops(img, s);
  EXPECT_EQ(out.negative_values_clamped, 2u);
  for (float v : out.image.pixels) ASSERT_GE(v, 0.f);
  EXPECT_EQ(render_lens_drops(test_scene(80, 60), s).negative_values_clamped, 0u);
}

// A frame with a NaN or an infinity is refused before any work, naming the first such pixel in row
// order, as rain and fog refuse one (docs/rain.md lines 143-148, "A non-finite value (NaN, +-inf) in
// any channel is refused with its position"; the lens-drops check is src/rain/lens_drops.cpp, whose
// message is "pixel (x, y) is not finite; give an image of finite values": the position, without the
// channel or the value rain's NonFinitePixel adds; docs/lens-drops.md says nothing of it). The
// position is checked in a 3- and a 4-channel frame (the pixel is the value's index over the channel
// count); a finite frame with the same drops passes, and its output is finite.
TEST(LensDrops, NonFinitePixelsAreRefusedNamingThePixel) {
  LensDropSettings s;
  s.drops = 10;
  const auto refusal = [&](const Image& img) -> std::string {
    try {
      (void)render_lens_drops(img, s);
    } catch (const Error& e) {
      return e.what();
    }
    return "no error";
  };
  for (int channels : {3, 4}) {
    Image img(80, 60, channels);
    const Image scene = test_scene(80, 60);
    for (int y = 0; y < 60; ++y)
      for (int x = 0; x < 80; ++x)
        for (int c = 0; c < channels; ++c) img.at(x, y, c) = c < 3 ? scene.at(x, y, c) : 1.f;
    const Image finite = img;
    img.at(61, 9, 1) = std::numeric_limits<float>::quiet_NaN();  // row 9
    img.at(12, 40, 0) = std::numeric_limits<float>::infinity();  // row 40
    // Both: the NaN comes first in row order (row 9 before row 40, though its column is larger).
    EXPECT_EQ(refusal(img), "pixel (61, 9) is not finite; give an image of finite values") << channels;
    // The +inf alone.
    img.at(61, 9, 1) = finite.at(61, 9, 1);
    EXPECT_EQ(refusal(img), "pixel (12, 40) is not finite; give an image of finite values") << channels;
    // -inf in the last light channel of the last pixel.
    Image last = finite;
    last.at(79, 59, 2) = -std::numeric_limits<float>::infinity();
    EXPECT_EQ(refusal(last), "pixel (79, 59) is not finite; give an image of finite values") << channels;
    // The same frame without them renders, every output value finite.
    const auto out = render_lens_drops(finite, s);
    EXPECT_GT(out.drops, 0u);
    for (float v : out.image.pixels) ASSERT_TRUE(std::isfinite(v));
    for (float v : out.mask.pixels) ASSERT_TRUE(std::isfinite(v));
  }
}

}  // namespace
}  // namespace hydrolux::rain
