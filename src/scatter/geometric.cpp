// Geometric optics with interference for a sphere (van de Hulst 1957, ch. 12). The equations are
// in the header and derived in docs/rainbow-theories.md.
#include "hydrolux/scatter/geometric.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "hydrolux/core/error.hpp"
#include "hydrolux/core/math.hpp"
#include "hydrolux/optics/fresnel.hpp"

namespace hydrolux::scatter {

namespace {

constexpr double kPiD = kPi<double>;
constexpr double kHalfPi = kPiD / 2;
// Targets this close to 0 or pi (rad) are on the symmetry axis (see the header).
constexpr double kAxisTolerance = 1e-9;
// The central ray's focal-line count is the limit theta_i -> 0+, taken at this incidence.
constexpr double kCentralRayLimit = 1e-6;
// Targets this close (rad) to a rainbow's deviation are on the caustic: the computed deviation is
// flat to rounding there, the two rays merge and D is infinite; they are left out.
constexpr double kCausticTolerance = 1e-12;

void check_index(double n) {
  require_in_range("m_real", n, kMinGeometricIndex, kMaxGeometricIndex, "geometric optics");
}
void check_order(int p) { require_in_range("ray_order", p, 0, kMaxRayOrder, "geometric optics"); }
void check_common(Complex m, double x) {
  check_index(m.real());
  require_in_range("m_imag", m.imag(), 0.0, 1.0, "geometric optics");
  require_in_range("size_parameter", x, kMinSizeParameter, kMaxGeometricSizeParameter,
                   "geometric optics");
}
void check_sizes(std::span<const double> theta, std::span<Complex> s1, std::span<Complex> s2) {
  const double n = static_cast<double>(theta.size());
  require_in_range("s1_size", static_cast<double>(s1.size()), n, n, "the theta_rad span");
  require_in_range("s2_size", static_cast<double>(s2.size()), n, n, "the theta_rad span");
}

// sin theta_t and cos theta_t for incidence theta_i on a drop of real index n > 1.
struct Refracted {
  double sin_i, cos_i, sin_t, cos_t, theta_t;
};
Refracted refract(double n, double theta_i) {
  Refracted r;
  r.sin_i = std::sin(theta_i);
  r.cos_i = std::cos(theta_i);
  r.sin_t = r.sin_i / n;
  r.cos_t = std::sqrt((n - r.sin_i) * (n + r.sin_i)) / n;  // sqrt(n^2 - sin^2) / n, no cancellation
  r.theta_t = std::asin(r.sin_t);
  return r;
}

// 2 theta_i - 2 p theta_t, the part of Theta_p (p >= 1) that is small near the axis: computing
// sin Theta from it keeps relative accuracy for the central ray.
double reduced_deviation(double n, int p, double theta_i) {
  return 2 * theta_i - 2 * p * refract(n, theta_i).theta_t;
}

double sin_deviation(double n, int p, double theta_i) {
  if (p == 0) return std::sin(2 * theta_i);  // sin(pi - 2 theta_i)
  const double s = std::sin(reduced_deviation(n, p, theta_i));
  return (p - 1) % 2 == 0 ? s : -s;  // sin(u + (p - 1) pi)
}

// (-i)^k for integer k >= 0, exactly.
Complex minus_i_power(int k) {
  switch (k % 4) {
    case 0:
      return {1, 0};
    case 1:
      return {0, -1};
    case 2:
      return {-1, 0};
    default:
      return {0, 1};
  }
}

// Solve Theta_p(theta_i) = target on [a, b], where Theta_p is monotonic and the target lies
// between its end values: Newton steps kept inside a shrinking bracket, bisection otherwise.
double solve_branch(double n, int p, double a, double b, double target) {
  const double fa = deviation(n, p, a) - target, fb = deviation(n, p, b) - target;
  if (fa == 0) return a;
  if (fb == 0) return b;
  const double sign = fb > fa ? 1.0 : -1.0;  // g = sign * (Theta - target) increases from a to b
  double lo = a, hi = b;
  double t = 0.5 * (a + b);
  for (int it = 0; it < 200; ++it) {
    const double g = sign * (deviation(n, p, t) - target);
    if (g == 0) return t;
    if (g < 0)
      lo = t;
    else
      hi = t;
    const double dg = sign * deviation_derivative(n, p, t);
    double next = dg > 0 ? t - g / dg : 0.5 * (lo + hi);
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    if (std::abs(next - t) <= 1e-16 * std::max(1.0, std::abs(t)) || hi - lo <= 4e-16) return next;
    t = next;
  }
  return t;
}

GeometricRay make_ray(Complex m, double x, int p, double theta_i, bool central) {
  const double n = m.real();
  const Refracted r = refract(n, theta_i);
  GeometricRay ray;
  ray.p = p;
  ray.theta_i = theta_i;
  ray.theta_t = r.theta_t;
  ray.deviation = deviation(n, p, theta_i);
  const double dtheta = deviation_derivative(n, p, theta_i);
  if (central) {
    // sin theta_i / sin theta -> 1 / |dTheta/dtheta_i| as theta_i -> 0 (the axial limit).
    ray.divergence = r.cos_i / (dtheta * dtheta);
  } else {
    ray.divergence =
        r.sin_i * r.cos_i / (std::abs(sin_deviation(n, p, theta_i)) * std::abs(dtheta));
  }
  ray.focal_lines = focal_lines(n, p, theta_i);
  // Optical path relative to the central reference: p chords of length 2 a cos theta_t at index m
  // (complex m: attenuation exp(-2 x Im(m) cos theta_t) per chord, along the ray), less the
  // 2 a cos theta_i saved outside.
  ray.phase_path = 2 * x * (static_cast<double>(p) * r.cos_t * m - r.cos_i);
  const RayFresnelFactors eps = ray_fresnel_factors(m, p, theta_i);
  const Complex common = x * std::sqrt(ray.divergence) * std::exp(Complex(0, 1) * ray.phase_path) *
                         minus_i_power(ray.focal_lines + 1);
  ray.s1 = eps.perpendicular * common;
  ray.s2 = eps.parallel * common;
  return ray;
}

// Rays of one order at theta, without argument checks (callers check once per call).
void rays_at(Complex m, double x, int p, double theta, std::vector<GeometricRay>& out) {
  out.clear();
  const double n = m.real();
  const bool forward_axis = theta < kAxisTolerance;
  const bool backward_axis = theta > kPiD - kAxisTolerance;
  if (forward_axis || backward_axis) {
    // Only the central ray: Theta_p(0) = pi (p = 0) or (p - 1) pi.
    const bool central_backward = p == 0 || (p - 1) % 2 == 1;
    if (central_backward == backward_axis) out.push_back(make_ray(m, x, p, 0.0, true));
    return;
  }
  if (p == 0) {  // Theta_0 = pi - 2 theta_i = theta
    out.push_back(make_ray(m, x, 0, 0.5 * (kPiD - theta), false));
    return;
  }
  // Branches of theta_i on which Theta_p is monotonic.
  std::pair<double, double> branches[2];
  int n_branches = 0;
  double caustic = std::numeric_limits<double>::quiet_NaN();  // Theta at the rainbow ray
  if (p >= 2 && n < p) {
    const double ti_r = std::acos(std::sqrt((n * n - 1) / (static_cast<double>(p) * p - 1)));
    branches[n_branches++] = {0.0, ti_r};
    branches[n_branches++] = {ti_r, kHalfPi};
    caustic = deviation(n, p, ti_r);
  } else {
    branches[n_branches++] = {0.0, kHalfPi};
  }
  for (int k = 0; k < n_branches; ++k) {
    const auto [a, b] = branches[k];
    const double da = deviation(n, p, a), db = deviation(n, p, b);
    const double lo = std::min(da, db), hi = std::max(da, db);
    std::vector<double> roots;
    for (double s : {1.0, -1.0}) {
      const double base = s * theta;
      const auto k_lo = static_cast<long>(std::ceil((lo - base) / (2 * kPiD)));
      const auto k_hi = static_cast<long>(std::floor((hi - base) / (2 * kPiD)));
      for (long j = k_lo; j <= k_hi; ++j) {
        const double target = base + 2 * kPiD * static_cast<double>(j);
        if (target < lo || target > hi) continue;
        if (std::abs(target - caustic) <= kCausticTolerance) continue;
        roots.push_back(solve_branch(n, p, a, b, target));
      }
    }
    std::sort(roots.begin(), roots.end());
    for (double ti : roots) {
      if (deviation_derivative(n, p, ti) == 0) continue;  // on the caustic (see above)
      out.push_back(make_ray(m, x, p, ti, false));
    }
  }
}

}  // namespace

double deviation(double n, int p, double theta_i) {
  if (p == 0) return kPiD - 2 * theta_i;
  return reduced_deviation(n, p, theta_i) + (p - 1) * kPiD;
}

double deviation_derivative(double n, int p, double theta_i) {
  if (p == 0) return -2.0;
  const Refracted r = refract(n, theta_i);
  return 2 - 2 * p * r.cos_i / (n * r.cos_t);
}

RayFresnelFactors ray_fresnel_factors(Complex m, int p, double theta_i) {
  check_order(p);
  require_in_range("theta_i_rad", theta_i, 0.0, kHalfPi, "geometric optics");
  const auto f = optics::fresnel_amplitudes(std::cos(theta_i), 1.0, m);
  if (p == 0) return {f.r_s, f.r_p};
  // t t' = 1 - r^2 and r' = -r (Stokes relations, Hecht section 4.10).
  auto factor = [p](Complex r) {
    Complex power = 1.0;  // (-r)^(p-1) by repeated products: exact signs for real r
    for (int k = 1; k < p; ++k) power *= -r;
    return (1.0 - r * r) * power;
  };
  return {factor(f.r_s), factor(f.r_p)};
}

int focal_lines(double n, int p, double theta_i) {
  if (p == 0) return 0;  // reflection from a convex surface: a virtual focus only
  const double ti = std::max(theta_i, kCentralRayLimit);
  const Refracted r = refract(n, ti);
  // Tangential (meridional) focal lines: one on each chord inside the drop except where the
  // neighbouring rays' exit points move backwards around the circle, and one outside when the
  // emerging rays converge; the count reduces to p - [dTheta/dtheta_i < 0].
  const int tangential = p - (deviation_derivative(n, p, ti) < 0 ? 1 : 0);
  // Axial (sagittal) focal lines: each chord from surface angle psi_{k-1} to psi_k = theta_i +
  // k (pi - 2 theta_t) crosses the axis when it passes a multiple of pi; the emerging ray crosses
  // it once more when it heads to the other side of the axis from its exit point.
  const double psi = ti + p * (kPiD - 2 * r.theta_t);
  int axial = static_cast<int>(std::floor(psi / kPiD));
  const double exit_x = std::sin(psi);
  const double direction_x = -sin_deviation(n, p, ti);  // the ray's direction is -Theta_p
  if (exit_x * direction_x < 0) ++axial;
  return tangential + axial;
}

std::vector<GeometricRay> geometric_rays(Complex m, double x, int p, double theta) {
  check_common(m, x);
  check_order(p);
  require_in_range("theta_rad", theta, 0.0, kPiD, "geometric optics");
  std::vector<GeometricRay> rays;
  rays_at(m, x, p, theta, rays);
  return rays;
}

void geometric_amplitudes_order(Complex m, double x, int p, std::span<const double> theta_rad,
                                std::span<Complex> s1, std::span<Complex> s2) {
  check_common(m, x);
  check_order(p);
  check_sizes(theta_rad, s1, s2);
  std::vector<GeometricRay> rays;
  for (std::size_t i = 0; i < theta_rad.size(); ++i) {
    require_in_range("theta_rad", theta_rad[i], 0.0, kPiD, "geometric optics");
    rays_at(m, x, p, theta_rad[i], rays);
    Complex a1 = 0, a2 = 0;
    for (const auto& r : rays) {
      a1 += r.s1;
      a2 += r.s2;
    }
    s1[i] = a1;
    s2[i] = a2;
  }
}

void geometric_amplitudes(Complex m, double x, int p_max, std::span<const double> theta_rad,
                          std::span<Complex> s1, std::span<Complex> s2, bool diffraction) {
  check_common(m, x);
  check_order(p_max);
  check_sizes(theta_rad, s1, s2);
  std::vector<GeometricRay> rays;
  for (std::size_t i = 0; i < theta_rad.size(); ++i) {
    const double theta = theta_rad[i];
    require_in_range("theta_rad", theta, 0.0, kPiD, "geometric optics");
    Complex a1 = 0, a2 = 0;
    if (diffraction) a1 = a2 = fraunhofer_amplitude(x, theta);
    for (int p = 0; p <= p_max; ++p) {
      rays_at(m, x, p, theta, rays);
      for (const auto& r : rays) {
        a1 += r.s1;
        a2 += r.s2;
      }
    }
    s1[i] = a1;
    s2[i] = a2;
  }
}

Complex fraunhofer_amplitude(double x, double theta) {
  require_in_range("size_parameter", x, kMinSizeParameter, kMaxGeometricSizeParameter,
                   "Fraunhofer diffraction");
  require_in_range("theta_rad", theta, 0.0, kPiD, "Fraunhofer diffraction");
  if (theta > kHalfPi) return 0.0;
  const double u = x * std::sin(theta);
  // J1(u) / u = 1/2 - u^2/16 + u^4/384 - ... (A&S 9.1.10) where the quotient would lose digits.
  const double j1_over_u = u < 1e-4 ? 0.5 - u * u / 16 : std::cyl_bessel_j(1.0, u) / u;
  return x * x * j1_over_u;
}

RainbowRay rainbow_ray(double n, int p) {
  require_in_range("ray_order", p, 2, kMaxRayOrder, "a rainbow (p >= 2)");
  require_in_range("m_real", n, kMinGeometricIndex, std::min(kMaxGeometricIndex, p - 1e-9),
                   "a rainbow of this order (1 < n < p)");
  RainbowRay rb;
  rb.p = p;
  rb.n = n;
  const double pp = static_cast<double>(p) * p;
  const double cos2 = (n * n - 1) / (pp - 1);  // Descartes
  rb.theta_i = std::acos(std::sqrt(cos2));
  rb.impact_parameter = std::sqrt((pp - n * n) / (pp - 1));
  rb.theta_t = std::asin(rb.impact_parameter / n);
  rb.deviation = deviation(n, p, rb.theta_i);
  const double reduced = std::fmod(rb.deviation, 2 * kPiD);  // deviation > 0 here
  rb.side = reduced <= kPiD ? 1 : -1;
  rb.scattering_angle = reduced <= kPiD ? reduced : 2 * kPiD - reduced;
  rb.curvature = (pp - 1) * (pp - 1) * std::sqrt(pp - n * n) / (pp * std::pow(n * n - 1, 1.5));
  return rb;
}

double rainbow_angle(double n, int p) { return rainbow_ray(n, p).scattering_angle; }

}  // namespace hydrolux::scatter
