// docs/non-spherical.md, "Domain and errors" (issue 39):
//  1. The plane-section method (scatter::section_rainbow of scatter::spheroid_section) puts the
//     primary bow of an oblate spheroid at the fold of the rays kept in one plane. Where that plane
//     is not a plane of symmetry of the drop (0 < psi < 90, or psi = 90 with the sun up) real rays
//     leave it. Here the bow's edge is found by exact 3-D geometric optics through the oriented
//     spheroid and compared with the section's theta_R along the arc.
//  2. The first-order (Moebius) coefficient K of Delta rho = K (1 - Q) cos 2(h - rho / 2), derived
//     here by first-order perturbation theory of the Descartes ray in a slightly elliptical
//     section, against the library's section_rainbow (no calibration on a tracer).
//  3. The library's own 3-D edge (scatter::spheroid_bow, which the Lee tables of flattened drops use
//     for the bow's angle since this file showed the section's to be off): against the search
//     below along the arc, against brute force (the secondary, canted drops, near the feet), and in
//     a Lee table; where rays reach beyond its fold (the rim, the umbilic) and the tables' notes.
//
// The 3-D reference is written here and shares nothing with the library's 2-D section tracer: the
// ray-spheroid intersection is the quadratic of the spheroid's implicit equation along the ray
// (solved in the scaled coordinates, which is valid for the intersection point), while refraction
// and reflection use the spheroid's true normal (the normalised gradient p / axes^2) and vector
// Snell in world coordinates (scaling to the unit sphere is not valid for them). It is checked ray
// by ray against the project's exact 3-D tracer (drop::trace_paths through a StarSurface of the same
// spheroid, include/hydrolux/drop/trace.hpp), and its bow edge against a brute-force sample.
//
// The bow's edge at position psi. The observer sees the point of the bow at angular radius
// rho = pi - theta and position angle psi (0 at the top, 90 at the side) in the direction
//     D = cos(rho) L + sin(rho) (cos(psi) U + sin(psi) R),
// L = (0, -sin e, cos e) the light's direction (world +y up, sun at elevation e), U = (0, cos e,
// sin e), R = (1, 0, 0) (spheroid_section's frame); a ray leaving the drop along `out` reaches it
// when -out = D. A ray entering the drop at the point r (cos(phi) U + sin(phi) R) of its shadow is
// mapped to (theta, psi) of its exit direction; the primary bow's edge at psi0 is the fold of this
// map: the smallest theta among the rays that leave at psi = psi0. It is found by nesting two 1-D
// searches: for each r, Newton's method finds the phi whose ray leaves at psi0; golden-section
// search then minimises theta over r along that curve (a constrained extremum: there the curve
// psi = psi0 touches a level line of theta, which is the fold). The search starts at the top of
// the bow from a scan for theta's interior minimum and follows the edge along the arc in steps of
// 1 degree (each search bracketing r within 0.03 of the previous edge's). The continuation holds
// down to Q = 0.78 (at 0.77, near the hyperbolic umbilic of the top at Q = 0.763, the edge's entry
// point moves faster than the bracket near the feet); Q = 0.8 is also checked by brute force. At the top (and at the
// feet with the sun on the horizon) the scattering plane is a plane of symmetry of the drop, the
// curve psi = psi0 is the section itself, and the 3-D edge must be the section's theta_R.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "hydrolux/atmos/lee.hpp"
#include "hydrolux/core/math.hpp"
#include "hydrolux/core/vec.hpp"
#include "hydrolux/drop/trace.hpp"
#include "hydrolux/optics/media.hpp"
#include "hydrolux/scatter/ellipse_rainbow.hpp"
#include "hydrolux/scatter/geometric.hpp"
#include "hydrolux/scatter/sphere.hpp"
#include "hydrolux/scatter/spheroid_bow.hpp"
#include "hydrolux/scatter/theories.hpp"
#include "support/asan.hpp"

namespace hydrolux::scatter {
namespace {

constexpr double kPiD = kPi<double>;
constexpr double kN = 1.333;  // the refractive index of docs/non-spherical.md's numbers

double rad(double deg) { return deg_to_rad(deg); }
double deg(double r) { return rad_to_deg(r); }
double wrap(double a) { return std::remainder(a, 2 * kPiD); }

// ---------------------------------------------------------------------------------------------
// The exact 3-D ray tracer
// ---------------------------------------------------------------------------------------------

// An oblate spheroid of axis ratio Q and the volume of the unit sphere, its axis along +y:
// x^2/a^2 + y^2/c^2 + z^2/a^2 = 1, a = Q^(-1/3), c = Q^(2/3).
struct Spheroid {
  double a = 1, c = 1;
  explicit Spheroid(double Q) : a(std::cbrt(1 / Q)), c(Q * std::cbrt(1 / Q)) {}
  Vec3 axes() const { return {a, c, a}; }
  // The near (entering) or far (leaving) root of the line o + t d.
  std::optional<double> hit(const Vec3& o, const Vec3& d, bool near_root) const {
    const Vec3 os = o / axes(), ds = d / axes();
    const double A = glm::dot(ds, ds), B = glm::dot(os, ds), C = glm::dot(os, os) - 1;
    const double disc = B * B - A * C;
    if (disc < 0) return std::nullopt;
    const double q = -(B + std::copysign(std::sqrt(disc), B));  // the stable pair of roots
    double t0 = q / A, t1 = q != 0 ? C / q : -B / A;
    if (t0 > t1) std::swap(t0, t1);
    return near_root ? t0 : t1;
  }
  // The outward unit normal at a point of the surface: the gradient of the implicit function.
  Vec3 normal(const Vec3& p) const { return glm::normalize(p / (axes() * axes())); }
};

// Vector Snell's law: d refracted through the interface of unit normal m (on d's side:
// dot(d, m) < 0) with eta = n_from / n_to; nothing under total internal reflection.
std::optional<Vec3> refract(const Vec3& d, const Vec3& m, double eta) {
  const double ci = -glm::dot(d, m);
  const double k = 1 - eta * eta * (1 - ci * ci);
  if (k < 0) return std::nullopt;
  return eta * d + (eta * ci - std::sqrt(k)) * m;
}

// The ray of order p (p - 1 internal reflections) from `origin` along unit `dir`; its exit
// direction, or nothing if it misses or is totally reflected where it should leave.
std::optional<Vec3> trace3(const Spheroid& s, double n, int p, const Vec3& origin, const Vec3& dir) {
  const auto t0 = s.hit(origin, dir, true);
  if (!t0 || *t0 <= 0) return std::nullopt;
  Vec3 at = origin + *t0 * dir;
  auto d = refract(dir, s.normal(at), 1 / n);
  if (!d) return std::nullopt;
  for (int k = 0; k < p; ++k) {
    const auto t = s.hit(at, *d, false);
    if (!t) return std::nullopt;
    at = at + *t * *d;
    const Vec3 m = s.normal(at);
    if (k + 1 < p) {
      *d = *d - 2 * glm::dot(*d, m) * m;  // internal reflection
    } else {
      d = refract(*d, -m, n);  // leaving
      if (!d) return std::nullopt;
    }
  }
  return glm::normalize(*d);
}

// The frame of the sun at elevation e (spheroid_section's: light along L, U towards the top of the
// bow, R towards its right side).
struct Frame {
  Vec3 L, U, R;
  explicit Frame(double e) : L(0, -std::sin(e), std::cos(e)), U(0, std::cos(e), std::sin(e)), R(1, 0, 0) {}
  Vec3 entry(double r, double phi) const { return r * (std::cos(phi) * U + std::sin(phi) * R) - 4.0 * L; }
};

// Where the ray entering at (r, phi) is seen: its scattering angle and the position angle psi.
struct Seen {
  double theta = 0, psi = 0;
};
std::optional<Seen> seen(const Spheroid& s, const Frame& f, double r, double phi, int p = 2) {
  const auto out = trace3(s, kN, p, f.entry(r, phi), f.L);
  if (!out) return std::nullopt;
  return Seen{std::acos(std::clamp(glm::dot(*out, f.L), -1.0, 1.0)),
              std::atan2(-glm::dot(*out, f.R), -glm::dot(*out, f.U))};
}

// ---------------------------------------------------------------------------------------------
// The 3-D bow edge
// ---------------------------------------------------------------------------------------------

// The phi at which the ray entering at radius r leaves at position angle psi0: Newton's method
// from phi (a forward-difference slope, step 1e-7; steps limited to 0.05 rad), until psi is
// within 1e-14 rad (or the step below 1e-14 rad; rounding stops it near 1e-15).
std::optional<double> phi_leaving_at(const Spheroid& s, const Frame& f, double r, double psi0, double phi) {
  for (int it = 0; it < 60; ++it) {
    const auto a = seen(s, f, r, phi);
    if (!a) return std::nullopt;
    const double miss = wrap(a->psi - psi0);
    if (std::abs(miss) < 1e-14) return phi;
    const auto b = seen(s, f, r, phi + 1e-7);
    if (!b) return std::nullopt;
    const double step = std::clamp(miss / (wrap(b->psi - a->psi) / 1e-7), -0.05, 0.05);
    phi -= step;
    if (std::abs(step) < 1e-14) return phi;
  }
  return std::nullopt;
}

struct Edge {
  bool found = false;
  double theta = 0, r = 0, phi = 0;
};

// theta along the curve psi = psi0, phi continued from call to call.
struct Curve {
  const Spheroid& s;
  const Frame& f;
  double psi0, phi;
  double operator()(double r) {
    const auto ph = phi_leaving_at(s, f, r, psi0, phi);
    if (!ph) return 1e300;
    const auto a = seen(s, f, r, *ph);
    if (!a) return 1e300;
    phi = *ph;
    return a->theta;
  }
};

// The minimum of theta along psi = psi0 with r in [lo, hi] by golden section to 1e-10 in r (theta
// is stationary there: its error is ~q (1e-10)^2, far below rounding).
Edge edge_in(const Spheroid& s, const Frame& f, double psi0, double lo, double hi, double phi) {
  Curve curve{s, f, psi0, phi};
  const double g = (std::sqrt(5.0) - 1) / 2;
  double c = hi - g * (hi - lo), d = lo + g * (hi - lo);
  double fc = curve(c), fd = curve(d);
  while (hi - lo > 1e-10) {
    if (fc < fd) {
      hi = d;
      d = c;
      fd = fc;
      c = hi - g * (hi - lo);
      fc = curve(c);
    } else {
      lo = c;
      c = d;
      fc = fd;
      d = lo + g * (hi - lo);
      fd = curve(d);
    }
  }
  Edge e;
  e.r = 0.5 * (lo + hi);
  e.theta = curve(e.r);
  e.phi = curve.phi;
  e.found = e.theta < 1e299;
  return e;
}

// The 3-D edge at the positions 0, 5, ..., 90 degrees. At the top (phi = 0: the rays of the
// vertical plane) a scan of 200 radii finds theta's interior local minima (with the sun up, rays
// near total reflection at the exit leave at smaller angles still: an edge of the domain, not a
// fold), the lowest of them is refined, and the edge is followed along the arc. `at_bracket_edge`
// is set if a search ended at the end of its bracket (the continuation lost the fold).
struct Arc {
  std::vector<double> theta;  // index k: psi = 5 k degrees
  bool at_bracket_edge = false;
};
Arc bow_edge_3d(double Q, double e) {
  const Spheroid s(Q);
  const Frame f(e);
  Arc arc;
  constexpr int kScan = 200;
  const double r0 = 0.3, r1 = 1.0;
  std::vector<double> th(kScan);
  for (int k = 0; k < kScan; ++k) {
    const auto a = seen(s, f, r0 + (r1 - r0) * k / (kScan - 1), 0);
    th[std::size_t(k)] = a && std::abs(wrap(a->psi)) < 1e-9 ? a->theta : 1e300;
  }
  int best = -1;
  for (int k = 1; k + 1 < kScan; ++k) {
    const auto u = std::size_t(k);
    if (th[u - 1] > 1e299 || th[u + 1] > 1e299) continue;
    if (th[u] <= th[u - 1] && th[u] <= th[u + 1] && (best < 0 || th[u] < th[std::size_t(best)])) best = k;
  }
  if (best < 0) return arc;
  const double step = (r1 - r0) / (kScan - 1);
  Edge edge = edge_in(s, f, 0, r0 + (best - 1) * step, r0 + (best + 1) * step, 0);
  arc.theta.push_back(edge.theta);
  for (int k = 1; k <= 90 && edge.found; ++k) {
    const double w = 0.03;
    const Edge next = edge_in(s, f, rad(k), edge.r - w, edge.r + w, edge.phi);
    if (std::abs(next.r - edge.r) > w - 1e-6) arc.at_bracket_edge = true;
    edge = next;
    if (k % 5 == 0) arc.theta.push_back(edge.theta);
  }
  return arc;
}

double section_theta(double Q, double e, double psi_deg) {
  const auto r = section_rainbow(kN, 2, spheroid_section(Q, {0, 1, 0}, e, rad(psi_deg)));
  EXPECT_TRUE(r.has_value()) << Q << ' ' << e << ' ' << psi_deg;
  return r ? r->scattering_angle : 0;
}

// ---------------------------------------------------------------------------------------------
// 1. The tracer and the search
// ---------------------------------------------------------------------------------------------

// The tracer above against the project's exact 3-D tracer (drop::trace_paths; the spheroid as a
// StarSurface with its analytic normal; its path of one internal reflection): the exit directions
// agree for rays across the shadow of a flattened, sun-tilted drop. trace_paths refines each hit
// to 1e-12 of the bounding radius; measured <= 7e-13; tolerance 1e-10.
TEST(SectionVs3d, TracerAgreesWithTheExactDropTracer) {
  for (double Q : {0.95, 0.8}) {
    const Spheroid s(Q);
    const Vec3 axes = s.axes();
    const auto radius = [axes](const Vec3& u) { return 1 / std::sqrt(glm::dot(u / axes, u / axes)); };
    const drop::StarSurface star(
        Vec3(0), radius, std::max(axes.x, axes.y),
        [axes, radius](const Vec3& u) { return glm::normalize(radius(u) * u / (axes * axes)); });
    for (double e : {0.0, 25.0}) {
      const Frame f(rad(e));
      for (double r : {0.2, 0.6, 0.85}) {
        for (double phi : {0.0, 40.0, 135.0, 250.0}) {
          const Vec3 origin = f.entry(r, rad(phi));
          const auto mine = trace3(s, kN, 2, origin, f.L);
          ASSERT_TRUE(mine.has_value()) << Q << ' ' << e << ' ' << r << ' ' << phi;
          int found = 0;
          drop::trace_paths(star, drop::Ray{origin, f.L}, kN, {}, [&](const drop::ExitPath& path) {
            if (path.kind != drop::PathKind::Internal || path.internal_reflections != 1) return;
            ++found;
            EXPECT_NEAR(glm::length(path.ray.direction - *mine), 0, 1e-10) << Q << ' ' << e << ' ' << r << ' ' << phi;
          });
          EXPECT_EQ(found, 1);
        }
      }
    }
  }
}

// The search's edge against brute force: rays entering on a dense grid (700 x 700) over the
// drop's shadow, those leaving within 0.05 degrees of psi = 45; the smallest theta among them lies
// within the change of the edge across that window (|d theta_edge / d psi| <= 0.2 here, so 0.01
// degrees) of the search's edge, and none is smaller by more (the search finds the global fold).
// Sun on the horizon, where no ray leaves below the fold. Measured: Q = 0.9, 0.0048 degrees
// below the edge (a ray near the window's end).
TEST(SectionVs3d, SearchFindsTheBruteForceEdge) {
  if (HYDROLUX_TEST_ASAN) GTEST_SKIP() << "490,000 rays (0.2 s in Release): Release builds only";
  const double Q = 0.9, e = 0;
  const Arc arc = bow_edge_3d(Q, e);
  ASSERT_EQ(arc.theta.size(), 19u);
  const double edge = arc.theta[9];  // psi = 45
  const Spheroid s(Q);
  const Frame f(e);
  double lowest = 1e300;
  constexpr int kGrid = 700;
  for (int i = 0; i < kGrid; ++i) {
    for (int j = 0; j < kGrid; ++j) {
      // the quadrant of the shadow the rays seen at psi = 45 enter (x, y > 0)
      const double x = 1.1 * (i + 0.5) / kGrid, y = 1.1 * (j + 0.5) / kGrid;
      const auto a = seen(s, f, std::hypot(x, y), std::atan2(x, y));
      if (a && std::abs(wrap(a->psi - rad(45))) < rad(0.05)) lowest = std::min(lowest, a->theta);
    }
  }
  EXPECT_NEAR(deg(lowest), deg(edge), 0.01);
}

// Q = 0.8 (within the method's range, [0.77, 1]), sun on the horizon, psi = 45: rays entering on
// a 900 x 900 grid over the whole shadow, those leaving within 0.05 degrees of psi = 45. No ray
// leaves there at an angle below 163.8 degrees (the 3-D edge; the continuation gives 163.854):
// the section's bow, at 152.78 degrees, lies 11.1 degrees outside every ray the drop sends to that
// position. Measured 163.858 (the window's spread, 0.24 degrees of edge per degree of psi, and the
// grid's spacing, 0.0024, move it by ~0.015); tolerance 0.05.
TEST(SectionVs3d, FlatterDropsByBruteForce) {
  if (HYDROLUX_TEST_ASAN) GTEST_SKIP() << "810,000 rays (0.3 s in Release): Release builds only";
  const double Q = 0.8;
  const Spheroid s(Q);
  const Frame f(0);
  double lowest = 1e300;
  constexpr int kGrid = 900;
  for (int i = 0; i < kGrid; ++i) {
    for (int j = 0; j < kGrid; ++j) {
      const double x = 1.1 * (-1 + 2 * (i + 0.5) / kGrid), y = 1.1 * (-1 + 2 * (j + 0.5) / kGrid);
      const auto a = seen(s, f, std::hypot(x, y), std::atan2(x, y));
      if (a && std::abs(wrap(a->psi - rad(45))) < rad(0.05)) lowest = std::min(lowest, a->theta);
    }
  }
  const double section = section_theta(Q, 0, 45);
  EXPECT_NEAR(deg(section), 152.78, 0.005);
  EXPECT_NEAR(deg(lowest), 163.85, 0.05);
  EXPECT_GT(deg(lowest - section), 10.9);
}

// ---------------------------------------------------------------------------------------------
// 2. The section's bow against the 3-D edge
// ---------------------------------------------------------------------------------------------

// Where the scattering plane is a plane of symmetry (the top, any sun; the feet, sun on the
// horizon) no ray leaves it: the 3-D edge is the section's bow. Both are exact ray optics found
// to stationarity: measured <= 2e-15 rad (Q = 0.99-0.8); tolerance 1e-10 rad.
TEST(SectionVs3d, TopAndLowSunFeetAreExact) {
  for (double Q : {0.99, 0.95, 0.9, 0.85, 0.8}) {
    for (double e : {0.0, 20.0}) {
      const Arc arc = bow_edge_3d(Q, rad(e));
      ASSERT_EQ(arc.theta.size(), 19u) << Q << ' ' << e;
      EXPECT_FALSE(arc.at_bracket_edge) << Q << ' ' << e;
      EXPECT_NEAR(arc.theta[0], section_theta(Q, rad(e), 0), 1e-10) << Q << ' ' << e;
      if (e == 0) {
        EXPECT_NEAR(arc.theta[18], section_theta(Q, 0, 90), 1e-10) << Q;
      }
    }
  }
}

// Between the top and the side the section's bow lies OUTSIDE the 3-D edge (smaller theta, larger
// radius rho): the section underestimates the Moebius shift there. Measured differences
// theta_3d - theta_section in degrees (n = 1.333):
//
//   Q      sun   psi = 15    30     45     60     75     90
//   0.99    0         0.004  0.011  0.015  0.011  0.004  0
//   0.99   20         0.004  0.012  0.017  0.015  0.006  -0.0006
//   0.95    0         0.095  0.300  0.435  0.359  0.130  0
//   0.95   20         0.092  0.298  0.454  0.417  0.199  -0.014
//   0.9     0         0.40   1.33   2.10   1.96   0.82   0
//   0.9    20         0.33   1.12   1.87   1.92   1.04   -0.037
//   0.85    0         0.93   3.25   5.60   6.01   3.18   0
//   0.85   20         0.58   2.12   3.91   4.59   2.93   0.004
//   0.8     0         1.49   5.73   11.08  14.05  10.30  0
//   0.8    20         0.67   2.69   5.61   7.64   5.88   0.26
//
// The largest difference along the arc (5-degree steps): 0.015, 0.44, 2.2, 6.2 and 14.0 degrees
// for Q = 0.99, 0.95, 0.9, 0.85 and 0.8 (sun on the horizon, at psi = 45-60), 0.017, 0.47, 2.0, 4.6
// and 7.6 with the sun 20 degrees up (psi = 50-60); near the method's limit, Q = 0.78, 18.6 and
// 8.8 degrees.
//
// The difference is of SECOND order in the flattening: the sphere's rainbow ray is stationary in
// both directions of the entry disk (theta depends on |b| only), so the constrained extremum's
// first-order change is that of the unperturbed ray, which stays in the plane (the out-of-plane
// tilt of the normals moves theta at second order): the section's first-order Moebius shift is
// exact at every position. Halving 1 - Q (0.005 against 0.01) must divide the difference by
// four: measured 4.04-4.11 at psi = 30, 45 and 60; window 3.6-4.4 (third order moves
// the ratio by O(1 - Q)). A first-order error would give 2.
// The table's rows and the largest differences are asserted to their printed digits (within 3% or
// 0.002 degrees): both sides are exact ray optics found to ~1e-12 rad, so any change of either
// would show.
TEST(SectionVs3d, IntermediatePositionsDifferAtSecondOrder) {
  struct Row {
    double Q, e;
    double diff[7];  // psi = 0, 15, ..., 90 degrees
    double largest;  // over psi = 0, 5, ..., 90 degrees (the page's numbers)
  };
  const Row rows[] = {
      {0.99, 0, {0, 0.00363, 0.01101, 0.01492, 0.01139, 0.00385, 0}, 0.015},
      {0.99, 20, {0, 0.00379, 0.01183, 0.01698, 0.01454, 0.00647, -0.00059}, 0.017},
      {0.95, 0, {0, 0.09467, 0.30012, 0.43509, 0.35935, 0.12997, 0}, 0.44},
      {0.95, 20, {0, 0.09157, 0.29757, 0.45401, 0.41739, 0.19913, -0.01354}, 0.47},
      {0.9, 0, {0, 0.40094, 1.33321, 2.09955, 1.95755, 0.81698, 0}, 2.2},
      {0.9, 20, {0, 0.32714, 1.12342, 1.86836, 1.91812, 1.03577, -0.03682}, 2.0},
      {0.85, 0, {0, 0.92754, 3.25482, 5.59749, 6.01403, 3.18236, 0}, 6.2},
      {0.85, 20, {0, 0.57627, 2.12112, 3.91297, 4.58811, 2.92608, 0.00386}, 4.6},
      {0.8, 0, {0, 1.49063, 5.72535, 11.07818, 14.04507, 10.30442, 0}, 14.0},
      {0.8, 20, {0, 0.67029, 2.68561, 5.60668, 7.63706, 5.88354, 0.25550}, 7.6},
  };
  for (const Row& row : rows) {
    const Arc arc = bow_edge_3d(row.Q, rad(row.e));
    ASSERT_EQ(arc.theta.size(), 19u) << row.Q << ' ' << row.e;
    EXPECT_FALSE(arc.at_bracket_edge) << row.Q << ' ' << row.e;
    for (int k = 1; k < 6; ++k) {
      const double psi = 15.0 * k;
      const double diff = deg(arc.theta[std::size_t(3 * k)] - section_theta(row.Q, rad(row.e), psi));
      EXPECT_GT(diff, 0) << row.Q << ' ' << row.e << ' ' << psi;  // the section's bow lies outside
      EXPECT_NEAR(diff, row.diff[k], std::max(0.03 * row.diff[k], 0.002)) << row.Q << ' ' << row.e << ' ' << psi;
    }
    double largest = 0;
    for (std::size_t k = 0; k < arc.theta.size(); ++k)
      largest = std::max(largest, deg(arc.theta[k] - section_theta(row.Q, rad(row.e), 5.0 * double(k))));
    EXPECT_NEAR(largest, row.largest, 0.03 * row.largest) << row.Q << ' ' << row.e;
    // the feet with the sun up: the section is an ellipse but not a plane of symmetry
    const double feet = deg(arc.theta[18] - section_theta(row.Q, rad(row.e), 90));
    EXPECT_NEAR(feet, row.diff[6], std::max(0.03 * std::abs(row.diff[6]), 0.002)) << row.Q << ' ' << row.e;
  }
  // Second order: the difference at 1 - Q = 0.01 over that at 0.005.
  const Arc a1 = bow_edge_3d(0.99, 0), a2 = bow_edge_3d(0.995, 0);
  ASSERT_EQ(a1.theta.size(), 19u);
  ASSERT_EQ(a2.theta.size(), 19u);
  for (int k : {6, 9, 12}) {
    const double psi = 5.0 * k;
    const double d1 = a1.theta[std::size_t(k)] - section_theta(0.99, 0, psi);
    const double d2 = a2.theta[std::size_t(k)] - section_theta(0.995, 0, psi);
    EXPECT_GT(d1 / d2, 3.6) << psi;
    EXPECT_LT(d1 / d2, 4.4) << psi;
  }
}

// ---------------------------------------------------------------------------------------------
// 3. The first-order Moebius coefficient
// ---------------------------------------------------------------------------------------------

// First-order perturbation theory of the ray of order p in a slightly deformed circle,
// r(phi) = 1 + eps g(phi). A section of axis ratio Q = 1 - eps with the volume-preserving
// semi-axes Q^(-1/3) (long, at angle h from the light) and Q^(2/3) has, to first order,
//     g(phi) = -1/6 + (1/2) cos 2(phi - h).
// Derivation (angles of directions and of points measured from +X, the light's direction):
// - the outward normal at polar angle phi turns by -eps g'(phi): nu = phi - eps g';
// - entry at height b: (1 + eps g) sin phi_0 = b, so d phi_0 = -eps g tan phi_0;
// - refraction in, psi = nu + pi + r with sin i = n sin r, i = -(nu + pi) (the light along +X):
//   d psi = d nu (1 - cos i / (n cos r));
// - a chord from the point (phi_a, 1 + eps g_a) along psi ends at (phi_b, 1 + eps g_b) with
//   F = Im[(1 + eps g_b) e^{i (phi_b - psi)} - (1 + eps g_a) e^{i (phi_a - psi)}] = 0; its
//   linearisation in phi_a, phi_b, psi, g_a, g_b gives d phi_b (unperturbed: phi_b = 2 psi - pi -
//   phi_a);
// - a reflection, psi' = 2 nu + pi - psi: d psi' = 2 d nu - d psi;
// - the exit, psi' = nu + a' with sin a' = n sin a, a = psi - nu: d psi' = d nu + (n cos a / cos a')
//   (d psi - d nu).
// At the rainbow ray d theta / d b = 0, so the first-order change of the rainbow angle is the
// change of that ray's angle at fixed b (the constant part of g, a change of scale, drops out
// there). Returns d theta_R / d eps for the Descartes ray of the observer's side.
double moebius_first_order(double n, int p, double h) {
  const auto g = [h](double ph) { return -1.0 / 6 + 0.5 * std::cos(2 * (ph - h)); };
  const auto g_prime = [h](double ph) { return -std::sin(2 * (ph - h)); };
  const double cos_i = std::sqrt((n * n - 1) / (p * p - 1));  // Descartes (van de Hulst 13.1)
  for (double sign : {1.0, -1.0}) {  // the side whose ray leaves towards -Y, as section_rainbow's
    const double b = sign * std::sqrt(1 - cos_i * cos_i);
    double phi = kPiD - std::asin(b);
    double d_phi = -g(phi) * std::tan(phi);
    double nu = phi, d_nu = d_phi - g_prime(phi);
    const double i0 = wrap(-(nu + kPiD)), r0 = std::asin(std::sin(i0) / n);
    double psi = nu + kPiD + r0;
    double d_psi = d_nu * (1 - std::cos(i0) / (n * std::cos(r0)));
    for (int k = 1; k <= p; ++k) {
      const double pa = phi, pb = 2 * psi - kPiD - pa;
      const double F_b = std::cos(pb - psi), F_a = -std::cos(pa - psi);
      const double F_psi = -std::cos(pb - psi) + std::cos(pa - psi);
      const double F_gb = std::sin(pb - psi), F_ga = -std::sin(pa - psi);
      d_phi = -(F_a * d_phi + F_psi * d_psi + F_gb * g(pb) + F_ga * g(pa)) / F_b;
      phi = pb;
      nu = pb;
      d_nu = d_phi - g_prime(pb);
      if (k < p) {
        psi = 2 * nu + kPiD - psi;
        d_psi = 2 * d_nu - d_psi;
      } else {
        const double a = wrap(psi - nu), a_out = std::asin(n * std::sin(a));
        d_psi = d_nu + n * std::cos(a) / std::cos(a_out) * (d_psi - d_nu);
        psi = nu + a_out;
      }
    }
    if (wrap(psi) < 0) return -d_psi;  // theta = -psi on the observer's side
  }
  ADD_FAILURE() << "no ray on the observer's side";
  return 0;
}

// The library's d theta_R / d(1 - Q) at 1 - Q -> 0: section_rainbow at 1 - Q = 1e-4 and 2e-4,
// Richardson-extrapolated (the second-order term, ~200 degrees (1 - Q)^2, cancels).
double library_slope(int p, double h) {
  double s[2];
  for (int k = 0; k < 2; ++k) {
    const double eps = 1e-4 * (k + 1), Q = 1 - eps;
    const auto r = section_rainbow(kN, p, EllipseSection{std::cbrt(1 / Q), Q * std::cbrt(1 / Q), h});
    EXPECT_TRUE(r.has_value());
    s[k] = (r.value_or(SectionRainbow{}).scattering_angle - rainbow_angle(kN, p)) / eps;
  }
  return 2 * s[0] - s[1];
}

// docs/non-spherical.md: Delta rho = K (1 - Q) cos 2(h - rho / 2), K = -131.75 degrees for the
// primary, +7.33 for the secondary (18 times less, the other way). The perturbation theory above,
// evaluated at the Descartes ray, gives (n = 1.333) K = -131.752 degrees and K_3 = +7.330 degrees,
// and its h-dependence is exactly Moebius's cos 2(h - rho / 2) (the ratio below is constant in h to
// rounding: measured 3e-15 relative). The published coefficient (Lock & Koennen, Appl. Opt. 56,
// G88, 2017) was not available to us; this derivation replaces it.
// Against the library: its Richardson-extrapolated slope agrees with the first-order theory to
// ~1e-8 of K (measured <= 9e-9 of K for the primary, 1e-6 of K_3 for the secondary, whose slope is
// 18 times smaller against the same ~1e-13 rad rounding of the two angles over 1e-4); tolerance
// 1e-6 of K, 1e-5 of K_3. A wrong phase (h instead of h - rho / 2), sign,
// or the second-order bias of a one-sided slope (2e-4 of K) would fail.
TEST(MoebiusFirstOrder, PerturbationTheoryAgainstTheSection) {
  for (int p : {2, 3}) {
    const double rho = kPiD - rainbow_angle(kN, p);
    const double K = -deg(moebius_first_order(kN, p, 0)) / std::cos(rho);
    if (p == 2) {
      EXPECT_NEAR(K, -131.75, 0.005);
    } else {
      EXPECT_NEAR(K, 7.330, 0.0005);
    }
    for (double h : {0.0, 15.0, 30.0, 45.0, 60.0, 75.0, 90.0, 120.0, 150.0}) {
      const double theory = moebius_first_order(kN, p, rad(h));
      // Moebius's form: -theory = K cos 2(h - rho / 2) (in radians per unit 1 - Q)
      EXPECT_NEAR(-deg(theory), K * std::cos(2 * rad(h) - rho), 1e-9 * std::abs(K)) << p << ' ' << h;
      const double tol = (p == 2 ? 1e-6 : 1e-5) * std::abs(rad(K));
      EXPECT_NEAR(library_slope(p, rad(h)), theory, tol) << p << ' ' << h;
    }
  }
  const double ratio = moebius_first_order(kN, 2, 0) / moebius_first_order(kN, 3, 0) *
                       std::cos(kPiD - rainbow_angle(kN, 3)) / std::cos(kPiD - rainbow_angle(kN, 2));
  EXPECT_NEAR(ratio, -18.0, 0.1);  // "18 times less": measured -17.97
}

// ---------------------------------------------------------------------------------------------
// 4. The library's 3-D bow (scatter::spheroid_bow, used by the Lee tables) against the above
// ---------------------------------------------------------------------------------------------

std::optional<SpheroidBow> library_bow(double Q, double e, double psi, int p = 2, Vec3 axis = {0, 1, 0}) {
  const auto sec = section_rainbow(kN, p, spheroid_section(Q, axis, e, psi));
  if (!sec) return std::nullopt;
  return spheroid_bow(kN, p, Q, axis, e, psi, *sec);
}

// The library's search (Newton's method on the curve of rays leaving in the plane, followed from
// the sphere as the flattening grows) against this file's (golden section, followed along the arc
// from the top) at every 5 degrees from the top to the side, down to Q = 0.78 where the latter
// holds. Both are exact ray optics found to stationarity: measured <= 1.2e-12 rad; tolerance 1e-10
// rad. The section's angle, off by up to 14 degrees here, would fail by far; so would a search
// that found another fold. At the top (any sun) and at the feet with the sun on the horizon the
// library takes the section's angle as exact (`symmetric`), which the reference confirms.
TEST(SpheroidBow3d, AgreesWithTheIndependentSearchAlongTheArc) {
  for (double Q : {0.99, 0.95, 0.9, 0.85, 0.8, 0.78}) {
    for (double e : {0.0, 20.0}) {
      const Arc arc = bow_edge_3d(Q, rad(e));
      ASSERT_EQ(arc.theta.size(), 19u) << Q << ' ' << e;
      ASSERT_FALSE(arc.at_bracket_edge) << Q << ' ' << e;
      for (std::size_t k = 0; k < arc.theta.size(); ++k) {
        const double psi = 5.0 * double(k);
        const auto bow = library_bow(Q, rad(e), rad(psi));
        ASSERT_TRUE(bow.has_value()) << Q << ' ' << e << ' ' << psi;
        EXPECT_NEAR(bow->scattering_angle, arc.theta[k], 1e-10) << Q << ' ' << e << ' ' << psi;
        EXPECT_EQ(bow->symmetric, k == 0 || (k == 18 && e == 0)) << Q << ' ' << e << ' ' << psi;
      }
    }
  }
}

// Brute force where the continuation above cannot follow: every ray through a grid, those leaving
// within `window` of psi0 on the observer's side; their extremal scattering angle (the smallest for
// the primary, the largest for the secondary). First 700 x 700 rays over the drop's shadow (window
// 0.05 degrees), then 400 x 400 over the square of side 0.02 around the best of them (spacing 5e-5,
// window 0.01 degrees). The drop's axis may be tilted: the frame is rotated into the drop's (the
// spheroid above keeps its axis along +y).
// With min_entry_cos, rays entering at a larger angle of incidence (near the rim) are left out.
double brute_force_edge(double Q, const Frame& f, double psi0, int p, double min_entry_cos = 0) {
  const Spheroid s(Q);
  const auto grazing = [&](double r, double phi) {
    if (min_entry_cos <= 0) return false;
    const Vec3 o = f.entry(r, phi);
    const auto t = s.hit(o, f.L, true);
    return !t || -glm::dot(f.L, s.normal(o + *t * f.L)) < min_entry_cos;
  };
  const double sign = p == 2 ? 1 : -1;
  double best = 1e300, bx = 0, by = 0;
  const auto sweep = [&](double x0, double y0, double half, int grid, double window) {
    for (int i = 0; i < grid; ++i) {
      for (int j = 0; j < grid; ++j) {
        const double x = x0 + half * (-1 + 2 * (i + 0.5) / grid), y = y0 + half * (-1 + 2 * (j + 0.5) / grid);
        const auto a = seen(s, f, std::hypot(x, y), std::atan2(x, y), p);
        if (!a || std::abs(wrap(a->psi - psi0)) > window || !(sign * a->theta < best)) continue;
        if (grazing(std::hypot(x, y), std::atan2(x, y))) continue;
        best = sign * a->theta;
        bx = x;
        by = y;
      }
    }
  };
  sweep(0, 0, 1.2, 700, rad(0.05));
  best = 1e300;
  sweep(bx, by, 0.01, 400, rad(0.01));
  return sign * best;
}

// The frame of the sun at elevation e seen from a drop whose axis is `axis` (world frame): the
// rotation that takes the axis to +y (Rodrigues' formula) applied to the light, up and right.
Frame drop_frame(double e, const Vec3& axis) {
  Frame f(e);
  const Vec3 a = glm::normalize(axis), y(0, 1, 0);
  const Vec3 k = glm::cross(a, y);
  const double s = glm::length(k), c = glm::dot(a, y);
  if (s < 1e-15) return f;
  const Vec3 u = k / s;
  const auto turn = [&](const Vec3& v) { return c * v + s * glm::cross(u, v) + (1 - c) * glm::dot(u, v) * u; };
  f.L = turn(f.L);
  f.U = turn(f.U);
  f.R = turn(f.R);
  return f;
}

// The library's edge against brute force where the arc search has no answer:
// - the secondary (a maximum of theta), Q = 0.9 and 0.85, sun 20 degrees up, psi = 45;
// - a tilted drop (axis (tan 10, 1, tan 5) degrees: canting), Q = 0.85, sun 10 up, psi = 0 and 30;
// - the flattest drop the arc search follows, Q = 0.8, sun on the horizon, psi = 75.
// The window's rays reach the edge within |d theta_edge / d psi| x 0.01 degrees on one side (the
// slope measured from the library's own edge 0.05 degrees either side) and the fine grid leaves
// them ~1e-4 degrees short of it: the brute-force extremum must lie within
// [edge - slope x 0.01 - 0.002, edge + 0.003] for the primary (mirrored for the secondary).
// Measured: 0.0002-0.0009 degrees (0.008 at Q = 0.8, where the edge runs 0.8 degrees per degree
// of psi), while the section is off by more than 0.3 degrees in each case (asserted).
TEST(SpheroidBow3d, BruteForceForTheSecondaryAndCanting) {
  if (HYDROLUX_TEST_ASAN) GTEST_SKIP() << "3.3 x 10^6 rays (1 s in Release): Release builds only";
  struct Case {
    double Q, e, psi;
    int p;
    Vec3 axis;
  };
  const Case cases[] = {
      {0.9, 20, 45, 3, {0, 1, 0}},
      {0.85, 20, 45, 3, {0, 1, 0}},
      {0.85, 10, 0, 2, {std::tan(rad(10)), 1, std::tan(rad(5))}},
      {0.85, 10, 30, 2, {std::tan(rad(10)), 1, std::tan(rad(5))}},
      {0.8, 0, 75, 2, {0, 1, 0}},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(testing::Message() << "Q " << c.Q << " sun " << c.e << " psi " << c.psi << " p " << c.p);
    const auto bow = library_bow(c.Q, rad(c.e), rad(c.psi), c.p, c.axis);
    ASSERT_TRUE(bow.has_value());
    EXPECT_FALSE(bow->symmetric);
    const auto before = library_bow(c.Q, rad(c.e), rad(c.psi - 0.05), c.p, c.axis);
    const auto after = library_bow(c.Q, rad(c.e), rad(c.psi + 0.05), c.p, c.axis);
    ASSERT_TRUE(before && after);
    const double slope = std::max(std::abs(deg(before->scattering_angle - bow->scattering_angle)),
                                  std::abs(deg(after->scattering_angle - bow->scattering_angle))) / 0.05;
    const double brute = deg(brute_force_edge(c.Q, drop_frame(rad(c.e), c.axis), rad(c.psi), c.p));
    const double edge = deg(bow->scattering_angle), sign = c.p == 2 ? 1 : -1;
    EXPECT_GT(sign * (brute - edge), -slope * 0.01 - 0.002) << brute << ' ' << edge;
    EXPECT_LT(sign * (brute - edge), 0.003) << brute << ' ' << edge;
    const auto sec = section_rainbow(kN, c.p, spheroid_section(c.Q, c.axis, rad(c.e), rad(c.psi)));
    ASSERT_TRUE(sec.has_value());
    EXPECT_GT(std::abs(deg(sec->scattering_angle) - edge), 0.3);  // the section would fail
  }
}

// The Lee table of the flattened drop holds the section's Airy profile moved to the 3-D edge.
// One radius (1 mm), one wavelength (where water / air = 1.333, the index of the reference above),
// a point sun: the table's value at a row is the profile at that angle. Airy's bow peaks where
// Ai(-z)^2 is largest, z = 1.018793 (the first zero of Ai', Abramowitz and Stegun table 10.13),
// z = (x^2 / q)^(1/3) (theta - theta_R), q the section's curvature (the profile's width stays the
// section's): so theta_R = theta_peak - 1.018793 (q / x^2)^(1/3), against this file's 3-D edge.
// The peak is found by golden section over one-row tables to 1e-6 degrees; tolerance 2e-4 degrees
// (measured <= 1e-5). At psi = 0 (the top) the edge is the section's, as before.
TEST(SpheroidBow3d, LeeTableBowAtTheExactEdge) {
  const auto water = optics::find_medium("water");
  const auto air = optics::find_medium("air");
  double lo = 400, hi = 700;  // water's index falls with the wavelength
  for (int it = 0; it < 60; ++it) {
    const double mid = 0.5 * (lo + hi);
    (scatter::sphere_problem(1000, mid, *water, *air).m.real() > kN ? lo : hi) = mid;
  }
  const double nm = 0.5 * (lo + hi);
  const scatter::SphereProblem sp = scatter::sphere_problem(1000, nm, *water, *air);
  ASSERT_NEAR(sp.m.real(), kN, 1e-12);
  for (double Q : {0.9, 0.85}) {
    for (double e : {0.0, 20.0}) {
      const Arc arc = bow_edge_3d(Q, rad(e));
      ASSERT_EQ(arc.theta.size(), 19u);
      for (double psi : {0.0, 45.0, 60.0}) {
        SCOPED_TRACE(testing::Message() << "Q " << Q << " sun " << e << " psi " << psi);
        const auto value = [&](double theta_deg) {
          atmos::LeeSpec s = atmos::profile_spec(atmos::LeeTableKind::rainbow, 1000, theta_deg, theta_deg, 1);
          s.theory = scatter::parse_theory("airy");
          s.shape = atmos::parse_drop_shape(fmt::format("spheroid:{}", Q));
          s.sun_elevation_deg = e;
          s.position_deg = psi;
          s.sun_disk_deg = 0;
          s.wavelength_min_nm = s.wavelength_max_nm = nm;
          s.threads = 1;
          return atmos::compute_lee_table(s).at(0, 0).Y;
        };
        const auto sec = section_rainbow(kN, 2, spheroid_section(Q, {0, 1, 0}, rad(e), rad(psi)));
        ASSERT_TRUE(sec.has_value());
        const double offset = deg(1.018793 * std::cbrt(sec->curvature / (sp.x * sp.x)));
        const double edge = deg(arc.theta[std::size_t(psi / 5)]);
        // golden section for the peak within 0.1 degrees of the expected one (the next maximum,
        // a supernumerary, lies ~0.2 degrees further out)
        double a = edge + offset - 0.05, b = edge + offset + 0.05;
        const double g = (std::sqrt(5.0) - 1) / 2;
        double c = b - g * (b - a), d = a + g * (b - a), fc = value(c), fd = value(d);
        while (b - a > 1e-6) {
          if (fc > fd) {
            b = d;
            d = c;
            fd = fc;
            c = b - g * (b - a);
            fc = value(c);
          } else {
            a = c;
            c = d;
            fc = fd;
            d = a + g * (b - a);
            fd = value(d);
          }
        }
        const double peak = 0.5 * (a + b);
        EXPECT_GT(peak - a, 0);
        EXPECT_NEAR(peak - offset, edge, 2e-4);
        if (psi > 0) {
          EXPECT_GT(edge - deg(sec->scattering_angle), 1.0);  // the section's bow is elsewhere
        }
      }
    }
  }
}

// Where the library's fold is not the edge of every ray. (1) Rays entering near the rim (at
// grazing incidence, weak and without a fold: theta falls monotonically towards the rim) reach
// beyond the fold of flattened drops at some positions: Q = 0.78, sun on the horizon, psi = 75,
// 4.7 degrees beyond (measured 4.74; asserted 4.5-5, the grid's outermost rim ray). Leaving out
// the rays entering at incidence above 75.5 degrees (cos < 0.25), the brute-force edge is the
// fold's (measured 0.009 degrees inside; tolerance: the window's slope as in the previous test).
// (2) Flatter than 0.78, near the feet, rays entering at 70-75 degrees still reach beyond the
// fold: Q = 0.77, sun on the horizon, psi = 85, by 2.2 degrees (measured 2.23; asserted 2.0-2.4),
// the neighbourhood of the hyperbolic umbilic (Q = 0.763): the Lee tables say so in a note
// (docs/non-spherical.md).
TEST(SpheroidBow3d, RimRaysAndTheUmbilicNearTheFeet) {
  if (HYDROLUX_TEST_ASAN) GTEST_SKIP() << "2 x 10^6 rays (0.6 s in Release): Release builds only";
  const auto fold = [](double Q, double psi) {
    const auto bow = library_bow(Q, 0, rad(psi));
    EXPECT_TRUE(bow.has_value());
    return bow ? deg(bow->scattering_angle) : 0.0;
  };
  const double edge = fold(0.78, 75);
  const double slope = std::max(std::abs(fold(0.78, 75.05) - edge), std::abs(fold(0.78, 74.95) - edge)) / 0.05;
  const double rim = deg(brute_force_edge(0.78, Frame(0), rad(75), 2));
  EXPECT_LT(rim, edge - 4.5);
  EXPECT_GT(rim, edge - 5.0);
  const double kept = deg(brute_force_edge(0.78, Frame(0), rad(75), 2, 0.25));
  EXPECT_GT(kept - edge, -slope * 0.01 - 0.002);
  EXPECT_LT(kept - edge, 0.003);
  const double umbilic = deg(brute_force_edge(0.77, Frame(0), rad(85), 2, 0.25)) - fold(0.77, 85);
  EXPECT_LT(umbilic, -2.0);
  EXPECT_GT(umbilic, -2.4);
}

// The Lee tables' notes: near the feet with a low sun, drops flatter than 0.78 (the rays beyond
// the fold, previous test); none for 0.8, nor away from the feet, nor with the sun 20 degrees up.
TEST(SpheroidBow3d, LeeTableNotesNearTheUmbilic) {
  const auto notes = [](const char* shape, double position, double sun, const char* theory = "airy") {
    atmos::LeeSpec s = atmos::profile_spec(atmos::LeeTableKind::rainbow, 500, 120, 170, 11);
    s.theory = scatter::parse_theory(theory);
    s.shape = atmos::parse_drop_shape(shape);
    s.position_deg = position;
    s.sun_elevation_deg = sun;
    s.wavelengths = 4;
    const auto t = atmos::compute_lee_table(s);
    std::string all;
    for (const auto& n : t.notes) all += n + "\n";
    return all;
  };
  EXPECT_NE(notes("spheroid:0.77", 85, 0).find("flatter than 0.78"), std::string::npos);
  EXPECT_NE(notes("spheroid:0.775", 100, 5).find("flatter than 0.78"), std::string::npos);
  EXPECT_EQ(notes("spheroid:0.8", 85, 0).find("flatter than"), std::string::npos);
  EXPECT_EQ(notes("spheroid:0.77", 45, 0).find("flatter than"), std::string::npos);
  EXPECT_EQ(notes("spheroid:0.77", 85, 20).find("flatter than"), std::string::npos);
  // Where the 3-D search finds no fold (here the secondary of a drop just above the limit, the sun
  // 40 degrees up, at the side), the section's angle stays and the table says so.
  EXPECT_NE(notes("spheroid:0.772", 90, 40, "airy:3").find("3-D edge of the bow was not found"), std::string::npos);
  EXPECT_EQ(notes("spheroid:0.9", 45, 20, "airy:3").find("3-D edge"), std::string::npos);
}

}  // namespace
}  // namespace hydrolux::scatter
