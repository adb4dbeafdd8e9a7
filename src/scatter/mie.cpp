// Lorenz-Mie scattering by a homogeneous sphere: coefficients, efficiencies and the scalar
// reference summation of the amplitudes S1, S2.
//
// References:
//   [BH]  C. F. Bohren and D. R. Huffman, "Absorption and Scattering of Light by Small Particles"
//         (Wiley, 1983), chapter 4 and Appendix A (BHMIE).
//   [W80] W. J. Wiscombe, "Improved Mie scattering algorithms", Appl. Opt. 19, 1505-1509 (1980):
//         the number of terms.
//   [W79] W. J. Wiscombe, "Mie scattering calculations: advances in technique and fast,
//         vector-speed computer codes", NCAR/TN-140+STR (1979, revised 1996), and its code MIEV0:
//         the g series (GQSC) and the test cases used in tests/scatter/test_mie.cpp.
//
// Conventions are those of include/hydrolux/scatter/mie.hpp (B&H: m = n + ik, exp(-i omega t)).
// MIEV0 uses m = n - ik; its amplitudes are the complex conjugates of these.
#include "hydrolux/scatter/mie.hpp"
#include "hydrolux/core/complex.hpp"

#include <algorithm>

#include <cmath>
#include <limits>
#include <string>

#include "hydrolux/core/error.hpp"
#include "hydrolux/scatter/riccati_bessel.hpp"

namespace hydrolux::scatter {

namespace {

constexpr const char* kContext = "the Lorenz-Mie solver";


// a b and a - i b without the C99 Annex G inf/nan recovery of the compiler's complex multiply
// (a library call without -ffast-math); every operand here is finite.
inline Complex mul(Complex a, Complex b) noexcept {
  return {a.real() * b.real() - a.imag() * b.imag(), a.real() * b.imag() + a.imag() * b.real()};
}
inline Complex minus_i_times(Complex a, Complex b) noexcept {
  return {a.real() + b.imag(), a.imag() - b.real()};
}

// An exact zero denominator (psi_n(mx) = 0 exactly, real m) replaced by a tiny number, as the
// downward recurrence of D_n does: the coefficients then take their limit psi_n / xi_n.
inline Complex nonzero(Complex v) noexcept { return v == Complex(0, 0) ? Complex(1e-300, 0) : v; }

void require_size_parameter(double x) {
  require_in_range("x", x, kMinSizeParameter, kMaxSizeParameter, kContext);
}

}  // namespace

int wiscombe_terms(double x) {
  require_size_parameter(x);
  // [W80] p. 1508 (MIEV0 cites it there); the Fortran REAL-to-INTEGER conversion truncates.
  const double cbrt = std::cbrt(x);
  double n = 0;
  if (x <= 8)
    n = x + 4.0 * cbrt + 1.0;
  else if (x < 4200)
    n = x + 4.05 * cbrt + 2.0;
  else
    n = x + 4.0 * cbrt + 2.0;
  return static_cast<int>(n);
}

MieCoefficients mie_coefficients(Complex m, double x, int n_terms) {
  require_size_parameter(x);
  require_in_range("m_real", m.real(), 1e-3, 10.0, kContext);
  require_in_range("m_imag", m.imag(), 0.0, 1.0, kContext);
  require_in_range("n_terms", n_terms, 0, 1e6, kContext);
  const int n_max = n_terms > 0 ? n_terms : wiscombe_terms(x);

  // D_n(mx) downward from an exact continued-fraction start; psi_n(x), xi_n(x) stably
  // (riccati_bessel.cpp). One order past n_max for the ratios T_n below. Three arrays of
  // n_max + 2 values: the only allocations besides a, b.
  const std::vector<Complex> d = log_derivative_psi(m * x, n_max + 1);
  std::vector<double> psi(static_cast<std::size_t>(n_max) + 2);
  std::vector<Complex> xi(psi.size());
  riccati_bessel(x, n_max + 1, psi, xi);

  MieCoefficients c;
  c.m = m;
  c.x = x;
  c.a.resize(static_cast<std::size_t>(n_max));
  c.b.resize(static_cast<std::size_t>(n_max));
  const Complex m_inv = reciprocal(m);
  const Complex one_minus_m2_over_m2 = mul(mul(1.0 - m, 1.0 + m), mul(m_inv, m_inv));  // 1/m^2-1
  const Complex z_inv = reciprocal(m * x);
  const double x_inv = 1.0 / x;
  const auto finite = [](Complex v) { return std::isfinite(v.real()) && std::isfinite(v.imag()); };
  for (int n = 1; n <= n_max; ++n) {
    const auto i = static_cast<std::size_t>(n);
    const double chi = -xi[i].imag(), chi_prev = -xi[i - 1].imag();
    const double n_over_x = n * x_inv;
    // Equation (4.88) [BH]:
    //   a_n = [(D_n(mx)/m + n/x) psi_n - psi_{n-1}] / [(D_n(mx)/m + n/x) xi_n - xi_{n-1}]
    //   b_n = [(m D_n(mx) + n/x) psi_n - psi_{n-1}] / [(m D_n(mx) + n/x) xi_n - xi_{n-1}]
    // With xi = psi - i chi each denominator is its numerator minus i [(...) chi_n - chi_{n-1}].
    const Complex da = mul(d[i], m_inv) + n_over_x;
    const Complex db = mul(m, d[i]) + n_over_x;
    const Complex chi_a = da * chi - chi_prev, chi_b = db * chi - chi_prev;
    if (!finite(chi_a) || !finite(chi_b)) {
      // chi_n(x) (nearly) overflowed, which needs far more terms than x calls for (n_terms):
      // a_n, b_n ~ psi_n / chi_n have underflowed to zero.
      c.a[i - 1] = c.b[i - 1] = Complex(0, 0);
      continue;
    }
    // The numerators, psi_n (D_n(mx)/m - D_n(x)) and psi_n (m D_n(mx) - D_n(x)), are evaluated
    // without their large cancelling terms: with T_n(z) = psi_{n+1}(z) / psi_n(z)
    // = 1 / (D_{n+1}(z) + (n+1)/z), D_n(z) = (n+1)/z - T_n(z), so
    //   a numerator = (n+1)/x (1/m^2 - 1) psi_n + psi_{n+1} - psi_n T_n(mx) / m
    //   b numerator = psi_{n+1} - m psi_n T_n(mx).
    // Written as in (4.88), the b numerator loses digits like 1 / (x^2 |m^2 - 1|) for small x
    // (1e-7 relative at x = 1e-3, m = 1.001); this form loses only the 1 / |m^2 - 1| that the
    // physics itself has. Using the same numerator in the denominator also keeps
    // Re a_n = |a_n|^2 to rounding for real m (no absorption by construction).
    const Complex t = reciprocal(nonzero(d[i + 1] + static_cast<double>(n + 1) * z_inv));  // T_n
    const Complex psi_t = psi[i] * t;
    const Complex num_a = ((n + 1) * x_inv * psi[i]) * one_minus_m2_over_m2 + psi[i + 1] -
                          mul(psi_t, m_inv);
    const Complex num_b = psi[i + 1] - mul(m, psi_t);
    c.a[i - 1] = mul(num_a, reciprocal(minus_i_times(num_a, chi_a)));
    c.b[i - 1] = mul(num_b, reciprocal(minus_i_times(num_b, chi_b)));
  }
  return c;
}

MieEfficiencies mie_efficiencies(const MieCoefficients& c) {
  require_size_parameter(c.x);
  if (c.a.size() != c.b.size()) throw Error("mie_efficiencies: a and b differ in length");
  const int n_max = c.terms();
  // Sums over n ([BH] ch. 4; the g series is MIEV0's GQSC, [W79], equal to [BH] eq. 4.92):
  //   ext  = sum (2n+1) Re(a_n + b_n)
  //   sca  = sum (2n+1) (|a_n|^2 + |b_n|^2)
  //   back = sum (2n+1) (-1)^n (a_n - b_n)
  //   gsca = sum n(n+2)/(n+1) Re(a_n a*_{n+1} + b_n b*_{n+1}) + (2n+1)/(n(n+1)) Re(a_n b*_n)
  double ext = 0, sca = 0, gsca = 0;
  Complex back = 0;
  double sign = -1;  // (-1)^n
  for (int n = 1; n <= n_max; ++n) {
    const Complex an = c.a[static_cast<std::size_t>(n - 1)];
    const Complex bn = c.b[static_cast<std::size_t>(n - 1)];
    const double fn = n, two_n_plus_1 = 2.0 * n + 1.0;
    ext += two_n_plus_1 * (an.real() + bn.real());
    sca += two_n_plus_1 * (std::norm(an) + std::norm(bn));
    back += (sign * two_n_plus_1) * (an - bn);
    sign = -sign;
    gsca += two_n_plus_1 / (fn * (fn + 1)) * (an.real() * bn.real() + an.imag() * bn.imag());
    if (n < n_max) {
      const Complex an1 = c.a[static_cast<std::size_t>(n)];
      const Complex bn1 = c.b[static_cast<std::size_t>(n)];
      gsca += fn * (fn + 2) / (fn + 1) *
              (an.real() * an1.real() + an.imag() * an1.imag() + bn.real() * bn1.real() +
               bn.imag() * bn1.imag());
    }
  }
  const double x2 = c.x * c.x;
  MieEfficiencies q;
  q.qext = 2.0 / x2 * ext;
  q.qsca = 2.0 / x2 * sca;
  // A sphere with real m absorbs nothing: report exactly 0 rather than the rounding-level
  // difference of two sums (|qext - qsca| ~ 1e-15 qext there).
  q.qabs = c.m.imag() == 0 ? 0.0 : q.qext - q.qsca;
  q.qback = std::norm(back) / x2;
  q.g = q.qsca > 0 ? 4.0 / x2 * gsca / q.qsca : 0.0;
  return q;
}

void mie_amplitudes_reference(const MieCoefficients& c, std::span<const double> mu,
                              std::span<Complex> s1, std::span<Complex> s2) {
  if (s1.size() != mu.size() || s2.size() != mu.size())
    throw Error("mie_amplitudes_reference: mu, s1 and s2 differ in length");
  if (c.a.size() != c.b.size()) throw Error("mie_amplitudes_reference: a and b differ in length");
  const int n_max = c.terms();
  for (std::size_t j = 0; j < mu.size(); ++j) {
    const double u = mu[j];
    require_in_range("mu", u, -1.0, 1.0, kContext);
    // Angular functions, Equation (4.47) [BH]: pi_0 = 0, pi_1 = 1,
    //   pi_n = (2n-1)/(n-1) mu pi_{n-1} - n/(n-1) pi_{n-2},  tau_n = n mu pi_n - (n+1) pi_{n-1}.
    double pi_prev = 0, pi = 1;
    Complex sum1 = 0, sum2 = 0;
    for (int n = 1; n <= n_max; ++n) {
      const double fn = n;
      const double tau = fn * u * pi - (fn + 1) * pi_prev;
      const double f = (2 * fn + 1) / (fn * (fn + 1));
      const Complex an = c.a[static_cast<std::size_t>(n - 1)];
      const Complex bn = c.b[static_cast<std::size_t>(n - 1)];
      // Equation (4.74) [BH]
      sum1 += f * (an * pi + bn * tau);
      sum2 += f * (an * tau + bn * pi);
      const double pi_next = ((2 * fn + 1) * u * pi - (fn + 1) * pi_prev) / fn;
      pi_prev = pi;
      pi = pi_next;
    }
    s1[j] = sum1;
    s2[j] = sum2;
  }
}

}  // namespace hydrolux::scatter
