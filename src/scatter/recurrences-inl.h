// The scalar recurrences behind riccati_bessel.hpp and the Lorenz-Mie solver, compiled once per
// SIMD target: included by riccati_bessel.cpp (the public functions) and mie.cpp (the solver, which
// inlines them into one dispatched kernel). Highway's per-target include guard: this file is read
// again for each target. Methods, references and accuracy: riccati_bessel.cpp.
#if defined(HYDROLUX_SCATTER_RECURRENCES_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef HYDROLUX_SCATTER_RECURRENCES_INL_H_
#undef HYDROLUX_SCATTER_RECURRENCES_INL_H_
#else
#define HYDROLUX_SCATTER_RECURRENCES_INL_H_
#endif

#include <hwy/highway.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <complex>
#include <cstdint>
#include <limits>
#include <string>
#include <type_traits>
#include <vector>

#include "hydrolux/core/complex.hpp"
#include "hydrolux/core/error.hpp"
#include "src/scatter/recurrences.hpp"

HWY_BEFORE_NAMESPACE();
namespace hydrolux::scatter::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

using Cx = std::complex<double>;

// a b without the C99 Annex G inf/nan recovery of the compiler's complex multiply (a library call
// without -ffast-math); the operands here are finite.
inline Cx mul(Cx a, Cx b) noexcept {
  return {std::fma(a.real(), b.real(), -a.imag() * b.imag()),
          std::fma(a.real(), b.imag(), a.imag() * b.real())};
}
inline double mul(double a, double b) noexcept { return a * b; }
// |v|^2 without the hypot of std::abs.
inline double abs2(Cx v) noexcept { return std::fma(v.real(), v.real(), v.imag() * v.imag()); }
inline double abs2(double v) noexcept { return v * v; }

// 1/w: conj(w) / |w|^2 with one division, or Smith's algorithm where |w|^2 leaves the normal
// range (never in the recurrences' usual values, which stay within about 1e+-40).
inline Cx recip(Cx w) noexcept {
  const double d = abs2(w);
  if (d > 1e-290 && d < 1e290) {
    const double inv = 1.0 / d;
    return {w.real() * inv, -w.imag() * inv};
  }
  return reciprocal(w);
}
inline double recip(double w) noexcept { return 1.0 / w; }

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
  Cx hi, lo;
  explicit InverseComplex(Cx z) {
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
    hi = Cx(re_hi, im_hi);
    lo = Cx(re_lo, im_lo);
  }
  Cx times(double k) const noexcept {
    return {std::fma(k, hi.real(), k * lo.real()), std::fma(k, hi.imag(), k * lo.imag())};
  }
  Cx value() const noexcept { return hi; }
};

// D_n(z) from the continued fraction, with zinv = 1/z. With nu = n + 1/2,
//   J_{nu-1}(z) / J_nu(z) = b_0 - 1/(b_1 - 1/(b_2 - ...)),  b_k = 2 (nu + k) / z = (2n+1+2k) / z,
// (from J_{nu-1} + J_{nu+1} = (2 nu / z) J_nu), written with unit partial numerators as
// b_0 + 1/(-b_1 + 1/(b_2 + 1/(-b_3 + ...))) (the form of [L76]), and
//   D_n(z) = J_{n-1/2}(z) / J_{n+1/2}(z) - n/z,
// since psi_n(z) = sqrt(pi z / 2) J_{n+1/2}(z) and J_nu' = J_{nu-1} - (nu/z) J_nu.
// Evaluated forward by the modified Lentz method ([TB]): f_j = f_{j-1} C_j D_j. For real z the
// fraction converges once the depth k passes about |z| - n, so the cost is O(|z| - n + 1)
// iterations; for complex z with a large imaginary part it converges much sooner (the two
// solutions of the recurrence separate at a rate that grows with Im z). The C and D chains are
// independent, so their divisions overlap.
template <typename T, typename Inverse>
T LogDerivativeContinuedFraction(const Inverse& zinv, int n) {
  const double two_n_plus_1 = 2.0 * n + 1.0;
  T f = nonzero(zinv.times(two_n_plus_1));
  T c = f;
  T d = T(0);
  // Converged when two successive factors C_j D_j are within 1e-15 of 1 (two, so that a factor
  // that passes near 1 by chance in the oscillating part of the fraction does not stop it).
  constexpr double kTol = 1e-15;
  const double z_abs = 1.0 / std::sqrt(abs2(zinv.value()));
  const long max_iter = 20 * static_cast<long>(z_abs + n) + 10000;
  int hits = 0;
  double sign = -1.0;
  for (long k = 1; k <= max_iter; ++k) {
    const T b = zinv.times(sign * (two_n_plus_1 + 2.0 * static_cast<double>(k)));
    sign = -sign;
    d = recip(nonzero(T(b + d)));
    c = nonzero(T(b + recip(c)));
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
inline void LogDerivativeDownward(const Inverse& zinv, int n_max, T* out, int n_low) {
  out[n_max] = LogDerivativeContinuedFraction<T>(zinv, n_max);
  for (int n = n_max; n > n_low; --n) {
    const T n_over_z = zinv.times(n);
    out[n - 1] = n_over_z - recip(nonzero(T(out[n] + n_over_z)));  // Equation (4.89) [BH]
  }
}

// ---- D_n(z) for a whole range of orders, from unnormalised psi_n(z) ----------------------------
//
// The ratio recurrence above has a division on its critical path (about 30 cycles a step). The
// three-term recurrence of psi_n itself, psi_{n-1} + psi_{n+1} = (2n+1)/z psi_n, is the same
// recurrence in linear form (a multiply-add a step), and D_n = psi_{n-1}/psi_n - n/z then follows
// for all orders at once, SIMD lanes wide (DFromRatiosComplex, DFromRatiosReal). p[k] holds psi_{k-1}(z) up to a
// factor that is common to each run of orders between two rescalings: the values are kept within
// 2^+-300 (so their squares stay normal) by multiplying the two live values by 2^-+300 where they
// leave that range; each such order is recorded (detail::Rescale) and its D_n recomputed.
//   Downward (PsiDownward) from the exact ratio at the top order (the continued fraction): the
// recessive direction of psi past the turning point, stable everywhere, as the ratio form.
//   Upward (PsiUpward) from psi_{-1} = cos z and psi_0 = sin z: stable while every order lies
// below the turning point n ~ |z|, where both solutions of the recurrence have the same size, and
// while absorption does not separate them (|psi_n| falls like exp(-n^2 Im z / (2 |z|^2)) there,
// so a rounding error grows by exp(n^2 Im z / |z|^2)). It needs no continued fraction, whose
// depth is |z| - n_max: 0.33 x for water, 9 x for m = 10. This is MIEV0's choice between upward
// and downward recurrence for D_n ([W80]) with a criterion derived from those two conditions.

using detail::Rescale;
constexpr double kBig = 0x1p300, kSmall = 0x1p-300;
constexpr int kRescaleBits = 300;

inline double scaled(double v, int e) noexcept { return std::ldexp(v, e); }
inline Cx scaled(Cx v, int e) noexcept { return {std::ldexp(v.real(), e), std::ldexp(v.imag(), e)}; }

// The size of the live pair (a, b) as one number: |a| + |b| (for complex values, C2 below,
// |Re a| + |Im a| + |Re b| + |Im b|), within a factor 4 of the largest part.
inline double pair_size(double a, double b) noexcept { return std::abs(a) + std::abs(b); }
// True where the size has left [2^-300, 2^300] (one test on its binary exponent, so that the
// recurrences' loops carry one rarely taken branch).
inline bool out_of_range(double size) noexcept {
  const auto biased = static_cast<std::uint32_t>(std::bit_cast<std::uint64_t>(size) >> 52);  // sign is 0
  return biased - (1023u - 300u) > 600u;
}
// Where the live pair left [2^-300, 2^300], the exponent that brings it back (0 for a zero pair).
inline int rescale_exponent(double size) noexcept {
  if (size > kBig) return -kRescaleBits;
  if (size < kSmall && size > 0) return kRescaleBits;
  return 0;
}

// The loops below carry a complex value as two doubles (C2), not std::complex: the compiler then
// keeps the recurrence's state in registers (with std::complex it packed and spilled it, which
// put a store and a reload on the critical path).
struct C2 {
  double re, im;
};
inline C2 to_c2(Cx v) noexcept { return {v.real(), v.imag()}; }
inline double to_c2(double v) noexcept { return v; }
inline void store(double* p, int k, double v) noexcept { p[k] = v; }
inline void store(double* p, int k, C2 v) noexcept {
  p[2 * k] = v.re;
  p[2 * k + 1] = v.im;
}
inline double pair_size(C2 a, C2 b) noexcept {
  return (std::abs(a.re) + std::abs(a.im)) + (std::abs(b.re) + std::abs(b.im));
}

// One step of the three-term recurrence, c f_n - f_{n-+1}, with c = (2n+1)/z, two fused
// multiply-adds deep.
inline double step(double c, double mid, double other) noexcept { return std::fma(c, mid, -other); }
inline C2 step(C2 c, C2 mid, C2 other) noexcept {
  return {std::fma(c.re, mid.re, -std::fma(c.im, mid.im, other.re)),
          std::fma(c.re, mid.im, std::fma(c.im, mid.re, -other.im))};
}

// The rare rescaling of the live pair, out of line so that the loops stay tight, and by value
// (a reference would make the compiler keep the pair in memory): both times 2^e, with e =
// rescale_exponent of their size.
template <typename V>
struct Rescaled {
  V a, b;
  int e;
};
HWY_NOINLINE inline Rescaled<double> RescalePair(double a, double b) {
  const int e = rescale_exponent(pair_size(a, b));
  return {std::ldexp(a, e), std::ldexp(b, e), e};
}
HWY_NOINLINE inline Rescaled<C2> RescalePair(C2 a, C2 b) {
  const int e = rescale_exponent(pair_size(a, b));
  return {{std::ldexp(a.re, e), std::ldexp(a.im, e)}, {std::ldexp(b.re, e), std::ldexp(b.im, e)}, e};
}

// psi downward: p[n_top + 1] = psi_{n_top}, p[n_top] = psi_{n_top - 1} from D_{n_top}, then down
// to p[0] (p: double pairs for complex z).
// T: double or Cx (the value type of zinv.times); the loop carries it as V = double or C2.
template <typename T, typename Inverse>
inline void PsiDownward(const Inverse& zinv_ref, int n_top, T d_top, double* p, std::vector<Rescale>& rescales) {
  const Inverse zinv = zinv_ref;  // in registers: p cannot alias it
  using V = decltype(to_c2(T(1)));
  V hi = to_c2(T(1));                              // psi_{n+1}
  V mid = to_c2(T(d_top + zinv.times(n_top)));     // psi_n, n = n_top - 1: psi_{n-1}/psi_n = D_n + n/z
  store(p, n_top + 1, hi);
  store(p, n_top, mid);
  // The inner loop has no call in it (a call would make the compiler keep the recurrence's state
  // in memory, all vector registers being caller-saved); it leaves only to rescale.
  for (int n = n_top - 1; n >= 0; --n) {
    V low{};
    for (; n >= 0; --n) {
      low = step(to_c2(zinv.times(2 * n + 1)), mid, hi);  // psi_{n-1}, stored at p[n]
      if (out_of_range(pair_size(low, mid))) [[unlikely]] break;
      store(p, n, low);
      hi = mid;
      mid = low;
    }
    if (n < 0) break;
    const auto r = RescalePair(low, mid);
    if (r.e != 0) rescales.push_back({n, -r.e});  // p[n + 1] keeps the old scale
    store(p, n, r.a);
    hi = r.b;
    mid = r.a;
  }
}

// psi upward: p[0] = psi_{-1}, p[1] = psi_0, then up to p[n_top + 1] = psi_{n_top}.
template <typename V, typename Inverse>
inline void PsiUpward(const Inverse& zinv_ref, int n_top, V psi_m1, V psi_0, double* p, std::vector<Rescale>& rescales) {
  const Inverse zinv = zinv_ref;  // in registers: p cannot alias it
  V low = psi_m1, mid = psi_0;
  store(p, 0, low);
  store(p, 1, mid);
  for (int n = 0; n < n_top; ++n) {  // as in PsiDownward: no call in the inner loop
    V hi{};
    for (; n < n_top; ++n) {
      hi = step(to_c2(zinv.times(2 * n + 1)), mid, low);  // psi_{n+1}, stored at p[n + 2]
      if (out_of_range(pair_size(hi, mid))) [[unlikely]] break;
      store(p, n + 2, hi);
      low = mid;
      mid = hi;
    }
    if (n == n_top) break;
    const auto r = RescalePair(hi, mid);
    if (r.e != 0) rescales.push_back({n + 1, r.e});  // p[n + 1] keeps the old scale
    store(p, n + 2, r.a);
    low = r.b;
    mid = r.a;
  }
}

// D_n = p[n] / p[n+1] - n/z for n = 0..n_top, whole vectors (p holds n_top + 2 + lanes values,
// out room for n_top + 1 + lanes), n/z with 1/z in two parts (hi + lo) as InverseComplex.
inline void DFromRatiosComplex(const double* HWY_RESTRICT p, int n_top, Cx zinv_hi, Cx zinv_lo,
                        double* HWY_RESTRICT out) {
  const hn::ScalableTag<double> d;
  using V = hn::Vec<decltype(d)>;
  const std::size_t lanes = hn::Lanes(d);
  const V hr = hn::Set(d, zinv_hi.real()), hi_ = hn::Set(d, zinv_hi.imag());
  const V lr = hn::Set(d, zinv_lo.real()), li = hn::Set(d, zinv_lo.imag());
  const V one = hn::Set(d, 1.0), zero = hn::Zero(d), huge = hn::Set(d, 1e300);
  for (std::size_t n = 0; n <= static_cast<std::size_t>(n_top); n += lanes) {
    V ar, ai, br, bi;
    hn::LoadInterleaved2(d, p + 2 * n, ar, ai);
    hn::LoadInterleaved2(d, p + 2 * (n + 1), br, bi);
    const V b2 = hn::MulAdd(br, br, hn::Mul(bi, bi));
    const auto zero_den = hn::Eq(b2, zero);  // psi_n exactly 0 (never seen): D_n -> 1e300
    const V inv = hn::Div(one, hn::IfThenElse(zero_den, one, b2));
    const V qr = hn::Mul(hn::MulAdd(ar, br, hn::Mul(ai, bi)), inv);
    const V qi = hn::Mul(hn::MulSub(ai, br, hn::Mul(ar, bi)), inv);
    const V nv = hn::Iota(d, static_cast<double>(n));
    const V nzr = hn::MulAdd(nv, hr, hn::Mul(nv, lr)), nzi = hn::MulAdd(nv, hi_, hn::Mul(nv, li));
    hn::StoreInterleaved2(hn::IfThenElse(zero_den, huge, hn::Sub(qr, nzr)),
                          hn::IfThenZeroElse(zero_den, hn::Sub(qi, nzi)), d, out + 2 * n);
  }
}

inline void DFromRatiosReal(const double* HWY_RESTRICT p, int n_top, double zinv_hi, double zinv_lo,
                     double* HWY_RESTRICT out) {
  const hn::ScalableTag<double> d;
  using V = hn::Vec<decltype(d)>;
  const std::size_t lanes = hn::Lanes(d);
  const V hr = hn::Set(d, zinv_hi), lr = hn::Set(d, zinv_lo);
  const V one = hn::Set(d, 1.0), zero = hn::Zero(d), huge = hn::Set(d, 1e300);
  for (std::size_t n = 0; n <= static_cast<std::size_t>(n_top); n += lanes) {
    const V a = hn::LoadU(d, p + n), b = hn::LoadU(d, p + n + 1);
    const auto zero_den = hn::Eq(b, zero);
    const V q = hn::Div(a, hn::IfThenElse(zero_den, one, b));
    const V nv = hn::Iota(d, static_cast<double>(n));
    hn::StoreU(hn::IfThenElse(zero_den, huge, hn::Sub(q, hn::MulAdd(nv, hr, hn::Mul(nv, lr)))), d, out + n);
  }
}

// Upward needs every order below the turning point by a margin and absorption growth below e.
inline bool UpwardIsStable(Cx z, int n_top) {
  const double az = std::sqrt(abs2(z));
  if (n_top > az - 5) return false;  // (without the cube root, which costs as much as a step)
  return n_top <= az - 3 * std::cbrt(az) - 5 && double(n_top) * n_top * std::abs(z.imag()) <= az * az;
}

// Far above the turning point (n > 1.5 |z| + 5) the downward recurrence forgets its start fast:
// one step multiplies a start error by |psi_n / psi_{n-1}|^2 <= (|z| / (2n + 1 - |z|))^2 (from
// psi_{n-1} / psi_n = (2n+1)/z - psi_{n+1} / psi_n and |psi_{n+1} / psi_n| < |z| / (2n + 1 -
// |z|) there), so K orders above n_top with (|z| / (2 n_top + 1 - |z|))^(2K) < 2^-57 (7e-18)
// make psi_{n-1}/psi_n = (2n+1)/z at n_top + K a start as good as the continued fraction's, and
// cheaper (small spheres: a handful of multiply-adds instead of tens of divisions). That start is
// itself wrong by only about ratio^2 (psi_{n+1}/psi_n ~ z/(2n+3) is what it leaves out), one
// order's damping, which is the margin. K is taken from the binary exponent of the ratio, rounded
// up; 0 where the continued fraction is needed.
inline int MillerOrders(double az, int n_top) {
  if (n_top < 1.5 * az + 5) return 0;
  const double ratio = az / (2.0 * n_top + 1 - az);  // < 1/2
  // ratio < 2^(e + 1) with e its binary exponent, so ratio^(2K) < 2^(2K (e + 1)) <= 2^-57.
  const int e = static_cast<int>((std::bit_cast<std::uint64_t>(ratio) >> 52) & 0x7ff) - 1023;
  const int per_order = -2 * (e + 1);  // >= 2 bits of damping per order
  return (57 + per_order - 1) / per_order;
}

// psi_{-1}(z) = cos z and psi_0(z) = sin z, both times exp(-|Im z|) (so that they stay finite
// for Im z of any size; the common factor cancels in D_n).
inline void ScaledCosSin(Cx z, Cx& c, Cx& s) {
  const double a = z.real(), b = std::abs(z.imag()), sign = z.imag() < 0 ? -1.0 : 1.0;
  const double ch = 0.5 * (1 + std::exp(-2 * b));  // cosh b e^-b
  const double sh = -0.5 * std::expm1(-2 * b);     // sinh b e^-b
  const double sa = std::sin(a), ca = std::cos(a);
  s = Cx(sa * ch, sign * ca * sh);
  c = Cx(ca * ch, -sign * sa * sh);
}

// Unnormalised psi_n(z) for n = -1..n_max into p[0..n_max+1] (complex: (re, im) pairs), with the
// orders where their scale changes in `rescales` (see detail::Rescale): upward from cos z, sin z
// where that is stable, else downward from the continued fraction at n_max or from a Miller start
// above it (whose values for higher orders may then lie in p past n_max + 1). p: n_max + 2 + lanes
// + detail::kMaxMillerOrders values; the lanes values past n_max + 1 are set finite and nonzero
// (first, so that no store is pending when a vector pass reads them). Returns D_{n_max} where the
// continued fraction gave it (exactly), else 0 and sets *exact = false.
template <typename T, typename Inverse>
inline T PsiAll(Cx z, const Inverse& zinv, int n_max, T* p, std::vector<Rescale>& rescales, bool* exact) {
  const std::size_t lanes = hn::Lanes(hn::ScalableTag<double>());
  const bool upward = UpwardIsStable(z, n_max);
  const int miller = upward ? 0 : MillerOrders(std::sqrt(abs2(z)), n_max);
  for (std::size_t k = static_cast<std::size_t>(n_max) + 2; k < static_cast<std::size_t>(n_max) + 2 + lanes; ++k)
    p[k] = T(1);
  double* pd = reinterpret_cast<double*>(p);  // complex values as (re, im) pairs
  *exact = false;
  if (upward) {
    Cx c, s;
    ScaledCosSin(z, c, s);
    if constexpr (std::is_same_v<T, Cx>) {
      PsiUpward(zinv, n_max, to_c2(c), to_c2(s), pd, rescales);
    } else {
      PsiUpward(zinv, n_max, c.real(), s.real(), pd, rescales);
    }
    return T(0);
  }
  if (miller > 0) {
    // D_{n_top} = psi_{n_top-1}/psi_{n_top} - n_top/z with the ratio taken as (2 n_top + 1)/z.
    const int n_top = n_max + miller;
    PsiDownward(zinv, n_top, T(zinv.times(n_top + 1)), pd, rescales);
    return T(0);
  }
  const T d_top = LogDerivativeContinuedFraction<T>(zinv, n_max);
  PsiDownward(zinv, n_max, d_top, pd, rescales);
  *exact = true;
  return d_top;
}

// D_n(z), n = 0..n_max, into out (interleaved for complex z, plain for real) from PsiAll's p, the
// ratios in SIMD and the rescaled orders fixed after. out: room for n_max + 1 + lanes values.
template <typename T, typename Inverse>
inline void LogDerivativeAll(Cx z, const Inverse& zinv, int n_max, T* p, T* out) {
  std::vector<Rescale> rescales;
  bool exact = false;
  const T d_top = PsiAll(z, zinv, n_max, p, rescales, &exact);
  if constexpr (std::is_same_v<T, Cx>) {
    DFromRatiosComplex(reinterpret_cast<const double*>(p), n_max, zinv.hi, zinv.lo,
                       reinterpret_cast<double*>(out));
  } else {
    DFromRatiosReal(p, n_max, zinv.hi, zinv.lo, out);
  }
  for (const Rescale& r : rescales) {
    if (r.n > n_max) continue;
    const T ratio = scaled(p[r.n], r.shift) * recip(nonzero(p[r.n + 1]));
    out[r.n] = ratio - zinv.times(r.n);
  }
  if (exact) out[n_max] = d_top;  // the continued fraction's value itself
}

// psi_n(x) and chi_n(x) for n = 0..n_max, real x > 0 (chi = +inf past its overflow).
inline void PsiChi(double x, int n_max, double* psi, double* chi) {
  const InverseReal xinv(x);
  // psi_n for n <= x: upward recurrence from psi_0 = sin x, psi_1 = sin x / x - cos x. Below the
  // turning point n ~ x both solutions oscillate with the same envelope, so rounding errors
  // neither grow nor shrink (they add up like a random walk), exactly as for chi below.
  // psi_n for n > x: from D_n(x) downward, or by Miller's algorithm for small x (below). Recurring
  // psi itself upward there would amplify rounding by chi_n / psi_n.
  // (The ratio form alone, for every n, is also stable, but its errors at n ~ x are systematic
  // and grow like n eps: 1e-11 at x = 1e5, against 1e-14 for the split.)
  const double s = std::sin(x), c = std::cos(x);
  const int n_up = std::min(n_max, static_cast<int>(std::min(x, 2e9)));
  // chi upward ([BH] section 4.8), and psi with it while n <= x: the two chains are independent,
  // so one loop runs both at the latency of one. chi_n grows like (2n-1)!! / x^n past n ~ x:
  // where it overflows, the rest is set to +inf below (psi_n has underflowed to 0 there), never
  // to inf - inf = NaN.
  double psi0 = s, psi1 = s * xinv.value() - c, chi0 = c, chi1 = c * xinv.value() + s;
  psi[0] = psi0;
  chi[0] = chi0;
  if (n_max == 0) return;
  if (n_up >= 1) psi[1] = psi1;
  chi[1] = chi1;
  int n = 1;
  for (; n < n_up; ++n) {
    const double k = xinv.times(2 * n + 1);
    const double psi2 = std::fma(k, psi1, -psi0), chi2 = std::fma(k, chi1, -chi0);
    psi[n + 1] = psi2;
    chi[n + 1] = chi2;
    psi0 = psi1;
    psi1 = psi2;
    chi0 = chi1;
    chi1 = chi2;
  }
  for (; n < n_max; ++n) {
    const double chi2 = std::fma(xinv.times(2 * n + 1), chi1, -chi0);
    chi[n + 1] = chi2;
    chi0 = chi1;
    chi1 = chi2;
  }
  if (!std::isfinite(chi[n_max])) {
    int k = 0;
    while (std::isfinite(chi[k])) ++k;
    for (; k <= n_max; ++k) chi[k] = std::numeric_limits<double>::infinity();
  }
  if (n_max <= n_up) return;
  const int miller = MillerOrders(x, n_max);
  const double psi_up = psi[n_up];  // from the upward recurrence (Miller's loop overwrites it)
  if (miller == 0) {
    // D_n(x) downward from n_max into psi[] itself, then psi_n = psi_{n-1} / (D_n + n/x) upward in
    // place (psi[n] still holds D_n when step n reads it), [PP].
    LogDerivativeDownward(xinv, n_max, psi, n_up + 1);
    for (int m = n_up + 1; m <= n_max; ++m) psi[m] = psi[m - 1] / nonzero(psi[m] + xinv.times(m));
    return;
  }
  // Far above the turning point (small x): Miller's algorithm, the three-term recurrence downward
  // from 0, 1 at n_max + miller orders (see MillerOrders) to n_up, scaled to the psi_{n_up} found
  // upward. The values grow downward; where the live pair passes 2^300 it is scaled by 2^-300 and
  // the order noted, so that the normalisation below undoes it.
  std::vector<Rescale> rescales;
  const InverseReal k = xinv;  // in registers: psi cannot alias it
  double hi = 0, mid = 1;      // p_{m+1}, p_m
  for (int m = n_max + miller; m > n_up; --m) {
    double low = std::fma(k.times(2 * m + 1), mid, -hi);  // p_{m-1}
    if (out_of_range(pair_size(low, mid))) [[unlikely]] {
      if (pair_size(low, mid) > kBig) {  // (downward, the values only grow)
        low = std::ldexp(low, -kRescaleBits);
        mid = std::ldexp(mid, -kRescaleBits);
        rescales.push_back({m - 1, -kRescaleBits});  // orders <= m - 1 carry 2^-300 more
      }
    }
    if (m - 1 <= n_max) psi[m - 1] = low;  // (psi[n_up] is restored below)
    hi = mid;
    mid = low;
  }
  // mid = p_{n_up}: psi_n = p_n psi_{n_up} / p_{n_up}, the factor adjusted across each rescaling.
  psi[n_up] = psi_up;
  double scale = psi_up / mid;
  std::size_t r = rescales.size();
  for (int m = n_up + 1; m <= n_max; ++m) {
    while (r > 0 && rescales[r - 1].n < m) {  // crossing a boundary upward
      scale = std::ldexp(scale, rescales[r - 1].shift);
      --r;
    }
    psi[m] *= scale;
  }
}

}  // namespace hydrolux::scatter::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#endif  // per-target include guard
