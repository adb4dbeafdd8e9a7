#pragma once
// Complex helpers for the scattering code.
#include <cmath>
#include <complex>

namespace hydrolux {

// 1/z by Smith's algorithm (R. L. Smith, Commun. ACM 5, 435, 1962): two real divisions, no
// overflow for any finite z != 0, and faster than the general complex division the compiler calls
// (__divdc3, with its NaN checks) without -ffast-math.
inline std::complex<double> reciprocal(std::complex<double> z) noexcept {
  const double a = z.real(), b = z.imag();
  if (std::abs(a) >= std::abs(b)) {
    const double r = b / a, d = a + b * r;
    return {1.0 / d, -r / d};
  }
  const double r = a / b, d = b + a * r;
  return {r / d, -1.0 / d};
}
// The real overload, so generic code can call reciprocal on either.
inline double reciprocal(double x) noexcept { return 1.0 / x; }

}  // namespace hydrolux
