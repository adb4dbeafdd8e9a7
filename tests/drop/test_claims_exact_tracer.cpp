// Claims of docs/drop-exact-tracer.md checked against computations written out here:
// - a sphere's path weights in closed form from the Fresnel amplitude equations (Hecht 4.34, 4.40,
//   4.41, 4.42), which also give the power left in the drop at the depth limit;
// - Garg & Nayar's checkerboard experiment (seed 000, section 4.4) by a two-dimensional trace in
//   the plane through the optical axis: the setup is symmetric about that axis (camera on it, board
//   perpendicular to it), so a corner at distance R from the axis images at a radius p(R) found by
//   bisection on one pixel coordinate, and the model's error is radial. Snell's law in vector form,
//   the line-sphere intersection and the board plane are written here; nothing of the library's
//   tracer or checkerboard code is used for the reference side.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "hydrolux/drop/checkerboard.hpp"
#include "hydrolux/drop/model.hpp"
#include "hydrolux/drop/trace.hpp"

namespace hydrolux::drop {
namespace {

// ------------------------------------------------------------------------------------------------
// Sphere: the weight of every path in closed form.

struct Fresnel {
  double rs, rp, ts, tp;  // power reflectances and transmittances (T from the amplitude t, not 1 - R)
};
// Light from index 1 onto index mu at incidence cos_i (Hecht 4.34, 4.40, 4.41, 4.42).
Fresnel fresnel_in(double cos_i, double mu) {
  const double sin_i = std::sqrt(1 - cos_i * cos_i), cos_q = std::sqrt(1 - sin_i * sin_i / (mu * mu));
  const double rs = (cos_i - mu * cos_q) / (cos_i + mu * cos_q);
  const double rp = (mu * cos_i - cos_q) / (mu * cos_i + cos_q);
  const double ts = 2 * cos_i / (cos_i + mu * cos_q), tp = 2 * cos_i / (mu * cos_i + cos_q);
  const double geometry = mu * cos_q / cos_i;  // ratio of the beams' cross sections times n
  return {rs * rs, rp * rp, geometry * ts * ts, geometry * tp * tp};
}

// docs/drop-exact-tracer.md l. 71-74 and 111-115: in a sphere every internal hit meets the surface
// at the refraction angle q, with the same reflectance as outside (Stokes), so the path with N
// internal reflections carries (T_s^2 R_s^N + T_p^2 R_p^N) / 2, the reflection (R_s + R_p) / 2:
// the product of its Fresnel power factors, with no mu^2 left over. At depth 64 the paths reach
// N = 62 and the power still inside is (T_s R_s^63 + T_p R_p^63) / 2 (the sum of the rest of the
// series). With R + T = 1 from the amplitudes, reported plus dropped is 1: asserted to 2e-15 (about
// nine rounding units of 1; measured 5.6e-16 here and 7.8e-16 for the ellipsoid, the sum of ~64
// weights each rounded, so 1e-15 would leave no room for another compiler's contraction or order).
// Total internal reflection cannot occur in a sphere (the internal angle is always q), so nothing
// is trapped; in an ellipsoid it can: of the 5400 rays below (each index), the worst keeps 8% inside
// past 64 interactions (asserted: more than 1%). Reported plus dropped is 1 to 2e-15 there too.
TEST(ClaimsExactTracer, SpherePathWeightsAreProductsOfFresnelFactors) {
  const double a = 0.5;
  const SphereSurface sphere({0, 0, 2}, a);
  TraceOptions deep;
  deep.max_depth = 64;
  double worst_total = 0;
  for (const double mu : {1.333, 1.49})
    for (const double rho : {0.0, 0.3, 0.6, 0.8, 0.9, 0.97, 0.995}) {
      const Ray ray{{rho * a, 0, 0}, {0, 0, 1}};
      const Fresnel f = fresnel_in(std::sqrt(1 - rho * rho), mu);
      EXPECT_NEAR(f.rs + f.ts, 1, 2e-15);
      EXPECT_NEAR(f.rp + f.tp, 1, 2e-15);
      int paths = 0;
      const auto sum = trace_paths(sphere, ray, mu, deep, [&](const ExitPath& p) {
        ++paths;
        double want_s = 0, want_p = 0;
        if (p.kind == PathKind::Reflection) {
          want_s = f.rs / 2, want_p = f.rp / 2;
        } else {
          const int n = p.internal_reflections;
          want_s = f.ts * f.ts * std::pow(f.rs, n) / 2;
          want_p = f.tp * f.tp * std::pow(f.rp, n) / 2;
        }
        // The nudge off the surface perturbs each bounce by ~1e-13 relative (docs l. 99-104), so
        // the N-bounce weight is asserted to 1e-11 (N + 1) of the path's weight (near Brewster's
        // angle R_p is small and its relative error larger), or 1e-14 absolute (the deep paths of
        // grazing rays, whose relative error reaches 5e-10 where the weight is below 1e-40). At
        // rho = 0.995 the inside angle q lies just below the critical angle (sin q = 0.746 against
        // 0.750 for mu = 1.333, 0.668 against 0.671 for 1.49), where R changes steeply with q:
        // there 1e-9 (N + 1).
        const double tol = (rho > 0.99 ? 1e-9 : 1e-11) * (p.internal_reflections + 1);
        EXPECT_NEAR(p.weight_s, want_s, tol * (want_s + want_p) + 1e-14) << mu << " " << rho << " N " << p.internal_reflections;
        EXPECT_NEAR(p.weight_p, want_p, tol * (want_s + want_p) + 1e-14) << mu << " " << rho << " N " << p.internal_reflections;
        EXPECT_NE(p.kind, PathKind::Other);
      });
      EXPECT_EQ(paths, 64);  // the reflection and N = 0..62
      const double inside = (f.ts * std::pow(f.rs, 63) + f.tp * std::pow(f.rp, 63)) / 2;
      EXPECT_NEAR(sum.dropped_depth, inside, 1e-15 + 1e-9 * inside);
      const double total = sum.exit_weight + sum.dropped_depth + sum.dropped_min_weight + sum.lost;
      worst_total = std::max(worst_total, std::abs(total - 1));
    }
  EXPECT_LE(worst_total, 2e-15);

  // The ellipsoid of the page (axes 0.7, 0.45, 0.5): rays that keep per cent of their power inside
  // past 64 interactions exist (trapped by total internal reflection); power is still kept.
  const StarSurface ellipsoid(
      {0, 0, 2},
      [](const Vec3& d) {
        return 1 / std::sqrt(d.x * d.x / (0.7 * 0.7) + d.y * d.y / (0.45 * 0.45) + d.z * d.z / (0.5 * 0.5));
      },
      0.7);
  double most = 0;
  for (int k = 0; k < 24; ++k) {  // directions spread over the sphere (a Fibonacci lattice)
    const double z = 1 - (k + 0.5) / 12, ph = 2.399963 * k, sz = std::sqrt(1 - z * z);
    const Vec3 dir{sz * std::cos(ph), sz * std::sin(ph), z};
    const Vec3 e1 = glm::normalize(glm::cross(dir, std::abs(dir.x) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0}));
    const Vec3 e2 = glm::cross(dir, e1);
    for (int i = 0; i < 15; ++i)
      for (int j = 0; j < 15; ++j) {
        const Vec3 origin = Vec3{0, 0, 2} - 2.0 * dir + (-0.7 + 1.4 * (i + 0.5) / 15) * e1 +
                            (-0.7 + 1.4 * (j + 0.5) / 15) * e2;
        for (const double mu : {1.333, 1.49}) {
          const auto sum = trace_paths(ellipsoid, Ray{origin, dir}, mu, deep, {});
          if (!sum.hit) continue;
          EXPECT_LE(std::abs(sum.exit_weight + sum.dropped_depth + sum.lost - 1), 2e-15);
          most = std::max(most, sum.dropped_depth);
        }
      }
  }
  std::printf("ellipsoid: most power trapped past 64 interactions %.3g\n", most);
  EXPECT_GT(most, 0.01);
}

// ------------------------------------------------------------------------------------------------
// The checkerboard experiment in the plane through the axis.

struct V2 {
  double x, z;
};
V2 operator+(V2 a, V2 b) { return {a.x + b.x, a.z + b.z}; }
V2 operator-(V2 a, V2 b) { return {a.x - b.x, a.z - b.z}; }
V2 operator*(double s, V2 a) { return {s * a.x, s * a.z}; }
double dot(V2 a, V2 b) { return a.x * b.x + a.z * b.z; }
V2 unit(V2 a) { return (1 / std::sqrt(dot(a, a))) * a; }

// Snell's law in vector form: d unit, n the unit normal against d, eta = n_from / n_to.
V2 refract(V2 d, V2 n, double eta) {
  const double c = -dot(d, n);
  const double k = 1 - eta * eta * (1 - c * c);
  return eta * d + (eta * c - std::sqrt(k)) * n;
}

struct BallSetup {
  double a = 0.875 * 0.0254, distance = 85 * 0.0254, behind = 6 * 0.0254, mu = 1.49;
  double image_radius_px = 250;
  double focal() const { return image_radius_px * std::sqrt(distance * distance - a * a) / a; }
};

// The board coordinate reached from image radius p (pixels, signed): the exact refraction path
// (entry, chord, exit, straight to the board), and the model's: the same exit direction (the
// model's directions are exact for a sphere) sent from the ball's centre.
struct Landing {
  double exact, model;
};
Landing land(const BallSetup& s, double p) {
  const V2 c{0, s.distance};
  const V2 d = unit({p, s.focal()});
  const double tc = dot(d, c);
  const V2 off = tc * d - c;
  const double t1 = tc - std::sqrt(s.a * s.a - dot(off, off));
  const V2 p1 = t1 * d;
  const V2 d1 = refract(d, (1 / s.a) * (p1 - c), 1 / s.mu);
  // The far intersection of the line p1 + t d1 with the sphere: the quadratic's other root.
  const V2 w = p1 - c;
  const double b = dot(w, d1), cc = dot(w, w) - s.a * s.a;
  const double t2 = -b + std::sqrt(b * b - cc);
  const V2 p2 = p1 + t2 * d1;
  const V2 n2 = (1 / s.a) * (p2 - c);
  const V2 d2 = refract(d1, -1 * n2, s.mu);
  const double board = s.distance + s.behind;
  return {p2.x + (board - p2.z) / d2.z * d2.x, (board - s.distance) / d2.z * d2.x};
}

// The image radius (pixels, > 0) of a board point at distance r from the axis, seen inverted
// (on the negative side): bisection on p in (0, image radius) for landing = -r.
double image_radius(const BallSetup& s, double r, bool model) {
  double lo = 0, hi = s.image_radius_px * (1 - 1e-9);
  for (int it = 0; it < 200; ++it) {
    const double mid = (lo + hi) / 2;
    const Landing l = land(s, mid);
    ((model ? l.model : l.exact) > -r ? lo : hi) = mid;
  }
  return (lo + hi) / 2;
}

struct Rms {
  int corners = 0;
  double fraction = 0;  // RMS radial error over the diameter
};
// Every corner (i, j) square apart whose exact image is within rho_max of the ball's image radius.
Rms corner_rms(const BallSetup& s, double square, double rho_max) {
  Rms out;
  double sum2 = 0;
  const double r_far = -land(s, rho_max * s.image_radius_px).exact;  // the exact mapping is monotone
  const int k = static_cast<int>(r_far / square) + 1;
  for (int i = -k; i <= k; ++i)
    for (int j = -k; j <= k; ++j) {
      const double r = square * std::hypot(i, j);
      if (r > r_far) continue;
      const double e = image_radius(s, r, false) - image_radius(s, r, true);
      sum2 += e * e;
      ++out.corners;
    }
  out.fraction = std::sqrt(sum2 / out.corners) / (2 * s.image_radius_px);
  return out;
}

// docs/drop-exact-tracer.md l. 166-173: the corners along the u axis, exact and model image x
// (pixels) and their difference, to half a unit of the table's last digit (0.005 px; rho 5e-4; the
// error 0.051 px, since the page rounds the difference of the unrounded values).
TEST(ClaimsCheckerboard, CornerTableAlongTheAxis) {
  const BallSetup s;
  const struct {
    double rho, exact, model, error;
  } table[] = {{0.313, -78.25, -62.33, 15.9},  {0.544, -135.92, -114.45, 21.5},
               {0.691, -172.69, -152.83, 19.9}, {0.782, -195.56, -179.33, 16.2},
               {0.840, -210.12, -197.34, 12.8}, {0.879, -219.71, -209.67, 10.0}};
  for (int k = 1; k <= 6; ++k) {
    const auto& row = table[k - 1];
    const double r = k * 0.0254;
    const double exact = -image_radius(s, r, false), model = -image_radius(s, r, true);
    EXPECT_NEAR(exact, row.exact, 0.005) << k;
    EXPECT_NEAR(model, row.model, 0.005) << k;
    EXPECT_NEAR(model - exact, row.error, 0.051) << k;
    EXPECT_NEAR(-exact / s.image_radius_px, row.rho, 0.0005) << k;
  }
}

// docs/drop-exact-tracer.md l. 163 and 180-183, 189-191: RMS over the corners within 0.9 of the
// image radius 2.9% of the diameter (1 in squares, 145 corners), and so with 0.5 in and 2 in
// squares; a tighter cutoff makes it worse (rho <= 0.5: 9 corners, 3.4%; rho <= 0.7: 29 corners,
// 4.0%); only the centre corner alone (rho <= 0.3) is under 1% (its error is 0). The board 6 in
// behind the ball's back surface: 2.5%; water instead of acrylic: 4.0%. Each to the page's last
// digit (half a unit: 0.05%). The library's compare_corners agrees where it takes the same setup.
TEST(ClaimsCheckerboard, OtherCornerSetsAndSetups) {
  const BallSetup s;
  const Rms base = corner_rms(s, 0.0254, 0.9);
  EXPECT_EQ(base.corners, 145);
  EXPECT_NEAR(base.fraction, 0.029, 0.0005);
  EXPECT_NEAR(corner_rms(s, 0.5 * 0.0254, 0.9).fraction, 0.029, 0.0005);
  EXPECT_NEAR(corner_rms(s, 2 * 0.0254, 0.9).fraction, 0.029, 0.0005);
  const Rms half = corner_rms(s, 0.0254, 0.5), most = corner_rms(s, 0.0254, 0.7);
  EXPECT_EQ(half.corners, 9);
  EXPECT_NEAR(half.fraction, 0.034, 0.0005);
  EXPECT_EQ(most.corners, 29);
  EXPECT_NEAR(most.fraction, 0.040, 0.0005);
  const Rms centre = corner_rms(s, 0.0254, 0.3);
  EXPECT_EQ(centre.corners, 1);
  EXPECT_LT(centre.fraction, 0.01);
  BallSetup back = s;
  back.behind = 6.875 * 0.0254;
  EXPECT_NEAR(corner_rms(back, 0.0254, 0.9).fraction, 0.025, 0.0005);
  BallSetup water = s;
  water.mu = 1.333;
  EXPECT_NEAR(corner_rms(water, 0.0254, 0.9).fraction, 0.040, 0.0005);

  CheckerboardSetup lib;
  const auto cmp = compare_corners(lib, BoardMapping::Model);
  EXPECT_EQ(static_cast<int>(cmp.corners.size()), base.corners);
  EXPECT_NEAR(cmp.rms_fraction, base.fraction, 1e-6);
  lib.board_behind_centre_m = 6.875 * 0.0254;
  EXPECT_NEAR(compare_corners(lib, BoardMapping::Model).rms_fraction,
              corner_rms(back, 0.0254, 0.9).fraction, 1e-6);
}

// docs/drop-exact-tracer.md l. 197-201: the model's own exit point (the entry point, then the chord
// 2 a cos q along the refracted direction, seed 000 Figure 3) is where the sphere's second
// intersection lies, so sent from there the model's direction lands where the exact path does:
// the library's ModelExitPoint corners against this file's exact trace, within 1e-6 of the
// diameter.
TEST(ClaimsCheckerboard, ModelFromItsExitPointIsExact) {
  const BallSetup s;
  // The chord: from the quadratic above against 2 a cos q with sin q = sin i / mu.
  for (const double p : {10.0, 100.0, 200.0, 240.0}) {
    const V2 c{0, s.distance};
    const V2 d = unit({p, s.focal()});
    const double tc = dot(d, c);
    const V2 off = tc * d - c;
    const V2 p1 = (tc - std::sqrt(s.a * s.a - dot(off, off))) * d;
    const double cos_i = -dot(d, (1 / s.a) * (p1 - c));
    const double sin_q = std::sqrt(1 - cos_i * cos_i) / s.mu;
    const V2 d1 = refract(d, (1 / s.a) * (p1 - c), 1 / s.mu);
    const V2 w = p1 - c;
    const double b = dot(w, d1), chord = -b + std::sqrt(b * b - (dot(w, w) - s.a * s.a));
    EXPECT_NEAR(chord, 2 * s.a * std::sqrt(1 - sin_q * sin_q), 1e-12 * s.a) << p;
  }
  CheckerboardSetup lib;
  const auto cmp = compare_corners(lib, BoardMapping::ModelExitPoint);
  ASSERT_EQ(static_cast<int>(cmp.corners.size()), 145);
  for (const auto& corner : cmp.corners) {
    const double r = 0.0254 * std::hypot(corner.i, corner.j);
    const double exact = image_radius(s, r, false);
    EXPECT_NEAR(std::hypot(corner.model.x, corner.model.y), exact, 1e-6 * 500) << corner.i << " " << corner.j;
  }
}

// Gallery drop_radiance_profile.svg (src/gallery/gallery.cpp:307): the figure plots the model's
// paths for Le = 1, mu = 1.333 against rho = sin i: refraction (1 - k)^2, reflection k, and
// k (1 - k)^2, k^2 (1 - k)^2 for one and two internal reflections, k = (R_s + R_p) / 2 (seed 000,
// eqs. 9-12). With k from the Fresnel equations written above, the refraction's share of the sum is
// 0.96 at the centre, 0.92 at rho = 0.8, 0.84 at 0.9 and one half at 0.98 (the caption's figures,
// to their last digit: 0.005); the figure's data (radiance_profile, 501 samples) equal the formulas
// at every sample (1e-12).
TEST(ClaimsGallery, DropRadianceProfileShares) {
  const double mu = 1.333;
  const auto share = [mu](double rho) {
    const Fresnel f = fresnel_in(std::sqrt(1 - rho * rho), mu);
    const double k = (f.rs + f.rp) / 2, t = (1 - k) * (1 - k);
    return t / (t + k + k * t + k * k * t);
  };
  EXPECT_NEAR(share(0.0), 0.96, 0.005);
  EXPECT_NEAR(share(0.8), 0.92, 0.005);
  EXPECT_NEAR(share(0.9), 0.84, 0.005);
  EXPECT_NEAR(share(0.98), 0.50, 0.005);
  const auto p = radiance_profile(mu, 501);
  ASSERT_EQ(p.rho.size(), 501u);
  for (std::size_t i = 0; i + 1 < p.rho.size(); ++i) {  // the rim itself (rho = 1) is grazing
    const Fresnel f = fresnel_in(std::sqrt(1 - p.rho[i] * p.rho[i]), mu);
    const double k = (f.rs + f.rp) / 2;
    EXPECT_NEAR(p.refraction[i], (1 - k) * (1 - k), 1e-12) << p.rho[i];
    EXPECT_NEAR(p.reflection[i], k, 1e-12) << p.rho[i];
    EXPECT_NEAR(p.internal[0][i], k * (1 - k) * (1 - k), 1e-12) << p.rho[i];
    EXPECT_NEAR(p.internal[1][i], k * k * (1 - k) * (1 - k), 1e-12) << p.rho[i];
  }
}

}  // namespace
}  // namespace hydrolux::drop
