// Garg & Nayar's checkerboard verification of the refraction mapping (2004, section 4.4, Figure 5;
// seed 000), simulated with the exact tracer as the photograph (checkerboard.hpp).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "hydrolux/core/error.hpp"
#include "hydrolux/core/math.hpp"
#include "hydrolux/drop/checkerboard.hpp"
#include "hydrolux/optics/snell.hpp"

namespace hydrolux::drop {
namespace {

constexpr double kInch = 0.0254;

// The refraction-only path through the ball worked out here independently of trace.cpp: entry by
// the sphere's quadratic, vector Snell in, the chord, vector Snell out, then the board plane.
std::optional<BoardPoint> independent_exact(const CheckerboardSetup& s, const ImagePoint& px) {
  const Ray ray = pixel_ray(s, px);
  const Vec3 c{0, 0, s.distance_m};
  const double b = glm::dot(c, ray.direction);
  const double disc = b * b - (glm::dot(c, c) - s.radius_m * s.radius_m);
  if (disc < 0) return std::nullopt;
  const Vec3 p1 = (b - std::sqrt(disc)) * ray.direction;
  const Vec3 n1 = (p1 - c) / s.radius_m;
  const auto in = optics::refract(-ray.direction, n1, s.mu);
  const Vec3 d = in->wt;
  const Vec3 p2 = p1 + (-2 * glm::dot(p1 - c, d)) * d;  // the other end of the chord
  const auto out = optics::refract(-d, (p2 - c) / s.radius_m, s.mu);
  if (!out) return std::nullopt;
  const double t = (s.distance_m + s.board_behind_centre_m - p2.z) / out->wt.z;
  return BoardPoint{p2.x + t * out->wt.x, p2.y + t * out->wt.y};
}

TEST(Checkerboard, SetupAndCamera) {
  CheckerboardSetup s;  // the paper's numbers in metres
  EXPECT_NEAR(s.radius_m, 0.022225, 1e-15);
  EXPECT_NEAR(s.distance_m, 2.159, 1e-15);
  EXPECT_NEAR(s.board_behind_centre_m, 0.1524, 1e-15);
  EXPECT_NO_THROW(validate(s));
  // The silhouette: the ray through the image circle of radius diameter_px / 2 grazes the ball.
  for (double phi : {0.0, 1.0, 2.5}) {
    const ImagePoint rim{250 * std::cos(phi), 250 * std::sin(phi)};
    const Ray r = pixel_ray(s, rim);
    const Vec3 c{0, 0, s.distance_m};
    EXPECT_NEAR(glm::length(c - glm::dot(c, r.direction) * r.direction), s.radius_m, 1e-14);
  }
  s.board_behind_centre_m = 0.01;  // inside the ball
  EXPECT_THROW(validate(s), DomainError);
  s = {};
  s.mu = 1.0;
  EXPECT_THROW(validate(s), DomainError);
  EXPECT_THROW((void)compare_corners({}, BoardMapping::Exact), DomainError);
}

// The exact mapping is the tracer's refraction-only path: against the independent chord
// computation above to 1e-12 m (both rounding-limited; the board is 0.17 m from the ball).
// The model sends the same direction from the centre; the exact exit line passes the centre on
// the pixel's side at the entry's impact parameter, so the exact board point is nearer the axis.
TEST(Checkerboard, MappingsAgainstIndependentTrace) {
  const CheckerboardSetup s;
  EXPECT_LT(std::hypot(board_point(s, BoardMapping::Exact, {0, 0})->u,
                       board_point(s, BoardMapping::Exact, {0, 0})->v), 1e-15);
  for (double rho : {0.05, 0.3, 0.6, 0.85}) {
    for (double phi : {0.3, 2.0, 4.0}) {
      const ImagePoint px{250 * rho * std::cos(phi), 250 * rho * std::sin(phi)};
      const auto exact = board_point(s, BoardMapping::Exact, px);
      const auto check = independent_exact(s, px);
      ASSERT_TRUE(exact && check);
      EXPECT_NEAR(exact->u, check->u, 1e-12);
      EXPECT_NEAR(exact->v, check->v, 1e-12);
      const auto model = board_point(s, BoardMapping::Model, px);
      ASSERT_TRUE(model);
      EXPECT_LT(std::hypot(exact->u, exact->v), std::hypot(model->u, model->v));
      // Inverted image: the board point lies on the far side of the axis from the pixel.
      EXPECT_LT(exact->u * px.x + exact->v * px.y, 0);
    }
  }
  // Off the ball, nothing.
  EXPECT_FALSE(board_point(s, BoardMapping::Exact, {260, 0}));
  EXPECT_FALSE(board_point(s, BoardMapping::Model, {260, 0}));
  EXPECT_FALSE(board_point(s, BoardMapping::ModelOrthographic, {260, 0}));
  // Squares: the one at the origin in the first quadrant is light.
  EXPECT_FALSE(checker_dark(s, {0.5 * kInch, 0.5 * kInch}));
  EXPECT_TRUE(checker_dark(s, {-0.5 * kInch, 0.5 * kInch}));
  EXPECT_TRUE(checker_dark(s, {1.5 * kInch, 0.2 * kInch}));
}

// Newton's inversion (with step halving) lands on the board point to rounding even from a poor
// start near the image centre, for targets out to rho ~ 0.8.
TEST(Checkerboard, InvertsTheMapping) {
  const CheckerboardSetup s;
  for (auto mapping : {BoardMapping::Exact, BoardMapping::Model, BoardMapping::ModelOrthographic}) {
    for (const BoardPoint target : {BoardPoint{kInch, 0}, BoardPoint{-2 * kInch, 3 * kInch},
                                    BoardPoint{4 * kInch, 4 * kInch}}) {
      const auto p = image_of_board_point(s, mapping, target, {10, -10});
      ASSERT_TRUE(p) << int(mapping) << " " << target.u << " " << target.v;
      const auto back = board_point(s, mapping, *p);
      EXPECT_NEAR(back->u, target.u, 1e-12);
      EXPECT_NEAR(back->v, target.v, 1e-12);
      EXPECT_LT(std::hypot(p->x, p->y), 250);
    }
  }
}

// The paper's experiment. Setup: acrylic ball mu = 1.49, radius 0.875 in, centre 85 in from the
// pinhole on the optical axis, board perpendicular to the axis 6 in behind the ball's CENTRE (the
// paper: "placed 6 inches from the center of the acrylic ball"), 1 in squares, the ball's image
// 500 px across; every corner whose exact image lies within 0.9 of the ball's image radius (145
// corners). The model (drop_rays per pixel, directions sent from the centre) misplaces them by
// 14.7 px RMS = 2.9 % of the diameter (max 21.5 px, at rho ~ 0.55), about three times the 1 % the
// paper reports: the paper's claim is NOT reproduced by the model with its distant-scene
// assumption in this geometry. The cause is that assumption alone (the exact tracer and drop_rays
// agree on every direction, test_trace.cpp): the exit ray of the refraction path runs at the
// entry's impact parameter a sin(i) from the centre, on the pixel's side, which moves its board
// point towards the axis by about a sin(i) against 2 (1 - 1/mu) D i for the direction: ~20 % of a
// corner's offset near the centre at D = 6 in. So the error falls as 1 / D: 1.36 % at 12 in,
// 0.89 % at 18 in, 0.67 % at 24 in. Read from the back surface (6.875 in from the centre), 2.5 %.
// The paper's orthographic camera adds little (3.2 %). Asserted: the measured values within
// 0.1 percentage point (the inversion is exact to 1e-9 px; the windows only allow for platform
// rounding and the corner set).
TEST(Checkerboard, PaperExperiment) {
  const CheckerboardSetup s;
  const auto model = compare_corners(s, BoardMapping::Model, 0.9);
  std::printf("6 in behind the centre, 1 in squares, 500 px diameter: %zu corners, RMS %.2f px = "
              "%.3f %% of the diameter, max %.2f px\n", model.corners.size(), model.rms_px,
              100 * model.rms_fraction, model.max_px);
  EXPECT_EQ(model.unmatched, 0);
  EXPECT_EQ(model.corners.size(), 145u);
  EXPECT_NEAR(100 * model.rms_fraction, 2.935, 0.1);
  EXPECT_GT(model.rms_fraction, 0.01);  // the paper's "< 1 %" does not hold for this model
  EXPECT_NEAR(model.max_px, 21.5, 0.5);
  // Where the error lies: along the u axis, growing to rho ~ 0.55 and shrinking towards the rim
  // where the mapping compresses the board.
  std::printf("corner  rho    exact x   model x   error px\n");
  for (const auto& m : model.corners) {
    if (m.j == 0 && m.i >= 0) {
      std::printf("%2d      %.3f  %8.2f  %8.2f  %6.2f\n", m.i, m.rho, m.exact.x, m.model.x,
                  m.error_px);
    }
    EXPECT_LE(m.rho, 0.9);
  }
  // Scale-free: the paper's 3.5 px = 1 % implies a 350 px ball; the fraction is the same.
  CheckerboardSetup small = s;
  small.diameter_px = 350;
  EXPECT_NEAR(compare_corners(small, BoardMapping::Model, 0.9).rms_fraction, model.rms_fraction,
              1e-6);
  // The paper's own model, orthographic as well.
  const auto ortho = compare_corners(s, BoardMapping::ModelOrthographic, 0.9);
  std::printf("orthographic model: RMS %.2f px = %.3f %%\n", ortho.rms_px,
              100 * ortho.rms_fraction);
  EXPECT_NEAR(100 * ortho.rms_fraction, 3.18, 0.1);
  // The distant-scene error falls as 1 / (board distance); squares scaled with the distance so
  // that the corners keep their image positions.
  std::printf("board behind centre   RMS %% of diameter\n");
  double previous = 1;
  for (double behind : {12.0, 18.0, 24.0, 60.0}) {
    CheckerboardSetup far = s;
    far.board_behind_centre_m = behind * kInch;
    far.square_m = kInch * behind / 6;
    const auto r = compare_corners(far, BoardMapping::Model, 0.9);
    std::printf("%5.0f in              %.3f\n", behind, 100 * r.rms_fraction);
    EXPECT_LT(r.rms_fraction, previous);
    EXPECT_NEAR(r.rms_fraction * behind, model.rms_fraction * 6, 0.25 * model.rms_fraction * 6);
    if (behind >= 18) {
      EXPECT_LT(r.rms_fraction, 0.01) << behind;
    }
    previous = r.rms_fraction;
  }
}

}  // namespace
}  // namespace hydrolux::drop

namespace hydrolux::drop {
namespace {

// A consistency check, not the paper's claim: the model's refraction direction sent from the point
// where the model's own geometry (seed 000, Figure 3: entry point, chord 2 a cos q) has the ray
// leave the ball. For a sphere that geometry is exact, so the corners must agree with the tracer's
// to rounding in the two traces and the Newton inversion (1e-9 px): asserted below 1e-6 of the
// diameter. It isolates the 2.9% of the test above as the cost of the distant-background
// assumption alone, which the paper names as the source of its error ("3.5 px, under 1%"); at its
// stated geometry that assumption costs about three times what it measured.
TEST(Checkerboard, ModelDirectionsFromTheirExitPointsAreExact) {
  const CheckerboardSetup s;
  const auto model = compare_corners(s, BoardMapping::ModelExitPoint, 0.9);
  EXPECT_EQ(model.unmatched, 0);
  EXPECT_EQ(model.corners.size(), 145u);
  EXPECT_LT(model.rms_fraction, 1e-6);
}

}  // namespace
}  // namespace hydrolux::drop
