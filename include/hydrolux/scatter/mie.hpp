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

#include "hydrolux/scatter/size_distribution.hpp"

namespace hydrolux::scatter {

using Complex = std::complex<double>;

// Domain of the Lorenz-Mie solver (DomainError outside; the quantities are named "x", "m_real",
// "m_imag", "m_abs", "n_terms"): x in [1e-6, 1e6]; m = n + ik with n in [0, 1000], k in [0, 1000]
// and |m| >= 1e-3. A negative k is refused with a message saying why (the sign convention), never
// conjugated silently. The accuracy over this domain, range by range, is in docs/mie.md.
inline constexpr double kMieMinSizeParameter = 1e-6;
inline constexpr double kMieMaxSizeParameter = 1e6;
inline constexpr double kMieMinIndex = 1e-3;
inline constexpr double kMieMaxIndex = 1e3;
// The domain of the other wave theories built on the Mie coefficients (Debye series, Airy
// theory) and of the Lee tables: x in [1e-3, 1e5], Re m in [1e-3, 10], Im m in [0, 1].
inline constexpr double kMinSizeParameter = 1e-3;
inline constexpr double kMaxSizeParameter = 1e5;
inline constexpr double kMinIndexReal = 1e-3;
inline constexpr double kMaxIndexReal = 10.0;
inline constexpr double kMaxIndexImag = 1.0;

// Wiscombe's number of terms (1980, Appl. Opt. 19, 1505, p. 1508, as coded in MIEV0):
// x + 4 x^(1/3) + 1 (x <= 8), x + 4.05 x^(1/3) + 2 (8 < x < 4200), x + 4 x^(1/3) + 2 (x >= 4200),
// truncated to an integer. It converges Qext and Qsca, but not Qback (7e-6 relative short at
// x = 1e4) nor g below x = 0.0147 (where it gives one term, and g needs a_2). DomainError for x
// outside the Mie domain.
int wiscombe_terms(double x);

// The number of terms the solver uses by default: x + c x^(1/3) + d with the constants below and
// at least kMieMinTerms, chosen so that every output it returns, Qext, Qsca, Qabs, g, Qback and S1,
// S2 at every angle, relative to the sphere's largest |S| and to |S| at that angle, is within 1e-12
// relative of the infinite series (tests/scatter/test_mie.cpp,
// MieStability.DefaultTruncationLeavesOutLessThan1e12: x = 1e-6 to 1e5, seven indices, measured worst
// 2.4e-13; MieReference.DefaultTruncationIsConverged against mpmath; tests/scatter/test_claims_mie.cpp
// against an independent long-double solver). The minimum is 4, not 3: S2 near 90 degrees, where the
// dipole term vanishes, needs a 4th term for x of about 0.004 to 0.023 (3 leave it 3.3e-11 short at
// x = 0.01, 5e-10 at 0.02). About 0.6% more terms than Wiscombe's at x = 1e4.
inline constexpr double kMieTermsCbrt = 7.0;
inline constexpr double kMieTermsConstant = 2.0;
inline constexpr int kMieMinTerms = 4;
int mie_terms(double x);

// Mie coefficients a_n, b_n for n = 1..N (stored at index n - 1).
struct MieCoefficients {
  Complex m;
  double x = 0;
  std::vector<Complex> a, b;
  int terms() const { return static_cast<int>(a.size()); }
};

// The coefficients with mie_terms(x) terms (n_terms = 0) or a given number of terms (up to 2e7).
// DomainError outside the domain above. Against the same truncated series in 45-digit arithmetic
// (scripts/reference/mie_mpmath.py) the efficiencies are within 1e-13 relative (Qback 1e-10 at
// x = 1e5) and the amplitudes within 2e-10 of |S| at any angle; docs/mie.md lists each range.
// O(N + the continued fraction's depth) time; the working arrays are per thread and reused.
MieCoefficients mie_coefficients(Complex m, double x, int n_terms = 0);
// The same into `out`, reusing its storage (no allocation once it has held as many terms).
void mie_coefficients(Complex m, double x, MieCoefficients& out, int n_terms = 0);

struct MieEfficiencies {
  double qext = 0, qsca = 0, qabs = 0, qback = 0, g = 0;
};
// Sums over the coefficients (g by the Wiscombe/B&H series in a_n a*_{n+1}, b_n b*_{n+1},
// a_n b*_n). qabs = qext - qsca, and exactly 0 when Im m = 0. g = 0 when qsca = 0 (m = 1).
MieEfficiencies mie_efficiencies(const MieCoefficients& c);
// The efficiencies alone, without angles and without keeping the coefficients: the path for size
// averages and extinction. Same terms and accuracy as mie_coefficients; no allocation once the
// thread has solved a sphere as large.
MieEfficiencies mie_efficiencies(Complex m, double x, int n_terms = 0);

// The bulk optics of a population of spheres of one index, through the efficiencies-only path:
// with the quadrature's drops per m^3 w_i at radii a_i and x_i = wavenumber a_i,
//   extinction  = sum w_i pi a_i^2 Qext(x_i)   (m^-1), likewise scattering and absorption;
//   backscatter = sum w_i pi a_i^2 Qback(x_i)  (m^-1; divide by 4 pi for the volume backscattering
//                 coefficient per steradian, B&H's radar convention for Qback);
//   g = sum w_i pi a_i^2 Qsca g_i / scattering  (the scattering-weighted asymmetry parameter).
// wavenumber = 2 pi n_medium / lambda_vacuum (m^-1). Radii in parallel on oneTBB (threads: 0 =
// all cores), summed in a fixed order: the same bits whatever the thread count. DomainError as
// mie_efficiencies for any radius outside the Mie domain ("x").
struct MieBulkOptics {
  double extinction_per_m = 0, scattering_per_m = 0, absorption_per_m = 0, backscatter_per_m = 0,
         g = 0;
};
MieBulkOptics mie_bulk_optics(Complex m, double wavenumber_per_m, const RadiusQuadrature& q,
                              int threads = 0);

// Scalar reference summation of S1, S2 at the given mu = cos(theta) values (any order, any
// count). The fast path (scatter/amplitudes.hpp) must agree with it. Plain double-precision sums
// over n of the pi_n / tau_n recurrences (B&H eq. 4.47), one angle at a time: O(N) per angle.
// DomainError ("mu") for mu outside [-1, 1]; Error if s1, s2 and mu differ in length.
void mie_amplitudes_reference(const MieCoefficients& c, std::span<const double> mu,
                              std::span<Complex> s1, std::span<Complex> s2);

}  // namespace hydrolux::scatter
