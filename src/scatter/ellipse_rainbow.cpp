// The plane-section rainbow of an oblate drop: see hydrolux/scatter/ellipse_rainbow.hpp.
#include "hydrolux/scatter/ellipse_rainbow.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "hydrolux/core/error.hpp"
#include "hydrolux/core/math.hpp"
#include "hydrolux/optics/fresnel.hpp"
#include "hydrolux/scatter/airy.hpp"

namespace hydrolux::scatter {

namespace {
constexpr double kPiD = kPi<double>;
}  // namespace

EllipseSection spheroid_section(double q, const Vec3& axis, double sun_elevation, double position) {
  require_in_range("axis_ratio", q, 1e-3, 1.0, "a spheroid's axis ratio");
  const double e = sun_elevation;
  const Vec3 along(0, -std::sin(e), std::cos(e));  // the light's direction
  const Vec3 up(0, std::cos(e), std::sin(e));       // towards the top of the bow, normal to `along`
  const Vec3 right(1, 0, 0);
  const Vec3 side = std::cos(position) * up + std::sin(position) * right;  // the plane's Y
  const Vec3 normal = glm::cross(along, side);
  const Vec3 s = glm::normalize(axis);
  const Vec3 in_plane = s - glm::dot(s, normal) * normal;
  const double cos_beta = glm::length(in_plane);  // the axis's angle to the plane is beta
  const double equatorial = std::cbrt(1 / q), polar = q * equatorial;
  EllipseSection sec;
  sec.semi_v = equatorial;
  if (cos_beta < 1e-12) {  // the axis normal to the plane: the section is the equator, a circle
    sec.semi_u = equatorial;
    return sec;
  }
  const double sin2_beta = std::max(0.0, 1 - cos_beta * cos_beta);
  sec.semi_u = 1 / std::sqrt(cos_beta * cos_beta / (polar * polar) + sin2_beta / (equatorial * equatorial));
  const Vec3 t = in_plane / cos_beta;
  sec.tilt = std::atan2(glm::dot(t, side), glm::dot(t, along));
  return sec;
}

namespace {

struct V2 {
  double x, y;
};
V2 operator+(V2 a, V2 b) { return {a.x + b.x, a.y + b.y}; }
V2 operator*(double s, V2 a) { return {s * a.x, s * a.y}; }
double dot(V2 a, V2 b) { return a.x * b.x + a.y * b.y; }

// The ellipse in its own axes: u along (cu, su), v along (-su, cu).
struct Frame {
  double a, b, cu, su;
  V2 local(V2 p) const { return {p.x * cu + p.y * su, -p.x * su + p.y * cu}; }
  V2 world(V2 p) const { return {p.x * cu - p.y * su, p.x * su + p.y * cu}; }
  // The outward unit normal at a point of the ellipse.
  V2 normal(V2 p) const {
    const V2 l = local(p);
    const V2 g = world({l.x / (a * a), l.y / (b * b)});
    const double len = std::hypot(g.x, g.y);
    return {g.x / len, g.y / len};
  }
  // The roots of |o + t d|_ellipse = 1 (t0 <= t1); false when the line misses.
  bool roots(V2 o, V2 d, double& t0, double& t1) const {
    const V2 lo = local(o), ld = local(d);
    const double ia2 = 1 / (a * a), ib2 = 1 / (b * b);
    const double A = ld.x * ld.x * ia2 + ld.y * ld.y * ib2;
    const double B = 2 * (lo.x * ld.x * ia2 + lo.y * ld.y * ib2);
    const double C = lo.x * lo.x * ia2 + lo.y * lo.y * ib2 - 1;
    const double disc = B * B - 4 * A * C;
    if (disc < 0) return false;
    const double qq = -0.5 * (B + std::copysign(std::sqrt(disc), B));
    const double r0 = qq / A, r1 = qq != 0 ? C / qq : -B / (2 * A);
    t0 = std::min(r0, r1);
    t1 = std::max(r0, r1);
    return true;
  }
};

}  // namespace

namespace {

// The trace; the Fresnel factors only when asked (the rainbow ray's search needs the directions).
template <bool kPower>
SectionRay trace(double n, int p, const Frame& f, double reach, double b) {
  SectionRay ray;
  V2 o{-reach, b}, d{1, 0};
  double t0, t1;
  if (!f.roots(o, d, t0, t1)) return ray;
  V2 at = o + t0 * d;
  // Entry, from air into the drop.
  V2 nrm = f.normal(at);
  double cos_i = std::clamp(-dot(d, nrm), 0.0, 1.0);
  const double eta = 1 / n;
  double ps = 1, pp = 1;
  if constexpr (kPower) {
    const auto in = optics::fresnel_dielectric(cos_i, 1.0, n);
    ps = in.T_s;
    pp = in.T_p;
  }
  const double cos_t = std::sqrt(std::max(0.0, 1 - eta * eta * (1 - cos_i * cos_i)));
  d = eta * d + (eta * cos_i - cos_t) * nrm;
  for (int k = 0; k < p; ++k) {
    // The far side along d (the near root is the point the ray starts from).
    if (!f.roots(at, d, t0, t1)) return ray;
    ray.path += t1;
    at = at + t1 * d;
    nrm = f.normal(at);
    cos_i = std::clamp(dot(d, nrm), 0.0, 1.0);
    if (k + 1 < p) {  // an internal reflection
      if constexpr (kPower) {
        const auto fr = optics::fresnel_dielectric(cos_i, n, 1.0);
        ps *= fr.R_s;
        pp *= fr.R_p;
      }
      d = d + (-2 * dot(d, nrm)) * nrm;
    } else {  // leaving
      const double s2 = n * n * (1 - cos_i * cos_i);
      if (s2 >= 1) return ray;  // totally reflected
      const double cos_out = std::sqrt(1 - s2);
      if constexpr (kPower) {
        const auto fr = optics::fresnel_dielectric(cos_i, n, 1.0);
        ps *= fr.T_s;
        pp *= fr.T_p;
      }
      d = n * d + (cos_out - n * cos_i) * nrm;
    }
  }
  const double len = std::hypot(d.x, d.y);
  ray.exits = true;
  ray.out_x = d.x / len;
  ray.out_y = d.y / len;
  ray.power_perpendicular = ps;
  ray.power_parallel = pp;
  return ray;
}

Frame frame_of(const EllipseSection& e) { return {e.semi_u, e.semi_v, std::cos(e.tilt), std::sin(e.tilt)}; }
double reach_of(const EllipseSection& e) { return 4 * std::max(e.semi_u, e.semi_v); }

}  // namespace

SectionRay trace_section(double n, int p, const EllipseSection& e, double b) {
  return trace<true>(n, p, frame_of(e), reach_of(e), b);
}

namespace {

// The scattering angle of the ray at height b when it leaves on the observer's side (out_y < 0).
std::optional<double> angle_at(double n, int p, const Frame& f, double reach, double b) {
  const SectionRay r = trace<false>(n, p, f, reach, b);
  if (!r.exits || !(r.out_y < 0)) return std::nullopt;
  return std::acos(std::clamp(r.out_x, -1.0, 1.0));
}

}  // namespace

std::optional<SectionRainbow> section_rainbow(double n, int p, const EllipseSection& e) {
  // The side of the extremum from the sphere's rainbow of the same order: a minimum of theta for
  // the primary (rays at larger angles), a maximum for the secondary.
  const int side = rainbow_ray(n, p).side;
  const Frame fr = frame_of(e);
  const double reach = reach_of(e);
  const double half = std::sqrt(sqr(e.semi_u * std::sin(e.tilt)) + sqr(e.semi_v * std::cos(e.tilt)));
  // A coarse scan for the extremal sample among rays on the observer's side, then golden-section
  // refinement inside the bracket of its neighbours. The scan is fine enough that a fold between
  // neighbours is not missed for the flattening of rain drops (the deviation's extremum is broad).
  constexpr int kScan = 96;
  std::array<double, kScan> ang{};
  std::array<bool, kScan> ok{};
  const auto b_of = [&](int i) { return half * (-1 + (2 * i + 1) / double(kScan)); };
  int best = -1;
  for (int i = 0; i < kScan; ++i) {
    const auto a = angle_at(n, p, fr, reach, b_of(i));
    ok[std::size_t(i)] = a.has_value();
    ang[std::size_t(i)] = a.value_or(0);
  }
  for (int i = 1; i + 1 < kScan; ++i) {
    const auto u = std::size_t(i);
    if (!ok[u] || !ok[u - 1] || !ok[u + 1]) continue;
    const double v = side * ang[u];
    if (v <= side * ang[u - 1] && v <= side * ang[u + 1] && (best < 0 || v < side * ang[std::size_t(best)])) best = i;
  }
  if (best < 0) return std::nullopt;
  const auto f = [&](double b) {
    const auto a = angle_at(n, p, fr, reach, b);
    return a ? side * *a : 1e300;
  };
  double lo = b_of(best - 1), hi = b_of(best + 1);
  const double g = (std::sqrt(5.0) - 1) / 2;
  double c = hi - g * (hi - lo), d = lo + g * (hi - lo);
  double fc = f(c), fd = f(d);
  while (hi - lo > 1e-9 * half) {
    if (fc < fd) {
      hi = d;
      d = c;
      fd = fc;
      c = hi - g * (hi - lo);
      fc = f(c);
    } else {
      lo = c;
      c = d;
      fc = fd;
      d = lo + g * (hi - lo);
      fd = f(d);
    }
  }
  SectionRainbow r;
  r.p = p;
  r.side = side;
  r.impact = 0.5 * (lo + hi);
  const SectionRay ray = trace_section(n, p, e, r.impact);
  r.scattering_angle = std::acos(std::clamp(ray.out_x, -1.0, 1.0));
  // q from central second differences at steps h and h / 2, Richardson-extrapolated (their
  // truncation errors, ~h^2 theta^(4) / 12, differ by a factor 4): h = 2e-4 of the half-width keeps
  // the rounding (~1e-15 rad / (h / 2)^2) near 1e-7 of q and the remaining truncation (h^4) below
  // it, also for the secondary, whose rainbow ray lies near grazing incidence.
  const double h = 2e-4 * half;
  const auto second = [&](double step) {
    const double fm = f(r.impact - step), f0 = f(r.impact), fp = f(r.impact + step);
    return (fm > 1e299 || fp > 1e299) ? std::nan("") : 0.5 * (fm - 2 * f0 + fp) / (step * step);
  };
  r.curvature = (4 * second(0.5 * h) - second(h)) / 3;
  if (!(r.curvature > 0)) return std::nullopt;
  r.power_perpendicular = ray.power_perpendicular;
  r.power_parallel = ray.power_parallel;
  r.path = ray.path;
  return r;
}

SectionAiry section_airy(const SectionRainbow& r, double x, double kappa) {
  require_in_range("size_parameter", x, kMinSizeParameter, kMaxGeometricSizeParameter, "Airy theory");
  require_in_range("m_imag", kappa, 0.0, kMaxIndexImag, "Airy theory");
  SectionAiry a;
  a.theta_r = r.scattering_angle;
  a.side = r.side;
  a.scale = std::cbrt(x * x / r.curvature);
  const double amplitude = std::sqrt(2 * kPiD * std::abs(r.impact) / std::sin(r.scattering_angle)) *
                           std::pow(x, 7.0 / 6.0) / std::cbrt(r.curvature) * std::exp(-x * kappa * r.path);
  a.weight_perpendicular = r.power_perpendicular * amplitude * amplitude;
  a.weight_parallel = r.power_parallel * amplitude * amplitude;
  return a;
}

double section_airy_intensity(const SectionAiry& a, double theta) {
  const double ai = airy_ai_fast(-a.scale * a.side * (theta - a.theta_r));
  return 0.5 * (a.weight_perpendicular + a.weight_parallel) * ai * ai;
}

}  // namespace hydrolux::scatter
