// Airy function and Airy theory of the rainbow; equations in the header and in
// docs/rainbow-theories.md.
#include "hydrolux/scatter/airy.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "hydrolux/core/error.hpp"
#include "hydrolux/core/math.hpp"

namespace hydrolux::scatter {

namespace {

// Ai(0) and -Ai'(0) (A&S 10.4.4, 10.4.5): 3^(-2/3) / Gamma(2/3) and 3^(-1/3) / Gamma(1/3).
constexpr double kC1 = 0.355028053887817239260;
constexpr double kC2 = 0.258819403792806798405;
constexpr double kSqrt3 = std::numbers::sqrt3;
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

// Ai (or Ai' with `derivative`): the Maclaurin series near 0, beyond it the Bessel forms (A&S
// 10.4.14-10.4.17) of zeta = 2/3 |x|^(3/2).
double airy(double x, bool derivative) {
  if (std::isnan(x)) return x;
  if (std::abs(x) <= kSeriesLimit) return derivative ? airy_series(x).aip : airy_series(x).ai;
  const double z = std::abs(x);
  const double zeta = 2.0 / 3.0 * z * std::sqrt(z);
  if (x > 0) {
    if (zeta > kMaxZeta) return 0.0;
    if (derivative) return -x * std::cyl_bessel_k(2.0 / 3.0, zeta) / (kPi<> * kSqrt3);
    return std::sqrt(x / 3) * std::cyl_bessel_k(1.0 / 3.0, zeta) / kPi<>;
  }
  if (derivative) return 0.5 * z * (std::cyl_bessel_j(2.0 / 3.0, zeta) + std::cyl_neumann(2.0 / 3.0, zeta) / kSqrt3);
  return 0.5 * std::sqrt(z) * (std::cyl_bessel_j(1.0 / 3.0, zeta) - std::cyl_neumann(1.0 / 3.0, zeta) / kSqrt3);
}

}  // namespace

double airy_ai(double x) { return airy(x, false); }

double airy_ai_prime(double x) { return airy(x, true); }

namespace {

// Ai and Ai' tabulated on [kTableLo, kTableHi] every 1/128 for airy_ai_fast.
constexpr double kTableLo = -16.0, kTableHi = 12.0, kTableStep = 1.0 / 128;
struct AiryTable {
  std::vector<double> ai, aip;
  AiryTable() {
    const int n = int((kTableHi - kTableLo) / kTableStep) + 1;
    ai.resize(n);
    aip.resize(n);
    for (int i = 0; i < n; ++i) {
      ai[i] = airy_ai(kTableLo + i * kTableStep);
      aip[i] = airy_ai_prime(kTableLo + i * kTableStep);
    }
  }
};

}  // namespace

double airy_ai_fast(double x) {
  static const AiryTable table;
  if (std::isnan(x)) return x;
  if (x >= kTableHi) return 0.0;  // Ai(12) = 1.1e-11
  if (x <= kTableLo) {
    // A&S 10.4.60 with zeta = (2/3) z^(3/2) >= 42.7: four terms leave < 2e-8 relative.
    const double z = -x, zeta = 2.0 / 3.0 * z * std::sqrt(z), iz = 1 / zeta, iz2 = iz * iz;
    const double p = 1 - 0.0371335390946502 * iz2, q = iz * (0.0694444444444444 - 0.0379930650255432 * iz2);
    const double phase = zeta + kPi<> / 4;
    return (std::sin(phase) * p - std::cos(phase) * q) / (std::sqrt(kPi<>) * std::sqrt(std::sqrt(z)));
  }
  // Cubic Hermite from Ai and Ai' at the two nodes around x.
  const double pos = (x - kTableLo) / kTableStep;
  const std::size_t i = std::min(std::size_t(pos), table.ai.size() - 2);
  const double t = pos - double(i), h = kTableStep;
  const double t2 = t * t, t3 = t2 * t;
  return (2 * t3 - 3 * t2 + 1) * table.ai[i] + (t3 - 2 * t2 + t) * h * table.aip[i] +
         (-2 * t3 + 3 * t2) * table.ai[i + 1] + (t3 - t2) * h * table.aip[i + 1];
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
  require_in_range("theta_rad", theta, 0.0, kPi<>, "Airy theory");
  const RainbowRay rb = rainbow_ray(n, p);
  return rb.side * (theta - rb.scattering_angle) * std::cbrt(x * x / rb.curvature);
}

AiryRainbow airy_rainbow(double n_real, double x, int p, double kappa) {
  check_airy(n_real, x, p);
  require_in_range("m_imag", kappa, 0.0, kMaxIndexImag, "Airy theory");
  AiryRainbow a;
  a.ray = rainbow_ray(n_real, p);
  a.x = x;
  a.eps = ray_fresnel_factors(Complex(n_real, 0), p, a.ray.theta_i);
  a.scale = std::cbrt(x * x / a.ray.curvature);  // z per radian
  // Weak absorption (van de Hulst 1957 section 14.2, as geometric.hpp): the rainbow ray's amplitude
  // decays as exp(-2 x kappa cos theta_t) along each of its p chords.
  a.amplitude = std::sqrt(2 * kPi<> * a.ray.impact_parameter / std::sin(a.ray.scattering_angle)) *
                std::pow(x, 7.0 / 6.0) / std::cbrt(a.ray.curvature) *
                std::exp(-2.0 * p * x * kappa * std::cos(a.ray.theta_t));
  const double delta_r =
      2 * x * (p * n_real * std::cos(a.ray.theta_t) - std::cos(a.ray.theta_i));  // optical path
  // Focal lines of the inner branch (theta_i just below the rainbow ray, dTheta/dtheta_i < 0).
  const int n_inner = focal_lines(n_real, p, a.ray.theta_i * (1 - 1e-9));
  a.phase0 = delta_r - kPi<> * (n_inner + 1) / 2 - kPi<> / 4;
  return a;
}

double airy_intensity(const AiryRainbow& a, double theta) {
  const double z = a.scale * a.ray.side * (theta - a.ray.scattering_angle);
  const double ai = airy_ai_fast(-z);
  return 0.5 * (std::norm(a.eps.perpendicular) + std::norm(a.eps.parallel)) * a.amplitude * a.amplitude * ai * ai;
}

void airy_amplitudes(double n_real, double x, int p, std::span<const double> theta_rad,
                     std::span<Complex> s1, std::span<Complex> s2) {
  const AiryRainbow a = airy_rainbow(n_real, x, p);
  const double size = static_cast<double>(theta_rad.size());
  require_in_range("s1_size", static_cast<double>(s1.size()), size, size, "the theta_rad span");
  require_in_range("s2_size", static_cast<double>(s2.size()), size, size, "the theta_rad span");
  for (std::size_t i = 0; i < theta_rad.size(); ++i) {
    const double theta = theta_rad[i];
    require_in_range("theta_rad", theta, 0.0, kPi<>, "Airy theory");
    const double dtheta = a.ray.side * (theta - a.ray.scattering_angle);  // Theta - Theta_R
    const Complex common = a.amplitude * airy_ai(-a.scale * dtheta) *
                           std::exp(Complex(0, a.phase0 + x * a.ray.impact_parameter * dtheta));
    s1[i] = a.eps.perpendicular * common;
    s2[i] = a.eps.parallel * common;
  }
}

}  // namespace hydrolux::scatter
