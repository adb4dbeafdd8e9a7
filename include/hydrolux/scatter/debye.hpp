#pragma once
// Debye-series decomposition of the Mie coefficients: each partial wave split by the number of
// times the light crosses the sphere's surface (p = 0 diffraction + external reflection, p = 1
// direct transmission, p = 2 one internal reflection / primary rainbow, p = 3 secondary rainbow,
// ...). Equations, derivation and sources: docs/debye.md.
//
// Conventions are those of mie.hpp (Bohren & Huffman 1983, exp(-i omega t), Im m >= 0), so that
// the coefficients returned here go straight into mie_amplitudes_reference / mie_amplitudes and
// give the S1, S2 of the selected orders. In that convention (docs/debye.md, eq. D1-D8)
//
//   a_n = 1/2 [1 - R22_n - sum_{p>=1} T21_n (R11_n)^(p-1) T12_n],
//
// with kappa = 1/m for a_n (TM, electric multipoles) and kappa = m for b_n (TE, magnetic), where
// the partial-wave Fresnel coefficients of the sphere's surface are (x outside, z = m x inside;
// xi1 = xi = psi - i chi is outgoing, xi2 = psi + i chi incoming; D1, D2 their log derivatives)
//   R22 = -[xi2(x)/xi1(x)] [D2(x) - kappa D2(z)] / [D1(x) - kappa D2(z)]   external reflection
//   R11 = -[xi1(z)/xi2(z)] [kappa D1(z) - D1(x)] / [kappa D2(z) - D1(x)]   internal reflection
//   T21 T12 = -4 kappa / {xi1(x)^2 xi2(z)^2 [D1(x) - kappa D2(z)]^2}      in and out again.
// R11 and T21 T12 include the propagation across the sphere (R11 ~ exp(2 i z) for n << |z|), so an
// absorbing sphere damps them. Only the product T21 T12 is physical: each factor alone depends on
// how the internal wave is normalised, and alone would overflow for large Im z.
//
// Numerics (docs/debye.md): only ratios xi_{n-1}/xi_n and products such as xi1/xi2 and 1/xi^2
// (mantissa and power of two) are formed, never a Hankel function itself, so nothing overflows for
// x in [1e-3, 1e5] and Im(m x) up to 1e5; the recurrences run in long double (the products would
// lose ~N ulp in double). 1 - R22 and T21 T12 / (1 - R11) are computed directly, because where a
// partial wave barely touches the sphere R22 and R11 are 1 to within 1e-26 and less.
// Limits of the series itself: for an absorbing m, |R11| can exceed 1 (the orders of that partial
// wave then grow; terms saturate at ~1e304 instead of overflowing), and the orders have poles
// where D1(x) = kappa D2(m x) (exact zeros are replaced by their rounding level).
// Valid domain (DomainError otherwise): x in [1e-3, 1e5] ("x"), Re m in [1e-3, 10] ("m_real"),
// Im m in [0, 1] ("m_imag"), p in [0, 1000] ("p"), n_terms in [0, 1e6] ("n_terms"; 0 means
// mie_terms(x), as for mie_coefficients).
#include <vector>

#include "hydrolux/scatter/mie.hpp"

namespace hydrolux::scatter {

inline constexpr int kMaxDebyeOrder = 1000;

// The partial-wave Fresnel coefficients of one polarisation, for n = 1..N at index n - 1, and
// two combinations that would lose all their digits if formed from them by subtraction (where a
// partial wave barely touches the sphere, R22 and R11 are 1 to within 1e-26 and less).
struct DebyeFresnel {
  std::vector<Complex> r22;            // external reflection R22_n
  std::vector<Complex> r11;            // internal reflection R11_n, one round trip in the sphere
  std::vector<Complex> t21t12;         // transmission in and out, T21_n T12_n
  std::vector<Complex> one_minus_r22;  // 1 - R22_n, computed directly (Equation (D3'))
  // sum_{p>=1} T21 R11^(p-1) T12 = T21 T12 / (1 - R11), computed directly (Equation (D5')).
  std::vector<Complex> transmitted;
};

// The coefficients of both polarisations: `a` (kappa = 1/m) builds a_n, `b` (kappa = m) builds b_n.
struct DebyeInterface {
  Complex m;
  double x = 0;
  DebyeFresnel a, b;
  int terms() const { return static_cast<int>(a.r22.size()); }
};

// R22, R11, T21 T12 (and 1 - R22, T21 T12 / (1 - R11)) for n = 1..N, N = mie_terms(x) when
// n_terms = 0 (the truncation of mie_coefficients). Cost O(N + |m x|): 5-8 ms at x = 1e4, 65-95 ms
// at x = 1e5 (long double recurrences; mie_coefficients takes ~1/6 of that).
DebyeInterface debye_interface(Complex m, double x, int n_terms = 0);

// The a_n, b_n of Debye order p alone (p in [0, 1000]):
//   p = 0: 1/2 (1 - R22);   p >= 1: -1/2 T21 T12 R11^(p-1).
MieCoefficients debye_coefficients(Complex m, double x, int p, int n_terms = 0);
MieCoefficients debye_coefficients(const DebyeInterface& d, int p);

// Orders p_first..p_last summed (0 <= p_first <= p_last <= 1000).
MieCoefficients debye_orders(const DebyeInterface& d, int p_first, int p_last);

// Orders 0..p_max summed.
MieCoefficients debye_sum(Complex m, double x, int p_max, int n_terms = 0);

// All orders p > p_max at once, by the geometric series (p_max in [0, 1000]):
//   sum_{p > P} -1/2 T21 T12 R11^(p-1) = -1/2 T21 T12 R11^P / (1 - R11),
// so debye_sum(P) + debye_remainder(P) is the Mie coefficient for every P. (Computed from the
// stored T21 T12 / (1 - R11), not by subtraction.)
MieCoefficients debye_remainder(Complex m, double x, int p_max, int n_terms = 0);
MieCoefficients debye_remainder(const DebyeInterface& d, int p_max);

// The Mie coefficients rebuilt from the closed form 1/2 [1 - R22 - T21 T12 / (1 - R11)]: all
// orders at once; equal to mie_coefficients (a check of the decomposition).
MieCoefficients debye_closed_form(const DebyeInterface& d);

}  // namespace hydrolux::scatter
