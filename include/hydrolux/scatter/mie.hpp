#pragma once
// Lorenz-Mie scattering of a plane wave by a homogeneous sphere.
//
// Conventions (Bohren & Huffman, "Absorption and Scattering of Light by Small Particles", 1983,
// ch. 4), stated once for all of hydrolux/scatter:
// - m = n + i k is the sphere's index relative to the surrounding medium (k >= 0 absorbing, time
//   dependence exp(-i omega t)); x = 2 pi r n_medium / lambda_vacuum is the size parameter.
// - theta is the scattering angle, 0 = forward; mu = cos(theta).
// - Amplitudes (B&H eq. 4.74): S1 = sum_n (2n+1)/(n(n+1)) (a_n pi_n + b_n tau_n) (perpendicular),
//   S2 = sum_n (2n+1)/(n(n+1)) (a_n tau_n + b_n pi_n) (parallel), so that
//   S1(0) = S2(0) = S(0) = 1/2 sum (2n+1)(a_n + b_n).
// - Efficiencies: Qext = 4/x^2 Re S(0) (optical theorem), Qsca = 2/x^2 sum (2n+1)(|a_n|^2 + |b_n|^2),
//   Qabs = Qext - Qsca, Qback = |sum (2n+1)(-1)^n (a_n - b_n)|^2 / x^2, g = <cos theta>.
// - Intensities i1 = |S1|^2, i2 = |S2|^2, unpolarised i = (i1 + i2)/2; the phase function
//   p(theta) = 4 i / (x^2 Qsca) is normalised to (1/4pi) int p dOmega = 1 (since
//   Qsca = (2/x^2) int_{-1}^{1} i dmu).
#include <complex>
#include <span>
#include <vector>

namespace hydrolux::scatter {

using Complex = std::complex<double>;

// Valid domain of the solvers (DomainError outside): x in [1e-3, 1e5], Re m in [1e-3, 10] (not 1
// exactly is fine), Im m in [0, 1].
inline constexpr double kMinSizeParameter = 1e-3;
inline constexpr double kMaxSizeParameter = 1e5;

// Number of terms: Wiscombe (1980, Appl. Opt. 19, 1505), eq. for the "standard" truncation:
// x + 4 x^(1/3) + 1 (x <= 8), x + 4.05 x^(1/3) + 2 (8 < x < 4200), x + 4 x^(1/3) + 2 (x >= 4200),
// truncated to an integer as MIEV0 does. DomainError for x outside [1e-3, 1e5].
// What it leaves out (tests/scatter/test_mie.cpp, TruncationAndExtraTerms): below 1e-6 relative
// in Qext, Qsca and g and below 2e-6 in Qback once N >= 2 (x >= 0.0147); below 1e-9 in Qext and
// 2e-7 in Qback for x > 1. Below x = 0.0147 it gives N = 1 (MIEV0 used small-particle expansions
// there): Qext and Qback then miss O(x^2) relative (2e-5 at x = 0.0146, absorbing m), and g,
// itself O(x^2), misses the a_1 a_2* term of its own order (it comes out 30% low for m = 1.333).
// Passing n_terms = 3 there converges all of them to rounding.
int wiscombe_terms(double x);

// Mie coefficients a_n, b_n for n = 1..N (stored at index n - 1).
struct MieCoefficients {
  Complex m;
  double x = 0;
  std::vector<Complex> a, b;
  int terms() const { return static_cast<int>(a.size()); }
};

// The coefficients with the Wiscombe truncation (n_terms = 0) or a given number of terms.
// DomainError (quantities "x", "m_real", "m_imag", "n_terms") outside the domain above. Against
// the same truncated series in 45-digit arithmetic (scripts/reference/mie_mpmath.py), the
// efficiencies below are within 1e-13 relative (Qback 1e-10 at x = 1e5) and the amplitudes within
// 2e-10 of |S| at any angle, for x up to 1e5. O(N) time, three work arrays of N + 2 values: about
// 1 ms at x = 1e4 and 10 ms at x = 1e5 on one core (x86-64, g++ -O3).
MieCoefficients mie_coefficients(Complex m, double x, int n_terms = 0);

struct MieEfficiencies {
  double qext = 0, qsca = 0, qabs = 0, qback = 0, g = 0;
};
// Sums over the coefficients (g by the Wiscombe/B&H series in a_n a*_{n+1}, b_n b*_{n+1},
// a_n b*_n). qabs = qext - qsca, and exactly 0 when Im m = 0. g = 0 when qsca = 0 (m = 1).
MieEfficiencies mie_efficiencies(const MieCoefficients& c);

// Scalar reference summation of S1, S2 at the given mu = cos(theta) values (any order, any
// count). The fast path (scatter/amplitudes.hpp) must agree with it. Plain double-precision sums
// over n of the pi_n / tau_n recurrences (B&H eq. 4.47), one angle at a time: O(N) per angle.
// DomainError ("mu") for mu outside [-1, 1]; Error if s1, s2 and mu differ in length.
void mie_amplitudes_reference(const MieCoefficients& c, std::span<const double> mu,
                              std::span<Complex> s1, std::span<Complex> s2);

}  // namespace hydrolux::scatter
