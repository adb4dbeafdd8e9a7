// Undoing a drop's distortion (Garg & Nayar Figure 9): the inverse of the refraction mapping
// against the forward model (drop_rays), and undistorted drop images against a direct perspective
// view of the same environment.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "hydrolux/core/error.hpp"
#include "hydrolux/core/math.hpp"
#include "hydrolux/core/random.hpp"
#include "hydrolux/drop/model.hpp"
#include "hydrolux/drop/render.hpp"
#include "hydrolux/drop/undistort.hpp"
#include "hydrolux/optics/fresnel.hpp"
#include "hydrolux/scene/environment.hpp"

namespace hydrolux::drop {
namespace {

// A smooth, asymmetric test world: red grows to the right (+x), green upwards (+y), blue towards
// +z, plus a low-frequency ripple. Each feature spans tens of degrees, so it stays resolved
// through a drop a few hundred pixels across; a sign error in the inversion flips a gradient.
class TestWorld final : public scene::Environment {
 public:
  scene::Rgb radiance(const Vec3& d) const override {
    const double ripple = 0.1 * std::cos(3 * d.x) * std::cos(3 * d.y + 0.5);
    return {0.5 + 0.35 * d.x + ripple, 0.5 + 0.35 * d.y - ripple, 0.45 + 0.3 * d.z + 0.5 * ripple};
  }
};

// The surface normal of the drop-image point at offset (x, y) (units of the image radius, image
// axes: y down) for the on-axis view: sin(theta_n) = rho, pointing back towards the camera.
Vec3 normal_at(double x, double y) {
  const double rho2 = x * x + y * y;
  return {x, -y, -std::sqrt(std::max(0.0, 1 - rho2))};
}

// Polar angle from +z.
double polar(const Vec3& d) { return std::atan2(std::hypot(d.x, d.y), d.z); }

// Direct perspective view of the environment: the reference an undistorted drop should match.
Image perspective(const scene::Environment& env, const UndistortView& view) {
  Image out(view.width, view.height, 3);
  for (int y = 0; y < view.height; ++y)
    for (int x = 0; x < view.width; ++x) {
      const auto L = env.radiance(view.direction(x + 0.5, y + 0.5));
      for (int c = 0; c < 3; ++c) out.at(x, y, c) = float(L[c]);
    }
  return out;
}

struct Comparison {
  double rms_relative = 0;  // RMS over pixels and channels of (undistorted - reference) / reference
  int pixels = 0;
  bool coverage_ok = true;  // every pixel inside the cutoff is marked covered (alpha 1)
};

// Compares over the output pixels whose direction lies within `cutoff_rad` of +z.
Comparison compare(const Image& undistorted, const Image& reference, const UndistortView& view,
                   double cutoff_rad) {
  Comparison c;
  double sum = 0;
  for (int y = 0; y < view.height; ++y)
    for (int x = 0; x < view.width; ++x) {
      if (polar(view.direction(x + 0.5, y + 0.5)) > cutoff_rad) continue;
      if (undistorted.at(x, y, 3) != 1.f) c.coverage_ok = false;
      for (int ch = 0; ch < 3; ++ch) {
        const double ref = reference.at(x, y, ch);
        sum += sqr((undistorted.at(x, y, ch) - ref) / ref);
      }
      ++c.pixels;
    }
  c.rms_relative = std::sqrt(sum / (3.0 * std::max(1, c.pixels)));
  return c;
}

// The closed-form inverse of eq. 8 against the forward model: theta_r(i(theta_r)) = theta_r.
TEST(Undistort, IncidenceInvertsTheDeflection) {
  for (double mu : {1.333, 1.49, 2.0}) {
    const double theta_max = max_refraction_deflection(mu);
    EXPECT_NEAR(2 * rad_to_deg(theta_max), field_of_view_deg(mu), 1e-9);
    for (int s = 0; s <= 1000; ++s) {
      const double theta_r = theta_max * s / 1000.0;
      const double i = incidence_for_deflection(theta_r, mu);
      EXPECT_GE(i, 0.0);
      EXPECT_LE(i, kPi<> / 2);
      const double q = std::asin(std::sin(i) / mu);
      EXPECT_NEAR(2 * (i - q), theta_r, 1e-13) << mu << " " << theta_r;
    }
    EXPECT_NEAR(incidence_for_deflection(theta_max, mu), kPi<> / 2, 1e-12);
    EXPECT_EQ(incidence_for_deflection(0, mu), 0.0);
  }
  EXPECT_THROW((void)incidence_for_deflection(-0.1, 1.333), DomainError);
  EXPECT_THROW((void)incidence_for_deflection(1.5, 1.333), DomainError);  // > 82.8 degrees
  EXPECT_THROW((void)incidence_for_deflection(0.5, 1.0), DomainError);
  try {
    (void)incidence_for_deflection(0.5, 0.9);
    ADD_FAILURE();
  } catch (const DomainError& e) {
    EXPECT_EQ(e.quantity(), "mu");
  }
}

// (a) The round trip: a direction d inside the field of view -> its drop-image point -> the sphere
// normal there -> the forward model's refracted ray (drop_rays, on-axis view +z) gives d back.
// Directions are uniform on the cap theta_r <= theta_max (rim included to 1e-12), all azimuths,
// so every quadrant checks the inversion's signs (image y down, world y up, picture inverted).
// Tolerance 1e-9: rounding only (rho = sin(i) -> sqrt(1 - rho^2) loses a few digits at the rim).
TEST(Undistort, RoundTripThroughTheForwardModel) {
  Rng rng(2004);
  double worst = 0;
  for (double mu : {1.333, 1.49}) {
    const double theta_max = max_refraction_deflection(mu);
    for (int k = 0; k < 20000; ++k) {
      const double cos_max = std::cos(theta_max);
      const double z = k == 0 ? cos_max + 1e-12 : 1 - (1 - cos_max) * rng.uniform();
      const double phi = 2 * kPi<> * rng.uniform(), r = std::sqrt(1 - z * z);
      const Vec3 d{r * std::cos(phi), r * std::sin(phi), z};
      const auto p = drop_image_point(d, mu);
      ASSERT_TRUE(p.has_value()) << polar(d) << " " << theta_max;
      EXPECT_NEAR(std::hypot(p->x, p->y), std::sin(p->incidence), 1e-15);
      const auto rays = drop_rays({0, 0, 1}, normal_at(p->x, p->y), mu, 0);
      const double err = glm::length(rays.refraction - d);
      worst = std::max(worst, err);
      EXPECT_LT(err, 1e-9) << "mu " << mu << " d " << d.x << " " << d.y << " " << d.z;
      EXPECT_NEAR(p->transmission, rays.R, 1e-12);
    }
  }
  std::printf("round trip: worst |d' - d| = %.3g over 40000 directions\n", worst);
  // The picture is inverted: a direction up and to the right appears down and to the left of the
  // drop's centre (image y grows downwards).
  const auto up_right = drop_image_point(glm::normalize(Vec3{0.3, 0.2, 1}), 1.333);
  EXPECT_LT(up_right->x, 0);
  EXPECT_GT(up_right->y, 0);
  // Beyond the field of view, nothing; straight behind the drop, its centre.
  EXPECT_FALSE(drop_image_point(glm::normalize(Vec3{1, 0, 0.1}), 1.333).has_value());
  EXPECT_FALSE(drop_image_point({0, 0, -1}, 1.333).has_value());
  const auto centre = drop_image_point({0, 0, 1}, 1.333);
  EXPECT_EQ(centre->x, 0.0);
  EXPECT_EQ(centre->y, 0.0);
  EXPECT_NEAR(centre->transmission, sqr(1 - sqr(0.333 / 2.333)), 1e-12);
}

// The virtual camera: horizontal field of view, yaw to the right, pitch up.
TEST(Undistort, ViewDirections) {
  UndistortView v;
  v.fov_deg = 90;
  v.width = 200;
  v.height = 100;
  EXPECT_LT(glm::length(v.direction(100, 50) - Vec3{0, 0, 1}), 1e-15);
  EXPECT_NEAR(rad_to_deg(polar(v.direction(0, 50))), 45, 1e-12);          // left edge: fov / 2
  EXPECT_LT(v.direction(0, 50).x, 0);
  EXPECT_GT(v.direction(100, 0).y, 0);                                   // top row looks up
  EXPECT_NEAR(rad_to_deg(polar(v.direction(100, 0))), rad_to_deg(std::atan(0.5)), 1e-12);
  v.yaw_deg = 90;
  EXPECT_LT(glm::length(v.direction(100, 50) - Vec3{1, 0, 0}), 1e-15);
  v.yaw_deg = 0;
  v.pitch_deg = 30;
  EXPECT_LT(glm::length(v.direction(100, 50) - Vec3{0, 0.5, std::sqrt(0.75)}), 1e-15);
  // Yaw turns about the world's vertical after the pitch: the view's centre keeps its elevation.
  v.yaw_deg = 40;
  EXPECT_NEAR(v.direction(100, 50).y, 0.5, 1e-15);
  for (double fov : {0.0, -5.0, 179.5, 200.0}) {
    v.fov_deg = fov;
    try {
      validate(v);
      ADD_FAILURE() << fov;
    } catch (const DomainError& e) {
      EXPECT_EQ(e.quantity(), "fov_deg");
    }
  }
  v.fov_deg = 179;
  EXPECT_NO_THROW(validate(v));
  v.width = 0;
  EXPECT_THROW(validate(v), DomainError);
}

TEST(Undistort, RejectsBadInput) {
  const Image img(16, 16, 3);
  const UndistortView view;
  const auto quantity = [&](double cx, double r, double mu, const Image& im) -> std::string {
    try {
      (void)undistort(im, cx, 8, r, mu, view, true);
    } catch (const DomainError& e) {
      return e.quantity();
    }
    return "";
  };
  EXPECT_EQ(quantity(8, -1, 1.333, img), "radius_px");
  EXPECT_EQ(quantity(8, 0, 1.333, img), "radius_px");
  EXPECT_EQ(quantity(8, 4, 1.0, img), "mu");
  EXPECT_EQ(quantity(std::nan(""), 4, 1.333, img), "center_x_px");
  EXPECT_EQ(quantity(8, 4, 1.333, Image()), "image_width");
  EXPECT_EQ(quantity(8, 4, 1.333, img), "");
}

// A drop image made with the on-axis forward model itself (refraction only: every drop pixel
// shows R Le(refraction direction) at its centre), undistorted with the transmission correction:
// what is left is the bilinear resampling of a drop 200 px in radius. RMS relative errors measured
// within theta_r <= 20 / 40 / 60 degrees: 2.5e-6 / 2.1e-5 / 4.9e-4, growing towards the rim where
// the mapping packs the view ever tighter (d rho / d theta_r -> 0) and the drop image curves
// faster than bilinear interpolation follows; tolerances 3e-5 (40 degrees) and 6e-4 (60). Without
// the correction the result is the scene dimmed by (1 - k)^2: 0.96 at the centre, less outwards.
TEST(Undistort, RecoversTheWorldFromAModelDrop) {
  const TestWorld world;
  const double mu = 1.333, R = 200, cx = 230.5, cy = 210;  // the drop off the image's centre
  Image drop(460, 430, 3);
  for (int y = 0; y < drop.height; ++y)
    for (int x = 0; x < drop.width; ++x) {
      const double ox = (x + 0.5 - cx) / R, oy = (y + 0.5 - cy) / R;
      if (ox * ox + oy * oy > 1) continue;
      const auto rays = drop_rays({0, 0, 1}, normal_at(ox, oy), mu, 0);
      const auto L = world.radiance(rays.refraction);
      for (int c = 0; c < 3; ++c) drop.at(x, y, c) = float(rays.R * L[c]);
    }
  UndistortView view;
  view.fov_deg = 120;
  view.width = 300;
  view.height = 200;
  const Image reference = perspective(world, view);
  const Image out = undistort(drop, cx, cy, R, mu, view, true);
  ASSERT_EQ(out.channels, 4);
  for (double cutoff : {20.0, 40.0, 60.0, 75.0}) {
    const auto c = compare(out, reference, view, deg_to_rad(cutoff));
    std::printf("model drop, R = 200 px, theta_r <= %g deg: RMS relative error %.3g over %d px\n", cutoff,
                c.rms_relative, c.pixels);
  }
  EXPECT_LT(compare(out, reference, view, deg_to_rad(40.0)).rms_relative, 3e-5);
  const auto c = compare(out, reference, view, deg_to_rad(60.0));
  EXPECT_TRUE(c.coverage_ok);
  EXPECT_GT(c.pixels, 10000);
  EXPECT_LT(c.rms_relative, 6e-4);
  // Coverage: a 170 degree view reaches past the drop's 165.6 degree cone at its left and right
  // edges (85 degrees off the axis): transparent black there.
  UndistortView wide = view;
  wide.fov_deg = 170;
  const Image w = undistort(drop, cx, cy, R, mu, wide, true);
  for (int ch = 0; ch < 4; ++ch) {
    EXPECT_EQ(w.at(0, 100, ch), 0.f);
    EXPECT_EQ(w.at(299, 100, ch), 0.f);
  }
  EXPECT_EQ(w.at(150, 100, 3), 1.f);
  // Image points outside the drop image are not covered either: a drop cut by the image's left
  // border loses the directions to the right (seen on its left half).
  const Image cut = undistort(drop, -50, cy, R, mu, view, true);
  EXPECT_EQ(cut.at(299, 100, 3), 0.f);
  EXPECT_EQ(cut.at(0, 100, 3), 1.f);
  // Without the correction: the scene times the transmission.
  const Image raw = undistort(drop, cx, cy, R, mu, view, false);
  const double T0 = sqr(1 - sqr(0.333 / 2.333));
  for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(raw.at(150, 100, ch) / reference.at(150, 100, ch), T0, 1e-3);
}

// (b) The whole chain: render_model's picture of a drop (refraction and the front-surface
// reflection; no internal reflections, no background), undistorted with camera.drop_center_px()
// and drop_radius_px(), against the direct perspective view of the same world.
//
// The drop image also holds the reflection k Le(s): after the transmission correction it adds
// k / (1 - k)^2 of the mirrored world, 2 % at the centre and growing fast towards the rim (k = 0.06
// at theta_r = 40 degrees, 0.26 at 60). render() jitters its supersamples deterministically per
// pixel, so rendering the reflection term alone with the same camera and options gives exactly
// that part of render_model's pixels, and subtracting it leaves the refracted light alone.
// What remains:
//   - the 4 x 4 box-filtered anti-aliasing of the drop image and its bilinear resampling; the
//     mapping compresses the view towards the rim: one drop pixel spans 0.14 degrees of the world
//     at the centre, 0.6 at theta_r = 40, 1.9 at 60 (an output pixel spans 0.4);
//   - the render's per-pixel perspective rays (up to 0.03 degrees off the axis) against the
//     on-axis inverse;
//   - towards the rim, the anti-aliased silhouette and the fast-varying (1 - k)^2.
// Measured RMS relative errors of the reflection-free image (drop radius 204.8 px), theta_r <= 20 /
// 40 / 60 degrees: 1.23e-4 / 1.97e-4 / 8.1e-4; tolerances 1.5e-4 / 2.5e-4 / 1e-3, just above. (A
// sign error in the inversion would give errors of tens of percent: the world's gradients are
// 0.35 per unit of direction.) With the reflection left in, the error is that of the reflection
// term itself: 2.4 % within 20 degrees, 6 % within 40, 37 % within 60.
TEST(Undistort, RecoversTheWorldFromARenderedDrop) {
  const TestWorld world;
  DropCamera camera;
  camera.radius_m = 1e-3;
  camera.distance_m = 2.0;
  camera.frame_m = 2.5e-3;
  camera.width = camera.height = 512;
  RenderOptions options;
  options.n_internal = 0;
  options.background = false;
  const double mu = 1.333;
  const Image drop = render_model(camera, world, {mu, mu, mu}, options);
  // The reflection term alone, on the same supersamples (own sphere intersection: the nearer root
  // of |t v - c|^2 = a^2 for the unit ray v from the pinhole).
  const Vec3 centre_m{0, 0, camera.distance_m};
  const Image reflection = render(camera, world, options, [&](const Ray& ray) -> std::optional<scene::Rgb> {
    const double b = glm::dot(ray.direction, centre_m);
    const double disc = b * b - (glm::dot(centre_m, centre_m) - sqr(camera.radius_m));
    if (disc < 0) return std::nullopt;
    const Vec3 normal = glm::normalize((b - std::sqrt(disc)) * ray.direction - centre_m);
    const auto p = drop_rays(ray.direction, normal, mu, 0);
    return p.S * world.radiance(p.reflection);
  });
  Image refracted = drop;
  for (std::size_t k = 0; k < refracted.pixels.size(); ++k)
    if (k % 4 != 3) refracted.pixels[k] -= reflection.pixels[k];

  const auto centre = camera.drop_center_px();
  const double R = camera.drop_radius_px();
  UndistortView view;
  view.fov_deg = 120;
  view.width = 300;
  view.height = 200;
  const Image reference = perspective(world, view);
  const Image with_reflection = undistort(drop, centre[0], centre[1], R, mu, view, true);
  const Image out = undistort(refracted, centre[0], centre[1], R, mu, view, true);
  struct Case {
    double cutoff_deg, tolerance;
  };
  for (const Case& k : {Case{20, 1.5e-4}, Case{40, 2.5e-4}, Case{60, 1e-3}}) {
    const auto c = compare(out, reference, view, deg_to_rad(k.cutoff_deg));
    const auto r = compare(with_reflection, reference, view, deg_to_rad(k.cutoff_deg));
    std::printf("rendered drop, R = %.1f px, theta_r <= %g deg (%d px): RMS relative error %.3g "
                "(reflection left in: %.3g)\n",
                R, k.cutoff_deg, c.pixels, c.rms_relative, r.rms_relative);
    EXPECT_TRUE(c.coverage_ok);
    EXPECT_LT(c.rms_relative, k.tolerance) << k.cutoff_deg;
  }
}

}  // namespace
}  // namespace hydrolux::drop

TEST(Undistort, ResolvedFractionCountsThePixelsWithAlpha) {
  hydrolux::Image img(4, 2, 4);
  img.at(0, 0, 3) = 1.f;
  img.at(3, 0, 3) = 0.25f;
  img.at(1, 1, 3) = 1e-6f;
  img.at(2, 1, 0) = 1.f;  // colour without alpha is not resolved
  EXPECT_DOUBLE_EQ(hydrolux::drop::resolved_fraction(img), 3.0 / 8.0);
  EXPECT_DOUBLE_EQ(hydrolux::drop::resolved_fraction(hydrolux::Image(4, 2, 3)), 0.0);  // no alpha
  EXPECT_DOUBLE_EQ(hydrolux::drop::resolved_fraction(hydrolux::Image{}), 0.0);
}
