// Riccati-Bessel functions psi_n, chi_n, xi_n and the logarithmic derivative D_n = psi_n' / psi_n:
// the public functions of riccati_bessel.hpp over the recurrences of src/scatter/recurrences-inl.h,
// which the Lorenz-Mie solver (mie.cpp) shares. They are compiled once per SIMD target (Highway
// foreach_target) so that their fused multiply-adds are single instructions where the CPU has
// them; they are scalar code otherwise.
//
// References:
//   [BH]  C. F. Bohren and D. R. Huffman, "Absorption and Scattering of Light by Small Particles"
//         (Wiley, 1983), section 4.8 and Appendix A (BHMIE).
//   [L76] W. J. Lentz, "Generating Bessel functions in Mie scattering calculations using continued
//         fractions", Appl. Opt. 15, 668-671 (1976).
//   [TB]  I. J. Thompson and A. R. Barnett, "Coulomb and Bessel functions of complex arguments and
//         order", J. Comput. Phys. 64, 490-509 (1986): the modified Lentz algorithm (zero
//         denominators replaced by a tiny number).
//   [W79] W. J. Wiscombe, "Mie scattering calculations: advances in technique and fast,
//         vector-speed computer codes", NCAR/TN-140+STR (1979, revised 1996), and [W80] Appl. Opt.
//         19, 1505 (1980): when D_n may be recurred upward, and why psi_n must not be recurred
//         upward past n ~ x.
//   [PP]  O. Pena and U. Pal, "Scattering of electromagnetic radiation by a multilayered sphere",
//         Comput. Phys. Commun. 180, 2348-2354 (2009), the paper of scattnlay, whose
//         evalUpwardPsi computes psi_n from the ratio psi_n / psi_{n-1} = 1 / (D_n + n/x).
//   [DLMF] NIST Digital Library of Mathematical Functions, 3.6: Miller's algorithm.
//
// Numerical choices (each checked against mpmath in tests/scatter/test_riccati_bessel.cpp;
// docs/mie.md has the derivations):
// - D_n(z), complex z: unnormalised psi_n(z) by the three-term recurrence
//   psi_{n-1} + psi_{n+1} = (2n+1)/z psi_n (the linear form of [BH] eq. 4.89), then
//   D_n = psi_{n-1}/psi_n - n/z for all orders in SIMD. Upward from cos z, sin z where every order
//   lies below the turning point and absorption is weak ([W80]'s choice, with a derived
//   criterion); else downward, the recessive direction, from the exact ratio at n_max (the
//   continued fraction for J_{n-1/2}(z) / J_{n+1/2}(z), [L76], [TB]) or, far above the turning
//   point, from an approximate start a few orders higher (Miller, [DLMF]). The values are kept
//   within 2^+-300 by rescaling, and the orders where the scale changes are recomputed.
// - psi_n(x), real x: upward recurrence from sin x while n <= x, where it is neutrally stable;
//   above x, where it is not, from D_n(x) downward: psi_n = psi_{n-1} / (D_n + n/x) ([PP]), or
//   for small x by Miller's algorithm scaled to the psi_n found upward.
// - chi_n(x): upward recurrence from chi_0 = cos x, chi_1 = cos x / x + sin x; chi_n is the
//   dominant solution, so the upward direction is stable.
// - k/z in every recurrence uses 1/z carried to twice double precision (InverseReal,
//   InverseComplex), so that rounding errors add like a random walk, sqrt(n) eps, instead of the
//   systematic n eps that a rounded 1/z would cause.
// - 1/w in the ratio recurrences is conj(w) / |w|^2 (one division), falling back to Smith's
//   algorithm (core/complex.hpp) only where |w|^2 would overflow or underflow.

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "src/scatter/riccati_bessel.cpp"  // NOLINT
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

#include "src/scatter/recurrences-inl.h"

HWY_BEFORE_NAMESPACE();
namespace hydrolux::scatter::HWY_NAMESPACE {

void LogDerivativeComplexKernel(double z_re, double z_im, int n_max, double* out, double* scratch) {
  const Cx z(z_re, z_im);
  // std::complex<double> is layout-compatible with double[2].
  LogDerivativeAll(z, InverseComplex(z), n_max, reinterpret_cast<Cx*>(scratch), reinterpret_cast<Cx*>(out));
}

void LogDerivativeRealKernel(double x, int n_max, double* out, double* scratch) {
  LogDerivativeAll(Cx(x, 0), InverseReal(x), n_max, scratch, out);
}

void PsiChiKernel(double x, int n_max, double* psi, double* chi) { PsiChi(x, n_max, psi, chi); }

}  // namespace hydrolux::scatter::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
#include <vector>

#include "hydrolux/scatter/riccati_bessel.hpp"
#include "src/core/simd_dispatch.hpp"
#include "src/scatter/recurrences.hpp"

namespace hydrolux::scatter {

HYDROLUX_SIMD_EXPORT(LogDerivativeComplexKernel);
HYDROLUX_SIMD_EXPORT(LogDerivativeRealKernel);
HYDROLUX_SIMD_EXPORT(PsiChiKernel);

namespace {

// Padding after the arrays the SIMD passes read: at least the lane count of any target (32
// doubles: 2048-bit vectors; HWY_MAX_BYTES is only the last target's here).
constexpr std::size_t kPad = 32;

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
    std::vector<double> dr(d.size() + kPad), scratch(d.size() + 1 + kPad + detail::kMaxMillerOrders);
    HYDROLUX_SIMD_DISPATCH(LogDerivativeRealKernel)(z.real(), n_max, dr.data(), scratch.data());
    for (std::size_t i = 0; i < d.size(); ++i) d[i] = dr[i];
  } else {
    std::vector<Complex> dc(d.size() + kPad), scratch(d.size() + 1 + kPad + detail::kMaxMillerOrders);
    HYDROLUX_SIMD_DISPATCH(LogDerivativeComplexKernel)(z.real(), z.imag(), n_max, reinterpret_cast<double*>(dc.data()),
                                                       reinterpret_cast<double*>(scratch.data()));
    std::copy(dc.begin(), dc.begin() + std::ptrdiff_t(d.size()), d.begin());
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
  std::vector<double> chi(size);
  HYDROLUX_SIMD_DISPATCH(PsiChiKernel)(x, n_max, psi.data(), chi.data());
  // xi_n = psi_n - i chi_n ([BH] section 4.8).
  for (std::size_t n = 0; n < size; ++n) xi[n] = Complex(psi[n], -chi[n]);
}

}  // namespace hydrolux::scatter
#endif  // HWY_ONCE
