#pragma once
// Riccati-Bessel functions and their logarithmic derivatives, the building blocks of the Mie
// coefficients and the Debye series (conventions of Bohren & Huffman 1983, section 4.8):
//   psi_n(z) = z j_n(z),   chi_n(z) = -z y_n(z),   xi_n(z) = z h_n^(1)(z) = psi_n(z) - i chi_n(z),
//   D_n(z) = psi_n'(z) / psi_n(z).
#include <complex>
#include <span>
#include <vector>

namespace hydrolux::scatter {

using Complex = std::complex<double>;

// D_n(z) for n = 0..n_max, from unnormalised psi_n(z) by their three-term recurrence: upward from
// cos z, sin z where every order lies below the turning point and absorption is weak, else
// downward from the exact ratio at n_max (Lentz's continued fraction, Appl. Opt. 15, 668 (1976),
// about |z| - n_max + 1 iterations when |z| > n_max and z is nearly real, fewer with absorption)
// or, far above the turning point, from an approximate start a few orders higher (Miller).
// Stable for any complex z with |z| > 0 and Im z >= 0 (docs/mie.md). Accuracy (against mpmath):
// within 100 sqrt(L) eps of |D_n| + n/|z|, L = max(n_max, |z|) (1.6e-12 relative at z = 1.5e5);
// near a zero of psi_n (a pole of D_n, nearly real z) the relative error grows with |D_n|.
// DomainError for n_max < 0 ("n_max") or z = 0 or not finite ("abs_z").
std::vector<Complex> log_derivative_psi(Complex z, int n_max);

// psi_n(x) and xi_n(x) for real x > 0 and n = 0..n_max (spans of at least n_max + 1 values;
// Error if shorter, DomainError for x <= 0 or n_max < 0). chi_n = -Im xi_n. Wronskian:
// psi_{n-1} chi_n - psi_n chi_{n-1} = 1. Relative accuracy about sqrt(n) eps on the envelope
// |xi_n| (on psi_n itself where n > x). Far past n ~ x, where chi_n would overflow a double, chi_n
// is +inf (psi_n has underflowed to 0 there), never NaN.
void riccati_bessel(double x, int n_max, std::span<double> psi, std::span<Complex> xi);

}  // namespace hydrolux::scatter
