#pragma once
// The scalar recurrences behind riccati_bessel.hpp and the Lorenz-Mie solver, exposed to
// mie.cpp without the checks and allocations of the public functions. Each dispatches to the
// SIMD target chosen for this CPU (hydrolux::simd), so that fused multiply-adds are instructions
// on CPUs that have them (the library's baseline, x86-64 without FMA, would call libm's fma).
// Methods and accuracy: riccati_bessel.cpp.
#include <complex>
#include <cstddef>

namespace hydrolux::scatter::detail {

// An order where the unnormalised psi_n(z) of the recurrences was rescaled:
// D_n = 2^shift p[n] / p[n+1] - n/z there (riccati_bessel.cpp).
struct Rescale {
  int n, shift;
};

// The lanes of the chosen SIMD target: the padding the arrays below need.
std::size_t simd_padding();

// Orders the downward recurrence may run above n_max (its approximate start far above the
// turning point): scratch arrays need this many more values.
inline constexpr int kMaxMillerOrders = 32;

// D_n(z) = psi_n'(z)/psi_n(z) for n = 0..n_max into out[2n] (real part), out[2n+1] (imaginary
// part); z != 0. Upward from cos z, sin z where that is stable, else downward from the continued
// fraction at n_max. out: room for n_max + 1 + simd_padding() complex values; scratch: n_max + 2 +
// simd_padding() + kMaxMillerOrders complex values.
void log_derivative(std::complex<double> z, int n_max, double* out, double* scratch);

// The same for real z, real arrays of the same lengths.
void log_derivative_real(double z, int n_max, double* out, double* scratch);

// psi_n(x) and chi_n(x), n = 0..n_max, real x > 0; chi_n = +inf past its overflow (psi_n has
// underflowed to 0 there).
void psi_chi(double x, int n_max, double* psi, double* chi);

}  // namespace hydrolux::scatter::detail
