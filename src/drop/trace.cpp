#include "hydrolux/drop/trace.hpp"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <utility>
#include <vector>

#include "hydrolux/core/error.hpp"
#include "hydrolux/core/math.hpp"
#include "hydrolux/drop/params.hpp"
#include "hydrolux/optics/fresnel.hpp"
#include "hydrolux/optics/snell.hpp"

namespace hydrolux::drop {

namespace {
constexpr const char* kContext = "the exact drop tracer";

// Some unit vector perpendicular to unit u (for the tangent frame of a normal or a direction).
Vec3 any_perpendicular(const Vec3& u) {
  const Vec3 axis = std::abs(u.x) < 0.6 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
  return glm::normalize(glm::cross(u, axis));
}
}  // namespace

// ------------------------------------------------------------------------------------------------
// Sphere
// ------------------------------------------------------------------------------------------------

SphereSurface::SphereSurface(const Vec3& centre, double radius) : centre_(centre), radius_(radius) {
  require_in_range("radius", radius, 1e-300, 1e6, kContext);
}

std::optional<SurfaceHit> SphereSurface::intersect(const Ray& ray, double t_min) const {
  // Everything relative to the centre: the origin's offset oc is formed once, so a small sphere
  // far from the world origin keeps its digits.
  const Vec3 oc = ray.origin - centre_;
  const Vec3& d = ray.direction;
  const double b = glm::dot(oc, d);  // the line's closest approach to the centre is at t = -b
  const Vec3 perp = oc - b * d;      // centre to that closest point
  // Squared half chord r^2 - |perp|^2, formed as (r - |perp|)(r + |perp|): b^2 - (|oc|^2 - r^2)
  // would lose every digit when |oc| >> r (Haines et al. 2019, section 7.2).
  const double dist = glm::length(perp);
  const double half_chord2 = (radius_ - dist) * (radius_ + dist);
  if (half_chord2 < 0) return std::nullopt;
  const double h = std::sqrt(half_chord2);
  // Roots -b -+ h. The one of larger magnitude, q = -(b + sign(b) h), has no cancellation; the
  // other follows from the product of the roots, c = |oc|^2 - r^2 (Vieta), which is accurate
  // where it matters (an origin on or near the sphere makes c small and the root near 0).
  const double q = b >= 0 ? -(b + h) : (-b + h);
  const double len_oc = glm::length(oc);
  const double c = (len_oc - radius_) * (len_oc + radius_);
  double t0 = q, t1 = q == 0 ? 0.0 : c / q;
  if (t0 > t1) std::swap(t0, t1);
  double t;
  if (t0 > t_min) {
    t = t0;
  } else if (t1 > t_min) {
    t = t1;
  } else {
    return std::nullopt;
  }
  // The hit put back on the sphere: normal from the centre, point at exactly one radius.
  const Vec3 n = glm::normalize(oc + t * d);
  return SurfaceHit{t, centre_ + radius_ * n, n};
}

// ------------------------------------------------------------------------------------------------
// Star-shaped surface
// ------------------------------------------------------------------------------------------------

StarSurface::StarSurface(const Vec3& centre, RadiusFn radius_toward, double max_radius,
                         NormalFn normal_toward, int samples_per_diameter)
    : centre_(centre),
      radius_(std::move(radius_toward)),
      max_radius_(max_radius),
      normal_(std::move(normal_toward)),
      samples_(samples_per_diameter) {
  require_in_range("max_radius", max_radius, 1e-300, 1e6, kContext);
  require_in_range("samples_per_diameter", samples_per_diameter, 8, 1 << 20, kContext);
  if (!radius_) throw DomainError("radius", 0, 1e-300, max_radius, "an empty radius function");
}

double StarSurface::radius_toward(const Vec3& unit_dir) const {
  const double r = radius_(unit_dir);
  if (!(r > 0 && r <= max_radius_ * (1 + 1e-9)))
    throw DomainError("radius", r, 0, max_radius_,
                      "a star-shaped drop surface (r along a direction)");
  return r;
}

Vec3 StarSurface::normal_toward(const Vec3& u) const {
  if (normal_) return glm::normalize(normal_(u));
  // F(p) = |p - c| - r(u(p)), u(p) = (p - c) / |p - c|. Moving p by a small distance e across u
  // along a unit tangent e1 turns u by e / |p - c| towards e1, so on the surface (|p - c| = r)
  //   grad F = u - (dr/ds_1 e1 + dr/ds_2 e2) / r,
  // with dr/ds the derivative of r along the great circle through u towards e1 (or e2). It is
  // taken by the fourth-order central difference (8 (r(h) - r(-h)) - (r(2h) - r(-2h))) / (12 h):
  // truncation error h^4 r^(5) / 30, rounding about 1.5 DBL_EPSILON r / h; h = 1e-3 rad keeps both
  // near 1e-13 r for a surface whose angular derivatives are of the order of r (an ellipsoid of
  // axis ratio 2, Beard & Chuang's shapes), so the normal is good to about 1e-12.
  constexpr double h = 1e-3;
  const Vec3 e1 = any_perpendicular(u);
  const Vec3 e2 = glm::cross(u, e1);
  const double r = radius_toward(u);
  const auto derivative = [&](const Vec3& e) {
    const auto at = [&](double s) { return radius_toward(std::cos(s) * u + std::sin(s) * e); };
    return (8 * (at(h) - at(-h)) - (at(2 * h) - at(-2 * h))) / (12 * h);
  };
  return glm::normalize(u - (derivative(e1) * e1 + derivative(e2) * e2) / r);
}

double StarSurface::signed_distance(const Vec3& v) const {
  // v = p - c. F < 0 inside, > 0 outside, 0 on the surface; |grad F| >= 1 near the surface, so F
  // is at most the distance to the surface along the radial line.
  const double len = glm::length(v);
  if (len == 0) return -radius_toward({0, 0, 1});
  return len - radius_toward(v / len);
}

std::optional<SurfaceHit> StarSurface::intersect(const Ray& ray, double t_min) const {
  const Vec3 oc = ray.origin - centre_;
  const Vec3& d = ray.direction;
  // The part of the ray inside the bounding sphere (widened by rounding's worth).
  const double bound = max_radius_ * (1 + 1e-9);
  const double b = glm::dot(oc, d);
  const double dist = glm::length(oc - b * d);
  const double half_chord2 = (bound - dist) * (bound + dist);
  if (half_chord2 <= 0) return std::nullopt;
  const double half_chord = std::sqrt(half_chord2);
  const double t_lo = std::max(t_min, -b - half_chord);
  const double t_hi = -b + half_chord;
  if (!(t_hi > t_lo)) return std::nullopt;

  const auto f = [&](double t) { return signed_distance(oc + t * d); };
  // The root's tolerance: 1e-12 of the drop's size, or the rounding of t itself far from the
  // origin.
  const double tol = 1e-12 * max_radius_ + 4 * DBL_EPSILON * std::abs(t_hi);

  // Refines a bracketed sign change of f in [a, b] (f(a) f(b) < 0): regula falsi with the
  // Illinois modification (Dowell & Jarratt 1971; the end kept twice has its value halved, which
  // makes the convergence superlinear), and a bisection whenever a step fails to halve the bracket,
  // so it never does worse than bisection.
  const auto refine = [&](double a, double fa, double c, double fc) {
    int kept = 0;  // +1: a kept in the last step(s), -1: c kept
    bool bisect = false;
    for (int it = 0; it < 200 && std::abs(c - a) > tol; ++it) {
      const double width = std::abs(c - a);
      double x = c - fc * (c - a) / (fc - fa);
      if (bisect || !(x > std::min(a, c) && x < std::max(a, c))) x = (a + c) / 2;
      const double fx = f(x);
      if (fx == 0) return x;
      if ((fx < 0) == (fa < 0)) {
        a = x;
        fa = fx;
        if (kept == -1) fc /= 2;  // c kept again: Illinois
        kept = -1;
      } else {
        c = x;
        fc = fx;
        if (kept == +1) fa /= 2;
        kept = +1;
      }
      bisect = std::abs(c - a) > width / 2;
    }
    return std::abs(fa) < std::abs(fc) ? a : c;
  };

  // Golden-section search (Kiefer 1953) for a point in [a, c] where s f changes sign, given
  // s f > 0 at both ends and a sampled minimum of s f in between: the ray grazes a bump of the
  // surface (or, from inside, dips out through a dimple) between two samples. Unimodality of f
  // over the bracket is what the sampling step provides; the search stops at a width of 1e-9
  // max_radius, where a sliver shallower than about 1e-18 max_radius could still be missed.
  const auto sliver = [&](double a, double c, double s) -> std::optional<double> {
    constexpr double kInvPhi = 0.6180339887498949;
    double x1 = c - kInvPhi * (c - a), x2 = a + kInvPhi * (c - a);
    double g1 = s * f(x1), g2 = s * f(x2);
    const double stop = 1e-9 * max_radius_;
    while (true) {
      if (g1 <= 0) return x1;
      if (g2 <= 0) return x2;
      if (c - a <= stop) return std::nullopt;
      if (g1 < g2) {
        c = x2;
        x2 = x1;
        g2 = g1;
        x1 = c - kInvPhi * (c - a);
        g1 = s * f(x1);
      } else {
        a = x1;
        x1 = x2;
        g1 = g2;
        x2 = a + kInvPhi * (c - a);
        g2 = s * f(x2);
      }
    }
  };

  const auto make_hit = [&](double t) {
    // The point put back on the surface along its radial direction; the normal there.
    const Vec3 v = oc + t * d;
    const double len = glm::length(v);
    const Vec3 u = len > 0 ? v / len : Vec3{0, 0, 1};
    return SurfaceHit{t, centre_ + radius_toward(u) * u, normal_toward(u)};
  };

  // Sampling step 2 max_radius / samples_per_diameter (default max_radius / 32). It has to be
  // short enough that f is unimodal between every other sample, so that a sliver the samples
  // step over shows as a sampled local minimum of |f|: for Beard & Chuang's shapes, whose
  // largest harmonic cos(10 theta) has a period of 0.63 rad (0.63 r of arc), it gives more than
  // ten samples per lobe.
  const double step = 2 * max_radius_ / samples_;
  const int n = std::max(4, int(std::ceil((t_hi - t_lo) / step)));
  const double dt = (t_hi - t_lo) / n;

  double t_prev = t_lo, f_prev = f(t_lo);
  if (f_prev == 0) {
    if (t_lo > t_min) return make_hit(t_lo);
    f_prev = f(t_lo + 1e-6 * dt);  // starts exactly on the surface: the side it moves into
    if (f_prev == 0) return make_hit(t_lo + 1e-6 * dt);
  }
  const double s = f_prev > 0 ? 1.0 : -1.0;  // outside or inside at the start
  // The sample before t_prev; none yet (an infinite value lets a minimum at the start count).
  double t_before = t_prev, f_before = f_prev, g_before = INFINITY;
  for (int k = 1; k <= n; ++k) {
    const double t = k == n ? t_hi : t_lo + k * dt;
    const double ft = f(t);
    if (s * ft <= 0) return make_hit(ft == 0 ? t : refine(t_prev, f_prev, t, ft));
    // A sampled local minimum of s f at t_prev: search the two intervals around it.
    const double g_prev = s * f_prev;
    if (g_prev <= g_before && g_prev <= s * ft) {
      if (const auto x = sliver(t_before, t, s)) {
        return make_hit(refine(t_before, f_before, *x, f(*x)));
      }
    }
    t_before = t_prev;
    f_before = f_prev;
    g_before = g_prev;
    t_prev = t;
    f_prev = ft;
  }
  // A minimum at the last sample (where the ray leaves the bounding sphere).
  if (s * f_prev <= g_before) {
    if (const auto x = sliver(t_before, t_prev, s)) {
      return make_hit(refine(t_before, f_before, *x, f(*x)));
    }
  }
  return std::nullopt;
}

// ------------------------------------------------------------------------------------------------
// The Fresnel-split tracer
// ------------------------------------------------------------------------------------------------

namespace {

// A ray still to be followed.
struct Pending {
  Ray ray;            // origin nudged off the surface into the medium it travels in
  Vec3 surface_point;  // where it left the surface (the camera's position for the camera ray)
  double ws = 0.5, wp = 0.5;
  int depth = 0;       // surface interactions so far
  int internal = 0;    // reflections inside the drop
  int entries = 0;     // refractions into the drop
  int external = 0;    // reflections off the outside
  bool inside = false;
};

PathKind kind_of(const Pending& p) {
  if (p.depth == 0) return PathKind::Miss;
  if (p.entries == 0 && p.depth == 1) return PathKind::Reflection;
  if (p.entries == 1 && p.external == 0)
    return p.internal == 0 ? PathKind::Refraction : PathKind::Internal;
  return PathKind::Other;
}

}  // namespace

TraceSummary trace_paths(const DropSurface& surface, const Ray& camera_ray, double mu,
                         const TraceOptions& options, const ExitCallback& on_exit) {
  require_in_range("mu", mu, 0.1, 10.0, kContext);
  static const Param& depth = drop_render_param("depth");  // the declared range (drop/params.hpp)
  require_in_range("max_depth", options.max_depth, depth.lo, depth.hi, kContext);
  require_in_range("min_weight", options.min_weight, 0.0, 1.0, kContext);
  require_in_range("camera_ray_direction", glm::length(camera_ray.direction), 1 - 1e-9, 1 + 1e-9,
                   kContext);

  // A new ray starts this far off the surface, on the side of the medium it travels in, so that
  // it cannot find its own starting point again whichever side it is on: 1e-13 of the drop's size
  // (some 500 times the rounding of r or |p - c|), plus 16 rounding units of the point's
  // coordinates for a drop far from the origin. The nudge moves the next hit by about as much: it
  // turns the following directions by ~1e-13 rad, and changes the Fresnel factors by that times
  // their slope (up to ~1e-12 within a degree of grazing incidence).
  const double scale = surface.bounding_radius();
  const auto offset = [&](const Vec3& p) {
    const double big = std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z)});
    return 1e-13 * scale + 16 * DBL_EPSILON * big;
  };

  TraceSummary summary;
  std::vector<Pending> stack;
  stack.push_back({camera_ray, camera_ray.origin});
  while (!stack.empty()) {
    const Pending p = stack.back();
    stack.pop_back();
    const auto hit = surface.intersect(p.ray, 0.0);
    if (!hit) {
      if (p.inside) {
        // A closed surface always stops a ray inside it; only a numerical failure (a ray grazing
        // the inside of the surface) lands here.
        summary.lost += p.ws + p.wp;
        continue;
      }
      ExitPath e;
      e.ray = {p.surface_point, p.ray.direction};
      e.weight_s = p.ws;
      e.weight_p = p.wp;
      e.weight = p.ws + p.wp;
      e.internal_reflections = p.internal;
      e.interactions = p.depth;
      e.kind = kind_of(p);
      ++summary.exits;
      summary.exit_weight += e.weight;
      if (on_exit) on_exit(e);
      continue;
    }
    summary.hit = true;
    if (p.depth == options.max_depth) {
      summary.dropped_depth += p.ws + p.wp;
      continue;
    }
    const Vec3& d = p.ray.direction;
    const Vec3& n = hit->normal;
    // The medium the ray travels in is tracked, not read off the sign of d . n (which can round
    // the wrong way at grazing incidence); cos_i is then clamped into [0, 1].
    const double n_i = p.inside ? mu : 1.0, n_t = p.inside ? 1.0 : mu;
    const Vec3 n_facing = p.inside ? -n : n;  // the normal on the incident side
    const double cos_i = std::clamp(-glm::dot(d, n_facing), 0.0, 1.0);
    const auto fr = optics::fresnel_dielectric(cos_i, n_i, n_t);
    const auto refracted = optics::refract(-d, n_facing, n_t / n_i);

    const auto spawn = [&](const Vec3& dir, double ws, double wp, bool inside, bool reflected) {
      const double w = ws + wp;
      if (w == 0) return;
      if (w < options.min_weight) {
        summary.dropped_min_weight += w;
        return;
      }
      Pending c = p;
      c.inside = inside;
      c.ws = ws;
      c.wp = wp;
      c.depth = p.depth + 1;
      if (reflected) {
        (p.inside ? c.internal : c.external) += 1;
      } else if (inside) {
        ++c.entries;
      }
      const Vec3 unit = glm::normalize(dir);
      c.ray = {hit->point + (inside ? -offset(hit->point) : offset(hit->point)) * n, unit};
      c.surface_point = hit->point;
      stack.push_back(c);
    };

    const Vec3 mirror = d - 2 * glm::dot(d, n) * n;
    if (fr.tir || !refracted || fr.T_s + fr.T_p == 0) {
      // Total internal reflection (or grazing incidence): everything is reflected.
      spawn(mirror, p.ws, p.wp, p.inside, true);
    } else {
      spawn(mirror, p.ws * fr.R_s, p.wp * fr.R_p, p.inside, true);
      spawn(refracted->wt, p.ws * fr.T_s, p.wp * fr.T_p, !p.inside, false);
    }
  }
  return summary;
}

std::optional<scene::Rgb> trace_radiance(const DropSurface& surface, const Ray& camera_ray,
                                         double mu, const scene::Environment& env,
                                         const TraceOptions& options) {
  scene::Rgb sum{0, 0, 0};
  const auto summary = trace_paths(surface, camera_ray, mu, options, [&](const ExitPath& e) {
    sum += e.weight * env.radiance(e.ray.direction);
  });
  if (!summary.hit) return std::nullopt;
  return sum;
}

}  // namespace hydrolux::drop
