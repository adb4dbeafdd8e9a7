#pragma once
// Microfacet normal distributions (Trowbridge-Reitz / GGX and Beckmann), the Smith masking and
// shadowing functions, and sampling of the distribution of visible normals.
//
// Conventions (those of core/vec.hpp and of the BSDFs in bsdf.hpp):
// - Local shading frame, macro-surface normal +z. Directions are unit vectors pointing AWAY from
//   the surface. Microfacet normals wm lie in the upper hemisphere (wm.z > 0); D(wm) = 0 below.
// - Anisotropic roughness (alpha_x, alpha_y) along the frame's x and y axes; alpha is the slope
//   scale of the distribution (no "roughness to alpha" remapping anywhere in hydrolux: callers pass
//   alpha). Isotropic is alpha_x = alpha_y.
// - A direction w below the surface (w.z < 0) is treated through its mirror -w: Lambda, G1 and the
//   projected area depend on |cos theta| only, and D_visible(w, wm) and sample_visible_normal(w)
//   use the normals seen from -w. This is what a two-sided interface (a dielectric seen from
//   inside) needs; see bsdf.hpp.
//
// Equations (D normalised so that the projected microfacet area is one, int D cos_m dwm = 1):
//   Trowbridge-Reitz (Walter et al. 2007 eq. 33, written anisotropically as in Heitz 2014):
//     D(wm) = 1 / (pi ax ay (x^2/ax^2 + y^2/ay^2 + z^2)^2)            with wm = (x, y, z)
//     Lambda(w) = (sqrt(1 + alpha(phi)^2 tan^2 theta) - 1) / 2    (Heitz 2014, Smith Lambda of GGX)
//   Beckmann (Walter et al. 2007 eq. 25):
//     D(wm) = exp(-(x^2/ax^2 + y^2/ay^2) / z^2) / (pi ax ay z^4)
//     Lambda(w) = (erf(a) - 1) / 2 + exp(-a^2) / (2 a sqrt(pi)),  a = 1 / (alpha(phi) tan theta)
//     (Walter et al. 2007 eq. 26 for G1 = 1 / (1 + Lambda); Heitz 2014, Smith Lambda of Beckmann)
//     This is the EXACT Smith Lambda of the Beckmann distribution. Walter et al. 2007's rational
//     approximation of G1 (eq. 27) is NOT used anywhere: with the exact form the distribution of
//     visible normals integrates to one to rounding, which the chi-square tests rely on.
//   with alpha(phi)^2 tan^2 theta = (ax^2 x^2 + ay^2 y^2) / z^2 for w = (x, y, z) (Heitz 2014:
//   the anisotropic Lambda is the isotropic one at the projected roughness alpha(phi)).
//   Smith masking G1(w) = 1 / (1 + Lambda(w)); height-correlated masking-shadowing
//   G(wo, wi) = 1 / (1 + Lambda(wo) + Lambda(wi)) (Heitz 2014 eq. 99).
//   Projected area of the microsurface seen from w: A(w) = |cos theta| (1 + Lambda(w)); written in
//   closed forms that stay finite at grazing angles (A -> alpha sin theta / 2 for GGX,
//   alpha sin theta / (2 sqrt(pi)) for Beckmann).
//   Distribution of visible normals (Heitz 2014; Heitz & d'Eon 2014):
//     D_w(wm) = G1(w) max(0, w.wm) D(wm) / |cos theta| = max(0, w.wm) D(wm) / A(w)
//   which integrates to one over wm for every w (the identity behind Heitz 2014's weak white
//   furnace test: int G1(w) max(0, w.wm) D(wm) dwm = |cos theta|).
//
// Sampling of visible normals:
//   GGX: Heitz 2018, "Sampling the GGX Distribution of Visible Normals", JCGT 7(4): stretch w to
//   the alpha = 1 configuration, sample the projected hemisphere (a disk, warped on its lower
//   half), unstretch the normal. Beckmann: Heitz & d'Eon 2014, "Importance Sampling
//   Microfacet-Based BSDFs using the Distribution of Visible Normals", EGSR: in the stretched
//   (alpha = 1) configuration with w at polar angle theta in the xz plane, the visible slopes (x,
//   y) (wm = normalize(-x, -y, 1)) are independent: y is Gaussian with density exp(-y^2)/sqrt(pi);
//   x has density proportional to (cot theta - x) exp(-x^2) on x < cot theta, with the normalised
//   CDF
//     C(x) = [c (1 + erf x) / 2 + exp(-x^2) / (2 sqrt(pi))] / [c (1 + Lambda)],  c = cot theta,
//   inverted here by a safeguarded Newton-bisection iteration (erfc in the left tail).
//
// All functions are pure, allocation-free and noexcept; no function returns NaN for a unit w and
// alpha in [kMinAlpha, kMaxAlpha]. Lambda returns +infinity at exactly grazing w (cos theta = 0),
// its true limit; G1 and G are then 0 and A(w) and D_w stay finite.
#include <cmath>
#include <glm/vec2.hpp>
#include <limits>
#include <numbers>

#include "hydrolux/core/error.hpp"
#include "hydrolux/core/math.hpp"
#include "hydrolux/core/vec.hpp"

namespace hydrolux::optics {

// Range of alpha the library accepts (validated by MicrofacetDistribution's factories): down to
// nearly specular, up to far rougher than any physical surface.
inline constexpr double kMinAlpha = 1e-5;
inline constexpr double kMaxAlpha = 10.0;

// ------------------------------------------------------------------------------------------------
// Inverse error function
// ------------------------------------------------------------------------------------------------

namespace detail {

// Giles 2010 ("Approximating the erfinv function", GPU Computing Gems Jade ed., ch. 10),
// single-precision branch: erf^-1(y) for y in [0, 1) to a relative error of a few 1e-7 while
// 1 - y > 1e-7 (w = -ln((1 - y)(1 + y)) < 16); beyond, a rough guess. w is passed in because the
// caller needs it too.
inline double erf_inv_giles(double y, double w) noexcept {
  double p;
  if (w < 5.0) {
    w -= 2.5;
    p = 2.81022636e-08;
    p = 3.43273939e-07 + p * w;
    p = -3.5233877e-06 + p * w;
    p = -4.39150654e-06 + p * w;
    p = 0.00021858087 + p * w;
    p = -0.00125372503 + p * w;
    p = -0.00417768164 + p * w;
    p = 0.246640727 + p * w;
    p = 1.50140941 + p * w;
  } else {
    w = std::sqrt(w) - 3.0;
    p = -0.000200214257;
    p = 0.000100950558 + p * w;
    p = 0.00134934322 + p * w;
    p = -0.00367342844 + p * w;
    p = 0.00573950773 + p * w;
    p = -0.0076224613 + p * w;
    p = 0.00943887047 + p * w;
    p = 1.00167406 + p * w;
    p = 2.83297682 + p * w;
  }
  return p * y;
}

// The unrefined guess for any y in [-1, 1] (+-inf at +-1): a starting point for root finders.
inline double erf_inv_guess(double y) noexcept {
  const double a = std::abs(y);
  if (!(a < 1.0)) return std::copysign(std::numeric_limits<double>::infinity(), y);
  return std::copysign(erf_inv_giles(a, -std::log((1.0 - a) * (1.0 + a))), y);
}

}  // namespace detail

// erf^-1(y) for y in (-1, 1); -inf / +inf at y = -1 / +1 (and beyond). Initial guess: the
// single-precision approximation of Giles 2010 (detail::erf_inv_giles), refined by a Halley step on
// std::erf / std::erfc (Newton steps on ln erfc in the far tail), which brings it to a few ulp in
// double; near |y| = 1, 1 - |y| keeps its digits.
template <typename Float>
inline Float erf_inv(Float y) noexcept {
  if (y < 0) return -erf_inv(-y);
  if (!(y < Float(1))) return y == y ? std::numeric_limits<Float>::infinity() : y;  // NaN stays
  if (y == 0) return Float(0);
  const double yd = static_cast<double>(y);
  const double w0 = -std::log((1.0 - yd) * (1.0 + yd));
  double x = detail::erf_inv_giles(yd, w0);
  const double two_over_sqrt_pi = 2.0 / std::sqrt(std::numbers::pi);
  if (w0 < 16.0 || yd < 0.5) {
    // One Halley step on g(x) = erf(x) - y (g' = 2/sqrt(pi) exp(-x^2), g'' = -2 x g'): cubic
    // convergence takes the guess (relative error < 1e-6 here) to rounding. For y >= 1/2 the
    // residual is (1 - y) - erfc(x), 1 - y being exact there (Sterbenz's lemma).
    const double g = yd < 0.5 ? std::erf(x) - yd : (1.0 - yd) - std::erfc(x);
    const double newton = g / (two_over_sqrt_pi * std::exp(-x * x));
    x -= newton / (1.0 + x * newton);
  } else {
    // Far tail (1 - y < 1e-7, beyond the range the guess was fitted on): Newton on
    // h(x) = ln(erfc(x) / (1 - y)), nearly linear there, until it stops moving.
    const double t = 1.0 - yd;
    for (int i = 0; i < 8; ++i) {
      const double e = std::erfc(x);
      if (!(e > 0)) break;
      const double step = std::log(e / t) / (-two_over_sqrt_pi * std::exp(-x * x) / e);
      if (!std::isfinite(step)) break;
      x -= step;
      if (std::abs(step) <= 1e-15 * x) break;
    }
  }
  return static_cast<Float>(x);
}

// ------------------------------------------------------------------------------------------------
// Shared pieces
// ------------------------------------------------------------------------------------------------

namespace detail {

// alpha(phi)^2 sin^2 theta = ax^2 x^2 + ay^2 y^2: the squared projected roughness of w times its
// squared sine (Heitz 2014, anisotropic Smith Lambda).
template <typename Float>
constexpr Float alpha2_sin2(const Vec3T<Float>& w, Float ax, Float ay) noexcept {
  return sqr(ax * w.x) + sqr(ay * w.y);
}

// w with its z made non-negative by mirroring through the origin (see the header comment).
template <typename Float>
constexpr Vec3T<Float> upper(const Vec3T<Float>& w) noexcept {
  return w.z < 0 ? -w : w;
}

// CRTP base: everything that follows from D, Lambda and the projected area.
template <typename Derived, typename Float>
class MicrofacetBase {
 public:
  // Smith masking, G1(w) = 1 / (1 + Lambda(w)).
  Float G1(const Vec3T<Float>& w) const noexcept {
    return Float(1) / (Float(1) + self().lambda(w));
  }
  // Height-correlated masking-shadowing, Heitz 2014 eq. 99.
  Float G(const Vec3T<Float>& wo, const Vec3T<Float>& wi) const noexcept {
    return Float(1) / (Float(1) + self().lambda(wo) + self().lambda(wi));
  }
  // Distribution of visible normals D_w(wm) = max(0, w'.wm) D(wm) / A(w), w' = w mirrored to the
  // upper hemisphere (Heitz 2014). A density over wm in solid angle.
  Float D_visible(const Vec3T<Float>& w, const Vec3T<Float>& wm) const noexcept {
    const Float c = glm::dot(upper(w), wm);
    if (!(c > 0)) return Float(0);
    return c * self().D(wm) / self().projected_area(w);
  }

 private:
  const Derived& self() const noexcept { return static_cast<const Derived&>(*this); }
};

}  // namespace detail

// ------------------------------------------------------------------------------------------------
// Trowbridge-Reitz (GGX)
// ------------------------------------------------------------------------------------------------

template <typename Float>
class TrowbridgeReitzDistribution
    : public detail::MicrofacetBase<TrowbridgeReitzDistribution<Float>, Float> {
 public:
  // Precondition: alpha_x, alpha_y in [kMinAlpha, kMaxAlpha] (see MicrofacetDistribution).
  constexpr TrowbridgeReitzDistribution(Float alpha_x, Float alpha_y) noexcept
      : ax_(alpha_x), ay_(alpha_y) {}
  constexpr Float alpha_x() const noexcept { return ax_; }
  constexpr Float alpha_y() const noexcept { return ay_; }

  // D(wm) = 1 / (pi ax ay (x^2/ax^2 + y^2/ay^2 + z^2)^2): the usual
  // 1 / (pi ax ay cos^4 (1 + tan^2 (cos^2 phi/ax^2 + sin^2 phi/ay^2))^2) multiplied through by
  // cos^4, so that nothing divides by cos theta.
  Float D(const Vec3T<Float>& wm) const noexcept {
    if (!(wm.z > 0)) return Float(0);
    const Float s = sqr(wm.x / ax_) + sqr(wm.y / ay_) + sqr(wm.z);
    return Float(1) / (kPi<Float> * ax_ * ay_ * s * s);
  }

  // Lambda(w) = (sqrt(1 + t) - 1) / 2 with t = alpha(phi)^2 tan^2 theta, evaluated as
  // t2 / (2 |c| (|c| + sqrt(c^2 + t2))) with t2 = t c^2 (no cancellation at small t, +inf at c =
  // 0).
  Float lambda(const Vec3T<Float>& w) const noexcept {
    const Float t2 = detail::alpha2_sin2(w, ax_, ay_);
    if (t2 == 0) return Float(0);
    const Float c = std::abs(w.z);
    return t2 / (Float(2) * c * (c + std::sqrt(c * c + t2)));
  }

  // A(w) = |cos theta| (1 + Lambda(w)) = (|c| + sqrt(c^2 + alpha(phi)^2 sin^2 theta)) / 2.
  Float projected_area(const Vec3T<Float>& w) const noexcept {
    const Float c = std::abs(w.z);
    return (c + std::sqrt(c * c + detail::alpha2_sin2(w, ax_, ay_))) / Float(2);
  }

  // A visible normal of w (of -w if w.z < 0), distributed as D_visible(w, .), from u1, u2 in
  // [0, 1). Heitz 2018, JCGT 7(4), Listing 1 / §4.
  Vec3T<Float> sample_visible_normal(const Vec3T<Float>& w, Float u1, Float u2) const noexcept {
    // 1. Stretch the view direction to the alpha = 1 configuration.
    Vec3T<Float> wh = glm::normalize(Vec3T<Float>(ax_ * w.x, ay_ * w.y, w.z));
    if (wh.z < 0) wh = -wh;
    // 2. Orthonormal basis (t1, t2, wh) with t1 horizontal.
    const Float len2 = wh.x * wh.x + wh.y * wh.y;
    const Vec3T<Float> t1 =
        len2 > 0 ? Vec3T<Float>(-wh.y, wh.x, 0) / std::sqrt(len2) : Vec3T<Float>(1, 0, 0);
    const Vec3T<Float> t2 = glm::cross(wh, t1);
    // 3. Uniform point on the unit disk; the lower half is squeezed to the projection of the
    //    visible hemisphere (a half ellipse of height wh.z).
    const Float r = std::sqrt(u1);
    const Float phi = Float(2) * kPi<Float> * u2;
    const Float p1 = r * std::cos(phi);
    Float p2 = r * std::sin(phi);
    const Float s = (Float(1) + wh.z) / Float(2);
    p2 = (Float(1) - s) * safe_sqrt(Float(1) - p1 * p1) + s * p2;
    // 4. Lift onto the hemisphere around wh.
    const Vec3T<Float> nh = p1 * t1 + p2 * t2 + safe_sqrt(Float(1) - p1 * p1 - p2 * p2) * wh;
    // 5. Unstretch (normals transform with the inverse transpose of the stretch).
    return glm::normalize(Vec3T<Float>(ax_ * nh.x, ay_ * nh.y, std::max(Float(0), nh.z)));
  }

 private:
  Float ax_, ay_;
};

// ------------------------------------------------------------------------------------------------
// Beckmann
// ------------------------------------------------------------------------------------------------

template <typename Float>
class BeckmannDistribution : public detail::MicrofacetBase<BeckmannDistribution<Float>, Float> {
 public:
  // Precondition: alpha_x, alpha_y in [kMinAlpha, kMaxAlpha] (see MicrofacetDistribution).
  constexpr BeckmannDistribution(Float alpha_x, Float alpha_y) noexcept
      : ax_(alpha_x), ay_(alpha_y) {}
  constexpr Float alpha_x() const noexcept { return ax_; }
  constexpr Float alpha_y() const noexcept { return ay_; }

  // D(wm) = exp(-tan^2 theta (cos^2 phi/ax^2 + sin^2 phi/ay^2)) / (pi ax ay cos^4 theta).
  Float D(const Vec3T<Float>& wm) const noexcept {
    if (!(wm.z > 0)) return Float(0);
    const Float c2 = wm.z * wm.z;
    const Float c4 = c2 * c2;
    if (!(c4 > 0)) return Float(0);  // cos^4 underflows only where exp(-tan^2/alpha^2) is 0
    const Float e = (sqr(wm.x / ax_) + sqr(wm.y / ay_)) / c2;
    return std::exp(-e) / (kPi<Float> * ax_ * ay_ * c4);
  }

  // Exact Smith Lambda, a = |cos theta| / (alpha(phi) sin theta) (Walter et al. 2007 eq. 26), as
  // (exp(-a^2) / (a sqrt(pi)) - erfc(a)) / 2 so that erf(a) - 1 does not cancel for large a.
  Float lambda(const Vec3T<Float>& w) const noexcept {
    const Float s = std::sqrt(detail::alpha2_sin2(w, ax_, ay_));
    if (s == 0) return Float(0);
    const Float c = std::abs(w.z);
    if (c == 0) return std::numeric_limits<Float>::infinity();
    const Float a = c / s;
    if (a > Float(30)) return Float(0);  // both terms underflow (exp(-900))
    const Float l = (std::exp(-a * a) / (a * kSqrtPi) - std::erfc(a)) / Float(2);
    return std::max(Float(0), l);
  }

  // A(w) = |cos theta| (1 + Lambda) = c (1 + erf a) / 2 + alpha(phi) sin theta exp(-a^2) / (2 sqrt
  // pi): finite at grazing (c = 0) and exactly c at normal incidence.
  Float projected_area(const Vec3T<Float>& w) const noexcept {
    const Float s = std::sqrt(detail::alpha2_sin2(w, ax_, ay_));
    const Float c = std::abs(w.z);
    if (s == 0) return c;
    const Float a = c / s;
    return c * (Float(1) - std::erfc(a) / Float(2)) + s * std::exp(-a * a) / (Float(2) * kSqrtPi);
  }

  // A visible normal of w (of -w if w.z < 0), distributed as D_visible(w, .). Heitz & d'Eon 2014:
  // stretch, sample the visible slopes of the alpha = 1 distribution, rotate, unstretch.
  Vec3T<Float> sample_visible_normal(const Vec3T<Float>& w, Float u1, Float u2) const noexcept {
    Vec3T<Float> ws = glm::normalize(Vec3T<Float>(ax_ * w.x, ay_ * w.y, w.z));
    if (ws.z < 0) ws = -ws;
    const Float sin_t = std::sqrt(ws.x * ws.x + ws.y * ws.y);
    const Float cos_p = sin_t > 0 ? ws.x / sin_t : Float(1);
    const Float sin_p = sin_t > 0 ? ws.y / sin_t : Float(0);
    const glm::vec<2, Float> s11 = sample_visible_slopes_11(ws.z, sin_t, u1, u2);
    // Rotate back to the azimuth of ws, then unstretch the slopes.
    const Float x = ax_ * (cos_p * s11.x - sin_p * s11.y);
    const Float y = ay_ * (sin_p * s11.x + cos_p * s11.y);
    return glm::normalize(Vec3T<Float>(-x, -y, Float(1)));
  }

  // Visible slopes of the isotropic alpha = 1 Beckmann distribution for a direction at polar angle
  // theta (given as cos, sin) in the xz plane. Public for tests.
  static glm::vec<2, Float> sample_visible_slopes_11(Float cos_t, Float sin_t, Float u1,
                                                     Float u2) noexcept {
    constexpr Float kEps = std::numeric_limits<Float>::epsilon();
    // y: Gaussian of variance 1/2, y = erf^-1(2 u2 - 1), kept finite at u2 = 0.
    const Float slope_y =
        erf_inv(std::clamp(Float(2) * u2 - Float(1), Float(-1) + kEps, Float(1) - kEps));
    const Float u = std::clamp(u1, kEps, Float(1) - kEps);
    const Float c = cos_t / sin_t;  // cot theta, +inf at normal incidence
    if (!(c < Float(1e150))) {
      // Normal incidence (or closer to it than matters): (c - x) is constant, x is Gaussian too.
      return {erf_inv(Float(2) * u - Float(1)), slope_y};
    }
    return {invert_slope_x_cdf(c, u), slope_y};
  }

  // Solves C(x) = u for the x slope (see the header comment), c = cot theta >= 0, u in (0, 1).
  // Unnormalised CDF F(x) = c erfc(-x) / 2 + exp(-x^2) / (2 sqrt(pi)), F' = (c - x) exp(-x^2) /
  // sqrt(pi); F(c) = c (1 + Lambda). Both terms of F are positive (c >= 0): no cancellation, and
  // erfc keeps the left tail's relative accuracy. Newton steps, with bisection whenever a step
  // leaves the bracket [lo, hi] that the signs of F - u F(c) have established.
  static Float invert_slope_x_cdf(Float c, Float u) noexcept {
    const Float F_c = c * std::erfc(-c) / Float(2) + std::exp(-c * c) / (Float(2) * kSqrtPi);
    // (c large enough for exp(-c^2) to underflow takes the c > 1 branch below.)
    const Float target = u * F_c;
    // Bracket: F(-9) < 1e-36 F(c) for every c >= 0, below any u this function is given.
    Float lo = Float(-9);
    Float hi = c;
    // Initial guess from the exact inverse of an approximation of F:
    //   large c: (c - x) ~ c, F ~ c erfc(-x) / 2: a Gaussian quantile;
    //   small c, lower part: the exp(-x^2) term dominates, exp(-x^2) / (2 sqrt(pi)) = u F(c) gives
    //     x_lo = -sqrt(-ln(2 sqrt(pi) u F(c))) (exact at c = 0);
    //   small c, upper part: near x = c the density is ~ (c - x) exp(-c^2) / sqrt(pi), so
    //     F(c) - F(x) ~ (c - x)^2 exp(-c^2) / (2 sqrt(pi)) = (1 - u) F(c) gives x_hi.
    //   The lower guess is used for u below a split that grows with the share r of the exp term
    //   in F(c) (all of it at c = 0). This keeps Newton to 2-4 steps on average.
    Float x;
    if (c > Float(1)) {
      x = static_cast<Float>(detail::erf_inv_guess(
          static_cast<double>(std::min(Float(2) * target / c - Float(1), Float(1)))));
      // There c erfc(-x) / 2 = u F(c), so F(x) - u F(c) is just the dropped exp term and a Newton
      // step costs no erfc: x -= (exp(-x^2) / (2 sqrt pi)) / ((c - x) exp(-x^2) / sqrt pi).
      if (x < c) x -= Float(1) / (Float(2) * (c - x));
    } else {
      const Float e_c = std::exp(-c * c);
      const Float q = Float(2) * kSqrtPi * target;
      const Float r = e_c / (Float(2) * kSqrtPi * F_c);
      if (q < Float(1) && u < Float(0.2) + Float(0.8) * r) {
        x = -std::sqrt(-std::log(q));
      } else {
        x = c - std::sqrt(Float(2) * kSqrtPi * (Float(1) - u) * F_c / e_c);
      }
    }
    if (!(x > lo && x < hi)) x = (lo + hi) / Float(2);
    // Converged when F matches to 1e-13 relative or the Newton step is below 1e-11 (after which
    // the quadratic convergence leaves an error far below rounding), or 64 ulp where Float is
    // coarser than double; at most ~60 steps if every one bisects.
    constexpr Float kUlp = std::numeric_limits<Float>::epsilon();
    constexpr Float kResidualTol = std::max(Float(1e-13), Float(64) * kUlp);
    constexpr Float kStepTol = std::max(Float(1e-11), Float(64) * kUlp);
    for (int it = 0; it < 100; ++it) {
      const Float e = std::exp(-x * x);
      const Float g = c * std::erfc(-x) / Float(2) + e / (Float(2) * kSqrtPi) - target;
      if (std::abs(g) <= kResidualTol * target) break;
      if (g > 0) {
        hi = x;
      } else {
        lo = x;
      }
      const Float dg = (c - x) * e / kSqrtPi;
      Float xn = dg > 0 ? x - g / dg : lo;  // lo: forces the bisection below
      if (!(xn > lo && xn < hi)) xn = (lo + hi) / Float(2);
      const bool done = std::abs(xn - x) <= kStepTol * (Float(1) + std::abs(x));
      x = xn;
      if (done || hi - lo <= std::numeric_limits<Float>::epsilon() * (Float(1) + std::abs(x))) {
        break;
      }
    }
    return x;
  }

 private:
  static constexpr Float kSqrtPi = Float(1.772453850905516027298167483341145183L);
  Float ax_, ay_;
};

// ------------------------------------------------------------------------------------------------
// Run-time choice of distribution (what the BSDFs hold)
// ------------------------------------------------------------------------------------------------

enum class MicrofacetModel { TrowbridgeReitz, Beckmann };

// A distribution chosen at run time: a tag and two alphas; every call dispatches with a switch
// (no virtual call, no allocation). The factories validate alpha; the methods are noexcept.
class MicrofacetDistribution {
 private:
  // Calls fn with the concrete distribution (defined first: the members below deduce its type).
  template <typename Fn>
  auto dispatch(Fn&& fn) const noexcept {
    if (model_ == MicrofacetModel::TrowbridgeReitz)
      return fn(TrowbridgeReitzDistribution<double>(ax_, ay_));
    return fn(BeckmannDistribution<double>(ax_, ay_));
  }

 public:
  // Throws DomainError unless alpha_x, alpha_y are in [kMinAlpha, kMaxAlpha].
  static MicrofacetDistribution trowbridge_reitz(double alpha_x, double alpha_y) {
    return {MicrofacetModel::TrowbridgeReitz, alpha_x, alpha_y};
  }
  static MicrofacetDistribution beckmann(double alpha_x, double alpha_y) {
    return {MicrofacetModel::Beckmann, alpha_x, alpha_y};
  }
  static MicrofacetDistribution make(MicrofacetModel model, double alpha_x, double alpha_y) {
    return {model, alpha_x, alpha_y};
  }

  MicrofacetModel model() const noexcept { return model_; }
  double alpha_x() const noexcept { return ax_; }
  double alpha_y() const noexcept { return ay_; }

  double D(const Vec3& wm) const noexcept {
    return dispatch([&](const auto& d) { return d.D(wm); });
  }
  double lambda(const Vec3& w) const noexcept {
    return dispatch([&](const auto& d) { return d.lambda(w); });
  }
  double projected_area(const Vec3& w) const noexcept {
    return dispatch([&](const auto& d) { return d.projected_area(w); });
  }
  double G1(const Vec3& w) const noexcept { return 1.0 / (1.0 + lambda(w)); }
  double G(const Vec3& wo, const Vec3& wi) const noexcept {
    return 1.0 / (1.0 + lambda(wo) + lambda(wi));
  }
  double D_visible(const Vec3& w, const Vec3& wm) const noexcept {
    return dispatch([&](const auto& d) { return d.D_visible(w, wm); });
  }
  Vec3 sample_visible_normal(const Vec3& w, double u1, double u2) const noexcept {
    return dispatch([&](const auto& d) { return d.sample_visible_normal(w, u1, u2); });
  }

 private:
  MicrofacetDistribution(MicrofacetModel model, double alpha_x, double alpha_y)
      : model_(model), ax_(alpha_x), ay_(alpha_y) {
    require_in_range("alpha_x", alpha_x, kMinAlpha, kMaxAlpha, "microfacet distribution");
    require_in_range("alpha_y", alpha_y, kMinAlpha, kMaxAlpha, "microfacet distribution");
  }

  MicrofacetModel model_;
  double ax_, ay_;
};

}  // namespace hydrolux::optics
