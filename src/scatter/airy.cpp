// Airy function and Airy theory of the rainbow; equations in the header and in
// docs/rainbow-theories.md.
#include "hydrolux/scatter/airy.hpp"

#include <cmath>

#include "hydrolux/core/error.hpp"
#include "hydrolux/core/math.hpp"

namespace hydrolux::scatter {

namespace {

constexpr double kPiD = kPi<double>;
// Ai(0) and -Ai'(0) (A&S 10.4.4, 10.4.5): 3^(-2/3) / Gamma(2/3) and 3^(-1/3) / Gamma(1/3).
constexpr double kC1 = 0.355028053887817239260;
constexpr double kC2 = 0.258819403792806798405;
constexpr double kSqrt3 = 1.7320508075688772935;
// Below this |x| the Maclaurin series; beyond, the Bessel forms.
constexpr double kSeriesLimit = 2.0;
// K_nu(zeta) underflows past zeta ~ 705; Ai(x) < 1e-300 there anyway.
constexpr double kMaxZeta = 700.0;

struct AiryPair {
  double ai, aip;
};

// Maclaurin series (A&S 10.4.2-10.4.3): Ai = c1 f - c2 g with
//   f = sum_k a_k x^(3k),      a_0 = 1, a_k = a_{k-1} / ((3k - 1) 3k),
//   g = sum_k b_k x^(3k + 1),  b_0 = 1, b_k = b_{k-1} / (3k (3k + 1)),
// and Ai' = c1 f' - c2 g' term by term.
AiryPair airy_series(double x) {
  const double x3 = x * x * x;
  double f = 1, fp = 0;    // f and f'
  double gs = 1, gp = 1;   // g / x and g'
  double af = 1, bg = 1;   // a_k x^(3k) and b_k x^(3k)
  double dfk = x * x / 6;  // a_k x^(3k-1), starting at k = 1
  for (int k = 1; k < 80; ++k) {
    const double k3 = 3.0 * k;
    af *= x3 / ((k3 - 1) * k3);
    bg *= x3 / (k3 * (k3 + 1));
    if (k > 1) dfk *= x3 / ((k3 - 1) * k3);
    f += af;
    gs += bg;
    fp += k3 * dfk;
    gp += (k3 + 1) * bg;
    if (std::abs(af) <= 1e-17 * std::abs(f) && std::abs(bg) <= 1e-17 * std::abs(gs) &&
        std::abs(k3 * dfk) <= 1e-17 * std::abs(fp) + 1e-300)
      break;
  }
  return {kC1 * f - kC2 * x * gs, kC1 * fp - kC2 * gp};
}

}  // namespace

double airy_ai(double x) {
  if (std::isnan(x)) return x;
  if (std::abs(x) <= kSeriesLimit) return airy_series(x).ai;
  if (x > 0) {
    const double zeta = 2.0 / 3.0 * x * std::sqrt(x);
    if (zeta > kMaxZeta) return 0.0;
    return std::sqrt(x / 3) * std::cyl_bessel_k(1.0 / 3.0, zeta) / kPiD;
  }
  const double z = -x;
  const double zeta = 2.0 / 3.0 * z * std::sqrt(z);
  return 0.5 * std::sqrt(z) *
         (std::cyl_bessel_j(1.0 / 3.0, zeta) - std::cyl_neumann(1.0 / 3.0, zeta) / kSqrt3);
}

double airy_ai_prime(double x) {
  if (std::isnan(x)) return x;
  if (std::abs(x) <= kSeriesLimit) return airy_series(x).aip;
  if (x > 0) {
    const double zeta = 2.0 / 3.0 * x * std::sqrt(x);
    if (zeta > kMaxZeta) return 0.0;
    return -x * std::cyl_bessel_k(2.0 / 3.0, zeta) / (kPiD * kSqrt3);
  }
  const double z = -x;
  const double zeta = 2.0 / 3.0 * z * std::sqrt(z);
  return 0.5 * z *
         (std::cyl_bessel_j(2.0 / 3.0, zeta) + std::cyl_neumann(2.0 / 3.0, zeta) / kSqrt3);
}

namespace {
void check_airy(double n, double x, int p) {
  require_in_range("size_parameter", x, kMinSizeParameter, kMaxGeometricSizeParameter,
                   "Airy theory");
  (void)rainbow_ray(n, p);  // checks p >= 2 and 1 < n < p
}
}  // namespace

double airy_angular_scale(double n, double x, int p) {
  check_airy(n, x, p);
  return std::cbrt(x * x / rainbow_ray(n, p).curvature);
}

double airy_argument(double n, double x, int p, double theta) {
  check_airy(n, x, p);
  require_in_range("theta_rad", theta, 0.0, kPiD, "Airy theory");
  const RainbowRay rb = rainbow_ray(n, p);
  return rb.side * (theta - rb.scattering_angle) * std::cbrt(x * x / rb.curvature);
}

void airy_amplitudes(double n_real, double x, int p, std::span<const double> theta_rad,
                     std::span<Complex> s1, std::span<Complex> s2) {
  check_airy(n_real, x, p);
  const double size = static_cast<double>(theta_rad.size());
  require_in_range("s1_size", static_cast<double>(s1.size()), size, size, "the theta_rad span");
  require_in_range("s2_size", static_cast<double>(s2.size()), size, size, "the theta_rad span");
  const RainbowRay rb = rainbow_ray(n_real, p);
  const Complex m(n_real, 0);
  const RayFresnelFactors eps = ray_fresnel_factors(m, p, rb.theta_i);
  const double scale = std::cbrt(x * x / rb.curvature);  // z per radian
  const double amplitude =
      std::sqrt(2 * kPiD * rb.impact_parameter / std::sin(rb.scattering_angle)) *
      std::pow(x, 7.0 / 6.0) / std::cbrt(rb.curvature);
  const double delta_r =
      2 * x * (p * n_real * std::cos(rb.theta_t) - std::cos(rb.theta_i));  // optical path
  // Focal lines of the inner branch (theta_i just below the rainbow ray, dTheta/dtheta_i < 0).
  const int n_inner = focal_lines(n_real, p, rb.theta_i * (1 - 1e-9));
  const double phase0 = delta_r - kPiD * (n_inner + 1) / 2 - kPiD / 4;
  for (std::size_t i = 0; i < theta_rad.size(); ++i) {
    const double theta = theta_rad[i];
    require_in_range("theta_rad", theta, 0.0, kPiD, "Airy theory");
    const double dtheta = rb.side * (theta - rb.scattering_angle);  // Theta - Theta_R
    const double z = scale * dtheta;
    const Complex common =
        amplitude * airy_ai(-z) * std::exp(Complex(0, phase0 + x * rb.impact_parameter * dtheta));
    s1[i] = eps.perpendicular * common;
    s2[i] = eps.parallel * common;
  }
}

}  // namespace hydrolux::scatter
