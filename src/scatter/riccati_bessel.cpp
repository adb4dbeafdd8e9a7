// Riccati-Bessel functions psi_n, chi_n, xi_n and the logarithmic derivative D_n = psi_n' / psi_n.
//
// References:
//   [BH]  C. F. Bohren and D. R. Huffman, "Absorption and Scattering of Light by Small Particles"
//         (Wiley, 1983), section 4.8 and Appendix A (BHMIE).
//   [L76] W. J. Lentz, "Generating Bessel functions in Mie scattering calculations using continued
//         fractions", Appl. Opt. 15, 668-671 (1976).
//   [TB]  I. J. Thompson and A. R. Barnett, "Coulomb and Bessel functions of complex arguments and
//         order", J. Comput. Phys. 64, 490-509 (1986): the modified Lentz algorithm (zero
//         denominators replaced by a tiny number) used below.
//   [W79] W. J. Wiscombe, "Mie scattering calculations: advances in technique and fast,
//         vector-speed computer codes", NCAR/TN-140+STR (1979, revised 1996): why D_n must be
//         recurred downward and psi_n must not be recurred upward past n ~ x.
//   [PP]  O. Pena and U. Pal, "Scattering of electromagnetic radiation by a multilayered sphere",
//         Comput. Phys. Commun. 180, 2348-2354 (2009), the paper of scattnlay, whose
//         evalUpwardPsi computes psi_n from the ratio psi_n / psi_{n-1} = 1 / (D_n + n/x).
//
// Numerical choices (each checked against mpmath in tests/scatter/test_riccati_bessel.cpp):
// - D_n(z), complex z: downward recurrence D_{n-1} = n/z - 1/(D_n + n/z) ([BH] eq. 4.89), which
//   damps errors for every z with Im z >= 0, started at n_max with the exact value of the
//   continued fraction for J_{n-1/2}(z) / J_{n+1/2}(z) ([L76]). Upward recurrence of D_n is
//   unstable for absorbing spheres ([W79]).
// - psi_n(x), real x: upward recurrence psi_{n+1} = (2n+1)/x psi_n - psi_{n-1} from sin x while
//   n <= x, where it is neutrally stable; above x, where it is not, the same D_n(x) in real
//   arithmetic gives psi_{n-1} / psi_n = D_n + n/x, so psi_n = psi_{n-1} / (D_n + n/x) ([PP]).
// - chi_n(x): upward recurrence chi_{n+1} = (2n+1)/x chi_n - chi_{n-1} from chi_0 = cos x,
//   chi_1 = cos x / x + sin x; chi_n is the dominant solution, so the upward direction is stable.
// - k/z in every recurrence uses 1/z carried to twice double precision (InverseReal,
//   InverseComplex below), so that rounding errors add like a random walk, sqrt(n) eps, instead of
//   the systematic n eps that a rounded 1/z would cause.
#include "hydrolux/scatter/riccati_bessel.hpp"
#include "hydrolux/core/complex.hpp"

#include <cmath>
#include <limits>
#include <string>

#include "hydrolux/core/error.hpp"

namespace hydrolux::scatter {

namespace {


// a b without the C99 Annex G inf/nan recovery of the compiler's complex multiply (a library call
// without -ffast-math); the operands here are finite.
inline Complex mul(Complex a, Complex b) noexcept {
  return {a.real() * b.real() - a.imag() * b.imag(), a.real() * b.imag() + a.imag() * b.real()};
}
inline double mul(double a, double b) noexcept { return a * b; }
// |v|^2 without the hypot of std::abs.
inline double abs2(Complex v) noexcept { return std::norm(v); }
inline double abs2(double v) noexcept { return v * v; }

// Stand-in for an exact zero in a denominator (modified Lentz, [TB]).
constexpr double kTiny = 1e-300;

template <typename T>
inline T nonzero(T v) noexcept {
  return v == T(0) ? T(kTiny) : v;
}

// 1/z to about twice double precision, as hi + lo, so that k/z = k hi + k lo is rounded once per
// use. Every recurrence below multiplies by k/z thousands of times; with a plain rounded 1/z its
// relative error delta (up to eps/2) is the same in every step, which is the recurrence for the
// argument z (1 - delta): at |z| = 1e4 that is a phase error of |z| delta ~ 1e-12 in D_n, psi_n
// and chi_n at low orders, growing linearly with |z|. Split, the error per step is random and the
// accumulated error grows only like sqrt(n) eps.
struct InverseReal {
  double hi, lo;
  explicit InverseReal(double x) : hi(1.0 / x), lo(std::fma(-x, hi, 1.0) * hi) {}
  double times(double k) const noexcept { return std::fma(k, hi, k * lo); }
  double value() const noexcept { return hi; }
};
struct InverseComplex {
  Complex hi, lo;
  explicit InverseComplex(Complex z) {
    // 1/z = conj(z) / |z|^2, with |z|^2 and its reciprocal carried as double-doubles (products and
    // sums split exactly by fma and Knuth's two-sum).
    const double a = z.real(), b = z.imag();
    const double p1 = a * a, e1 = std::fma(a, a, -p1);
    const double p2 = b * b, e2 = std::fma(b, b, -p2);
    const double s = p1 + p2, bb = s - p1, e3 = (p1 - (s - bb)) + (p2 - bb);
    const double d_hi = s, d_lo = e1 + e2 + e3;
    const double inv_hi = 1.0 / d_hi;
    const double inv_lo = (std::fma(-d_hi, inv_hi, 1.0) - d_lo * inv_hi) * inv_hi;
    const double re_hi = a * inv_hi, re_lo = std::fma(a, inv_hi, -re_hi) + a * inv_lo;
    const double im_hi = -b * inv_hi, im_lo = std::fma(-b, inv_hi, -im_hi) - b * inv_lo;
    hi = Complex(re_hi, im_hi);
    lo = Complex(re_lo, im_lo);
  }
  Complex times(double k) const noexcept {
    return {std::fma(k, hi.real(), k * lo.real()), std::fma(k, hi.imag(), k * lo.imag())};
  }
  Complex value() const noexcept { return hi; }
};

// D_n(z) from the continued fraction, with zinv = 1/z. With nu = n + 1/2,
//   J_{nu-1}(z) / J_nu(z) = b_0 - 1/(b_1 - 1/(b_2 - ...)),  b_k = 2 (nu + k) / z = (2n+1+2k) / z,
// (from J_{nu-1} + J_{nu+1} = (2 nu / z) J_nu), written with unit partial numerators as
// b_0 + 1/(-b_1 + 1/(b_2 + 1/(-b_3 + ...))) (the form of [L76]), and
//   D_n(z) = J_{n-1/2}(z) / J_{n+1/2}(z) - n/z,
// since psi_n(z) = sqrt(pi z / 2) J_{n+1/2}(z) and J_nu' = J_{nu-1} - (nu/z) J_nu.
// Evaluated forward by the modified Lentz method ([TB]): f_j = f_{j-1} C_j D_j. The fraction
// converges once the depth k passes about |z| - n, so the cost is O(|z| - n + 1) iterations.
template <typename T, typename Inverse>
T log_derivative_continued_fraction(const Inverse& zinv, int n) {
  const double two_n_plus_1 = 2.0 * n + 1.0;
  T f = nonzero(zinv.times(two_n_plus_1));
  T c = f;
  T d = T(0);
  // Converged when two successive factors C_j D_j are within 1e-15 of 1 (two, so that a factor
  // that passes near 1 by chance in the oscillating part of the fraction does not stop it).
  constexpr double kTol = 1e-15;
  const double z_abs = 1.0 / std::abs(zinv.value());
  const long max_iter = 20 * static_cast<long>(z_abs + n) + 10000;
  int hits = 0;
  double sign = -1.0;
  for (long k = 1; k <= max_iter; ++k) {
    const T b = zinv.times(sign * (two_n_plus_1 + 2.0 * static_cast<double>(k)));
    sign = -sign;
    d = reciprocal(nonzero(T(b + d)));
    c = nonzero(T(b + reciprocal(c)));
    const T delta = mul(c, d);
    f = mul(f, delta);
    if (abs2(delta - T(1)) < kTol * kTol) {
      if (++hits == 2) return f - zinv.times(n);
    } else {
      hits = 0;
    }
  }
  throw Error("log_derivative_psi: Lentz continued fraction did not converge for n = " +
              std::to_string(n));
}

// D_{n_low}..D_{n_max} into out[n_low..n_max]: the exact start at n_max, then [BH] eq. 4.89
// downward.
template <typename T, typename Inverse>
void log_derivative_downward(const Inverse& zinv, int n_max, T* out, int n_low = 0) {
  out[n_max] = log_derivative_continued_fraction<T>(zinv, n_max);
  for (int n = n_max; n > n_low; --n) {
    const T n_over_z = zinv.times(n);
    out[n - 1] = n_over_z - reciprocal(nonzero(T(out[n] + n_over_z)));  // Equation (4.89) [BH]
  }
}

void require_n_max(int n_max) {
  if (n_max < 0) throw DomainError("n_max", n_max, 0, std::numeric_limits<int>::max() - 1);
}

}  // namespace

std::vector<Complex> log_derivative_psi(Complex z, int n_max) {
  require_n_max(n_max);
  if (!(std::isfinite(z.real()) && std::isfinite(z.imag())) || std::abs(z) == 0)
    throw DomainError("abs_z", std::abs(z), std::numeric_limits<double>::min(),
                      std::numeric_limits<double>::max(), "log_derivative_psi (z finite, z != 0)");
  std::vector<Complex> d(static_cast<std::size_t>(n_max) + 1);
  if (z.imag() == 0) {
    // Real argument: the same recurrence in real arithmetic (twice as fast, same values).
    std::vector<double> dr(d.size());
    log_derivative_downward(InverseReal(z.real()), n_max, dr.data());
    for (std::size_t i = 0; i < d.size(); ++i) d[i] = dr[i];
  } else {
    log_derivative_downward(InverseComplex(z), n_max, d.data());
  }
  return d;
}

void riccati_bessel(double x, int n_max, std::span<double> psi, std::span<Complex> xi) {
  require_n_max(n_max);
  require_in_range("x", x, std::numeric_limits<double>::min(), std::numeric_limits<double>::max(),
                   "riccati_bessel (x > 0)");
  const auto size = static_cast<std::size_t>(n_max) + 1;
  if (psi.size() < size || xi.size() < size)
    throw Error("riccati_bessel: psi and xi need n_max + 1 = " + std::to_string(size) +
                " elements");
  const InverseReal xinv(x);
  // psi_n for n <= x: upward recurrence from psi_0 = sin x, psi_1 = sin x / x - cos x. Below the
  // turning point n ~ x both solutions oscillate with the same envelope, so rounding errors
  // neither grow nor shrink (they add up like a random walk), exactly as for chi below.
  // psi_n for n > x: D_n(x) downward from n_max into psi[] itself, then
  // psi_n = psi_{n-1} / (D_n + n/x) upward in place (psi[n] still holds D_n when step n reads it),
  // [PP]. Recurring psi itself upward there would amplify rounding by chi_n / psi_n.
  // (The ratio form alone, for every n, is also stable, but its errors at n ~ x are systematic
  // and grow like n eps: 1e-11 at x = 1e5, against 1e-14 for the split.)
  const double s = std::sin(x), c = std::cos(x);
  const int n_up = std::min(n_max, static_cast<int>(std::min(x, 2e9)));
  psi[0] = s;
  if (n_up >= 1) psi[1] = s * xinv.value() - c;
  for (int n = 1; n < n_up; ++n) psi[n + 1] = xinv.times(2 * n + 1) * psi[n] - psi[n - 1];
  if (n_max > n_up) {
    log_derivative_downward(xinv, n_max, psi.data(), n_up + 1);
    for (int n = n_up + 1; n <= n_max; ++n)
      psi[n] = psi[n - 1] / nonzero(psi[n] + xinv.times(n));
  }

  // chi upward; xi_n = psi_n - i chi_n ([BH] section 4.8). chi_n grows like (2n-1)!! / x^n past
  // n ~ x: where it would overflow, the rest is set to +inf (psi_n has underflowed to 0 there),
  // never to inf - inf = NaN.
  double chi_prev = c;  // chi_0
  xi[0] = Complex(s, -chi_prev);
  if (n_max == 0) return;
  double chi = c * xinv.value() + s;  // chi_1
  xi[1] = Complex(psi[1], -chi);
  int n = 1;
  for (; n < n_max; ++n) {
    const double next = xinv.times(2 * n + 1) * chi - chi_prev;
    if (!std::isfinite(next)) break;
    chi_prev = chi;
    chi = next;
    xi[n + 1] = Complex(psi[n + 1], -chi);
  }
  for (++n; n <= n_max; ++n) xi[n] = Complex(psi[n], -std::numeric_limits<double>::infinity());
}

}  // namespace hydrolux::scatter
