// The 3-D rainbow edge of an oblate spheroid: see hydrolux/scatter/spheroid_bow.hpp.
#include "hydrolux/scatter/spheroid_bow.hpp"

#include <algorithm>
#include <cmath>

#include "hydrolux/core/error.hpp"
#include "hydrolux/scatter/geometric.hpp"

namespace hydrolux::scatter {

namespace {

// The spheroid x.x / a^2 + (1/c^2 - 1/a^2) (x.s)^2 = 1 (equatorial semi-axis a, polar c, unit axis s).
struct Body {
  Vec3 s;
  double inv_a2, k;
  // The roots t0 <= t1 of the line o + t d on the surface; false when it misses.
  bool roots(const Vec3& o, const Vec3& d, double& t0, double& t1) const {
    const double os = glm::dot(o, s), ds = glm::dot(d, s);
    const double A = inv_a2 * glm::dot(d, d) + k * ds * ds;
    const double B = inv_a2 * glm::dot(o, d) + k * os * ds;
    const double C = inv_a2 * glm::dot(o, o) + k * os * os - 1;
    const double disc = B * B - A * C;
    if (disc < 0) return false;
    const double q = -(B + std::copysign(std::sqrt(disc), B));
    const double r0 = q / A, r1 = q != 0 ? C / q : -B / A;
    t0 = std::min(r0, r1);
    t1 = std::max(r0, r1);
    return true;
  }
  // The outward unit normal at a point of the surface (the implicit function's gradient).
  Vec3 normal(const Vec3& x) const { return glm::normalize(inv_a2 * x + k * glm::dot(x, s) * s); }
};

// The ray of order p entering along `light` at `origin` (outside the drop): its exit direction,
// or false when it misses or is totally reflected where it should leave.
bool trace(const Body& b, double n, int p, const Vec3& origin, const Vec3& light, Vec3& out) {
  double t0, t1;
  if (!b.roots(origin, light, t0, t1) || !(t0 > 0)) return false;
  Vec3 at = origin + t0 * light;
  Vec3 m = b.normal(at);
  const double eta = 1 / n;
  double ci = -glm::dot(light, m);
  Vec3 d = eta * light + (eta * ci - std::sqrt(std::max(0.0, 1 - eta * eta * (1 - ci * ci)))) * m;
  for (int k = 0; k < p; ++k) {
    if (!b.roots(at, d, t0, t1)) return false;
    at = at + t1 * d;  // the far root: the near one is the point the ray starts from
    m = b.normal(at);
    if (k + 1 < p) {
      d = d - 2 * glm::dot(d, m) * m;
    } else {
      ci = glm::dot(d, m);  // the cosine of incidence from inside
      const double s2 = n * n * (1 - ci * ci);
      if (s2 >= 1) return false;
      d = n * d + (std::sqrt(1 - s2) - n * ci) * m;
    }
  }
  out = glm::normalize(d);
  return true;
}

struct Search {
  Body body;
  double n;
  int p;
  int side;        // +1: the edge is theta's minimum (primary), -1 its maximum (secondary)
  Vec3 light, toward, normal;  // the light's direction, the bow point's direction, the plane's normal
  double reach;

  bool exit(double u, double v, Vec3& out) const {
    return trace(body, n, p, u * toward + v * normal - reach * light, light, out);
  }
  // The v at which the ray entering at u leaves in the plane, on the observer's side (out.toward
  // < 0), by Newton's method from v (forward-difference slope; steps limited to 0.05).
  bool on_plane(double u, double& v) const {
    Vec3 a, b;
    for (int it = 0; it < 60; ++it) {
      if (!exit(u, v, a)) return false;
      const double g = glm::dot(a, normal);
      if (std::abs(g) < 1e-14) return glm::dot(a, toward) < 0;
      constexpr double kDv = 1e-7;
      if (!exit(u, v + kDv, b)) return false;
      const double slope = (glm::dot(b, normal) - g) / kDv;
      if (!(std::abs(slope) > 0)) return false;
      const double step = std::clamp(g / slope, -0.05, 0.05);
      v -= step;
      if (std::abs(step) < 1e-15) return glm::dot(a, toward) < 0;
    }
    return false;
  }
  // side * theta along the curve at u; v is the curve's v near u on entry and at u on success.
  bool value(double u, double& v, double& f) const {
    if (!on_plane(u, v)) return false;
    Vec3 out;
    if (!exit(u, v, out)) return false;
    f = side * std::acos(std::clamp(glm::dot(out, light), -1.0, 1.0));
    return true;
  }
  // The spheroid of flattening eps = 1 - q (the equal-volume semi-axes).
  void shape(const Vec3& axis, double eps) {
    const double q = 1 - eps, equatorial = std::cbrt(1 / q), polar = q * equatorial;
    body = Body{axis, 1 / (equatorial * equatorial), 1 / (polar * polar) - 1 / (equatorial * equatorial)};
    reach = 4 * equatorial;
  }
  // Newton's method for the extremum of f(u) = side * theta along the curve, from (u, v): central
  // differences at h = 1e-4 (their truncation, ~h^2 f''' / 6, moves u by ~1e-9 and theta by
  // ~1e-18; rounding, ~1e-15 / h, moves u by ~1e-11), each step limited to 0.05 and halved until f
  // does not increase.
  bool extremum(double& u, double& v, double& f0) const {
    if (!value(u, v, f0)) return false;
    constexpr double kH = 1e-4;
    for (int it = 0; it < 50; ++it) {
      double vm = v, vp = v, fm, fp;
      if (!value(u - kH, vm, fm) || !value(u + kH, vp, fp)) return false;
      const double d1 = (fp - fm) / (2 * kH), d2 = (fp - 2 * f0 + fm) / (kH * kH);
      double step = std::clamp(d2 > 0 ? -d1 / d2 : (d1 > 0 ? -0.05 : 0.05), -0.05, 0.05);
      // Converged where Newton's step would lower f by less than 1e-14 rad (the extremum's own
      // error: f is quadratic there), which the noise of the curve's points (~1e-14 in f, so up to
      // ~1e-6 in d1 for the secondary, whose rays graze the rim) does not let the steps go below.
      if (d2 > 0 && (std::abs(step) < 1e-9 || d1 * d1 / (2 * d2) < 1e-14)) return true;
      bool moved = false;
      for (int half = 0; half < 40 && !moved; ++half, step *= 0.5) {
        double vt = v, ft;
        if (value(u + step, vt, ft) && ft <= f0 + 1e-15) {
          u += step;
          v = vt;
          f0 = ft;
          moved = true;
        }
      }
      if (!moved) return false;
    }
    return false;
  }
};

}  // namespace

std::optional<SpheroidBow> spheroid_bow(double n, int p, double q, const Vec3& axis, double sun_elevation,
                                        double position, const SectionRainbow& section, const SpheroidBow* seed) {
  require_in_range("axis_ratio", q, 0.5, 1.0, "a spheroid's 3-D bow");
  require_in_range("order", p, 2, 3, "a spheroid's 3-D bow (primary or secondary)");
  const double e = sun_elevation;
  Search s;
  s.light = Vec3(0, -std::sin(e), std::cos(e));
  s.toward = std::cos(position) * Vec3(0, std::cos(e), std::sin(e)) + std::sin(position) * Vec3(1, 0, 0);
  s.normal = glm::normalize(glm::cross(s.light, s.toward));
  const Vec3 a = glm::normalize(axis);
  SpheroidBow bow;
  bow.u = section.impact;
  bow.scattering_angle = section.scattering_angle;
  // A plane of symmetry (the axis in it, or normal to it; any plane of a sphere): no ray leaves it,
  // the section is exact.
  const double across = std::abs(glm::dot(a, s.normal));
  if (q == 1 || across < 1e-12 || across > 1 - 1e-12) {
    bow.symmetric = true;
    return bow;
  }
  s.n = n;
  s.p = p;
  const RainbowRay sphere = rainbow_ray(n, p);
  s.side = sphere.side;
  // From a nearby drop's edge (the same drop at a neighbouring wavelength): Newton's method alone.
  const double target = 1 - q;
  if (seed && !seed->symmetric) {
    s.shape(a, target);
    double u = seed->u, v = seed->v, f;
    if (s.extremum(u, v, f)) {
      bow.u = u;
      bow.v = v;
      bow.scattering_angle = s.side * f;
      return bow;
    }
  }
  // Continuation in the flattening from the sphere, whose edge is Descartes' ray in the plane (on
  // the side of the section's rainbow ray): each step's edge starts the next; a step whose search
  // fails is halved (down to 1e-4), one that succeeds lets the next double.
  double eps = 0, u = std::copysign(sphere.impact_parameter, section.impact), v = 0, f = 0;
  double step = target;
  bool found = false;
  while (!found) {
    const double next = std::min(target, eps + step);
    s.shape(a, next);
    double ut = u, vt = v, ft;
    if (s.extremum(ut, vt, ft)) {
      eps = next;
      u = ut;
      v = vt;
      f = ft;
      found = eps >= target;
      step *= 2;
    } else {
      step *= 0.5;
      if (step < 1e-4) return std::nullopt;
    }
  }
  bow.u = u;
  bow.v = v;
  bow.scattering_angle = s.side * f;
  return bow;
}

}  // namespace hydrolux::scatter
