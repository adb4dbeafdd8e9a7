// Lorenz-Mie scattering by a homogeneous sphere: coefficients, efficiencies and the scalar
// reference summation of the amplitudes S1, S2.
//
// References:
//   [BH]  C. F. Bohren and D. R. Huffman, "Absorption and Scattering of Light by Small Particles"
//         (Wiley, 1983), chapter 4 and Appendix A (BHMIE).
//   [W80] W. J. Wiscombe, "Improved Mie scattering algorithms", Appl. Opt. 19, 1505-1509 (1980):
//         the number of terms, and when D_n may be recurred upward.
//   [W79] W. J. Wiscombe, "Mie scattering calculations: advances in technique and fast,
//         vector-speed computer codes", NCAR/TN-140+STR (1979, revised 1996), and its code MIEV0:
//         the g series (GQSC) and the test cases used in tests/scatter/test_mie.cpp.
//   [Du]  H. Du, "Mie-scattering calculation", Appl. Opt. 43, 1951-1956 (2004): large and
//         strongly absorbing spheres (m = 10 + 10i), the downward recurrence there.
//
// Conventions are those of include/hydrolux/scatter/mie.hpp (B&H: m = n + ik, exp(-i omega t)).
// MIEV0 uses m = n - ik; its amplitudes are the complex conjugates of these.
//
// One kernel per sphere, compiled once per SIMD target (Highway foreach_target) and chosen at
// run time (hydrolux::simd), runs:
//   - the scalar recurrences for psi_n(mx) (unnormalised), psi_n(x) and chi_n(x)
//     (src/scatter/recurrences-inl.h, shared with riccati_bessel.cpp; methods there and in
//     docs/mie.md): each order depends on the last, so they cannot use SIMD lanes;
//   - a_n, b_n, independent across n, for as many orders at once as the vector holds, with
//     D_n(mx) and T_n(mx) formed from the psi_n(mx) on the way;
//   - the efficiency sums over n, likewise.
// Working arrays live in a per-thread workspace that only grows, so repeated calls (size
// distributions, tables) allocate nothing.

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "src/scatter/mie.cpp"  // NOLINT
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstddef>
#include <type_traits>
#include <vector>

#include "src/scatter/recurrences-inl.h"

HWY_BEFORE_NAMESPACE();
namespace hydrolux::scatter::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// a_n, b_n for the orders n = n_first..n_first+count-1 from the unnormalised psi_k(mx) of PsiAll,
// a vector of orders at a time (the tag d: the target's full width, or one lane for the few
// orders around a rescaling). Arrays are passed from the first order: for order n = n_first + j,
//   p[j], p[j+1], p[j+2] = psi_{n-1}, psi_n, psi_{n+1} of mx (complex (re, im) pairs, or real
//     values when kRealP: real m), each run between two rescalings to its own scale;
//   psi[j+1], psi[j+2] = psi_n(x), psi_{n+1}(x); chi[j], chi[j+1] = chi_{n-1}(x), chi_n(x);
//   a[2j], a[2j+1] = Re, Im a_n (likewise b).
// Whole vectors: the inputs must be readable a vector past the last order, and the lanes past it
// are written as zeros, followed by one more vector of zeros (for the sums' a_{n+1}).
template <bool kRealP, class DTag>
HWY_INLINE void Coefficients(DTag d, const double* HWY_RESTRICT p, const double* HWY_RESTRICT psi,
                             const double* HWY_RESTRICT chi, std::size_t n_first, std::size_t count,
                             double m_re, double m_im, double x, Cx zinv_hi, Cx zinv_lo,
                             double* HWY_RESTRICT a, double* HWY_RESTRICT b) {
  using V = hn::Vec<DTag>;
  const std::size_t lanes = hn::Lanes(d);
  // Scalar constants: 1/m, 1/m^2 - 1, 1/x (written without complex division, which is a library
  // call, __divdc3, in this build).
  const double m2 = m_re * m_re + m_im * m_im;
  const Cx minv(m_re / m2, -m_im / m2);
  const Cx q(minv.real() * minv.real() - minv.imag() * minv.imag() - 1, 2 * minv.real() * minv.imag());
  const V mr = hn::Set(d, m_re), mi = hn::Set(d, m_im);
  const V ir = hn::Set(d, minv.real()), ii = hn::Set(d, minv.imag());
  const V qr = hn::Set(d, q.real()), qi = hn::Set(d, q.imag());
  // n/z in two parts, as the recurrences use it (InverseComplex).
  const V zhr = hn::Set(d, zinv_hi.real()), zhi = hn::Set(d, zinv_hi.imag());
  const V zlr = hn::Set(d, zinv_lo.real()), zli = hn::Set(d, zinv_lo.imag());
  const V xinv = hn::Set(d, 1.0 / x);
  const V one = hn::Set(d, 1.0), zero = hn::Zero(d), huge = hn::Set(d, 1e300);
  const auto load_p = [&](std::size_t k, V& re, V& im) HWY_ATTR {
    if constexpr (kRealP) {
      re = hn::LoadU(d, p + k);
      im = zero;
    } else {
      hn::LoadInterleaved2(d, p + 2 * k, re, im);
    }
  };
  for (std::size_t j = 0; j < count; j += lanes) {
    const V nv = hn::Iota(d, static_cast<double>(n_first + j));
    const V n1 = hn::Add(nv, one);
    V p0r, p0i, p1r, p1i, p2r, p2i;
    load_p(j, p0r, p0i);      // psi_{n-1}(mx)
    load_p(j + 1, p1r, p1i);  // psi_n(mx)
    load_p(j + 2, p2r, p2i);  // psi_{n+1}(mx)
    const V s1 = hn::LoadU(d, psi + j + 1), s2 = hn::LoadU(d, psi + j + 2);
    const V c0 = hn::LoadU(d, chi + j), c1 = hn::LoadU(d, chi + j + 1);
    // D_n(mx) = psi_{n-1}/psi_n - n/(mx) and T_n(mx) = psi_{n+1}/psi_n share one division.
    const V w2 = hn::MulAdd(p1r, p1r, hn::Mul(p1i, p1i));
    const auto w_zero = hn::Eq(w2, zero);  // psi_n(mx) = 0 exactly (real m): D_n, T_n -> 1e300
    const V w_inv = hn::Div(one, hn::IfThenElse(w_zero, one, w2));
    const V ur = hn::Mul(p1r, w_inv), ui = hn::Neg(hn::Mul(p1i, w_inv));  // 1/psi_n
    const V nzr = hn::MulAdd(nv, zhr, hn::Mul(nv, zlr)), nzi = hn::MulAdd(nv, zhi, hn::Mul(nv, zli));
    const V Dr = hn::IfThenElse(w_zero, huge, hn::Sub(hn::MulSub(p0r, ur, hn::Mul(p0i, ui)), nzr));
    const V Di = hn::IfThenZeroElse(w_zero, hn::Sub(hn::MulAdd(p0r, ui, hn::Mul(p0i, ur)), nzi));
    const V tr = hn::IfThenElse(w_zero, huge, hn::MulSub(p2r, ur, hn::Mul(p2i, ui)));
    const V ti = hn::IfThenZeroElse(w_zero, hn::MulAdd(p2r, ui, hn::Mul(p2i, ur)));
    const V nx = hn::Mul(nv, xinv);
    // Equation (4.88) [BH], with xi = psi - i chi:
    //   a_n = [(D_n(mx)/m + n/x) psi_n - psi_{n-1}] / [(D_n(mx)/m + n/x) xi_n - xi_{n-1}]
    //   b_n = [(m D_n(mx) + n/x) psi_n - psi_{n-1}] / [(m D_n(mx) + n/x) xi_n - xi_{n-1}]
    // so each denominator is its numerator minus i C, C = (...) chi_n - chi_{n-1}.
    const V dar = hn::Add(hn::MulSub(Dr, ir, hn::Mul(Di, ii)), nx);
    const V dai = hn::MulAdd(Dr, ii, hn::Mul(Di, ir));
    const V dbr = hn::Add(hn::MulSub(mr, Dr, hn::Mul(mi, Di)), nx);
    const V dbi = hn::MulAdd(mr, Di, hn::Mul(mi, Dr));
    const V car = hn::MulSub(dar, c1, c0), cai = hn::Mul(dai, c1);
    const V cbr = hn::MulSub(dbr, c1, c0), cbi = hn::Mul(dbi, c1);
    // The numerators, psi_n (D_n(mx)/m - D_n(x)) and psi_n (m D_n(mx) - D_n(x)), without their
    // large cancelling terms: with T_n(z) = psi_{n+1}(z)/psi_n(z) and D_n(z) = (n+1)/z - T_n(z),
    //   a numerator = (n+1)/x (1/m^2 - 1) psi_n + psi_{n+1} - psi_n T_n(mx) / m
    //   b numerator = psi_{n+1} - m psi_n T_n(mx).
    // Written as in (4.88), the b numerator loses digits like 1/(x^2 |m^2 - 1|) for small x; this
    // form loses only the 1/|m^2 - 1| the physics has. Using the numerator inside the
    // denominator also keeps Re a_n = |a_n|^2 to rounding for real m (no absorption).
    const V ptr = hn::Mul(s1, tr), pti = hn::Mul(s1, ti);
    const V s = hn::Mul(hn::Mul(n1, xinv), s1);
    const V nar = hn::Sub(hn::MulAdd(s, qr, s2), hn::MulSub(ptr, ir, hn::Mul(pti, ii)));
    const V nai = hn::Sub(hn::Mul(s, qi), hn::MulAdd(ptr, ii, hn::Mul(pti, ir)));
    const V nbr = hn::Sub(s2, hn::MulSub(mr, ptr, hn::Mul(mi, pti)));
    const V nbi = hn::Neg(hn::MulAdd(mr, pti, hn::Mul(mi, ptr)));
    // a = num / (num - i C) = num conj(den) / |den|^2, den = (num_re + C_im, num_im - C_re).
    const auto divide = [&](V nr, V ni, V cr, V ci, V& out_r, V& out_i) HWY_ATTR {
      const V er = hn::Add(nr, ci), ei = hn::Sub(ni, cr);
      const V inv = hn::Div(one, hn::MulAdd(er, er, hn::Mul(ei, ei)));
      out_r = hn::Mul(hn::MulAdd(nr, er, hn::Mul(ni, ei)), inv);
      out_i = hn::Mul(hn::MulSub(ni, er, hn::Mul(nr, ei)), inv);
    };
    V ar, ai, br, bi;
    divide(nar, nai, car, cai, ar, ai);
    divide(nbr, nbi, cbr, cbi, br, bi);
    // Where chi_n(x) (nearly) overflowed, which needs far more terms than x calls for, a_n, b_n
    // ~ psi_n / chi_n have underflowed to zero; lanes past the last order are zeroed too.
    const auto keep = hn::And(hn::And(hn::And(hn::IsFinite(car), hn::IsFinite(cai)),
                                      hn::And(hn::IsFinite(cbr), hn::IsFinite(cbi))),
                              hn::FirstN(d, count - j));
    hn::StoreInterleaved2(hn::IfThenElseZero(keep, ar), hn::IfThenElseZero(keep, ai), d, a + 2 * j);
    hn::StoreInterleaved2(hn::IfThenElseZero(keep, br), hn::IfThenElseZero(keep, bi), d, b + 2 * j);
  }
  const std::size_t end = (count + lanes - 1) / lanes * lanes;
  hn::StoreInterleaved2(zero, zero, d, a + 2 * end);
  hn::StoreInterleaved2(zero, zero, d, b + 2 * end);
}

// The sums over n = 1..n_max behind the efficiencies ([BH] ch. 4; the g series is MIEV0's GQSC,
// [W79], equal to [BH] eq. 4.92), with a_{n_max+1} = b_{n_max+1} = 0:
//   out[0] ext  = sum (2n+1) Re(a_n + b_n)
//   out[1] sca  = sum (2n+1) (|a_n|^2 + |b_n|^2)
//   out[2..3] back = sum (2n+1) (-1)^n (a_n - b_n)
//   out[4] gsca = sum n(n+2)/(n+1) Re(a_n a*_{n+1} + b_n b*_{n+1}) + (2n+1)/(n(n+1)) Re(a_n b*_n)
// a, b interleaved, exactly n_max values each (the last vector is copied to a zero-padded
// buffer). The alternating back sum is reduced to a scalar every vector, so its partial sums stay
// the size of a few terms rather than growing to the sum of all terms of one sign.
inline void Sums(const double* HWY_RESTRICT a, const double* HWY_RESTRICT b, std::size_t n_max,
                double* HWY_RESTRICT out, bool padded = false) {
  const hn::ScalableTag<double> d;
  using V = hn::Vec<decltype(d)>;
  const std::size_t lanes = hn::Lanes(d);
  // (-1)^n for n = n0 + j with n0 odd; negated for a block starting at an even n0 (which happens
  // only with an odd lane count: the one-lane scalar target).
  HWY_ALIGN double sign_lanes[(HWY_MAX_BYTES / sizeof(double))];
  for (std::size_t j = 0; j < lanes; ++j) sign_lanes[j] = (j % 2 == 0) ? -1.0 : 1.0;
  const V sign_odd = hn::Load(d, sign_lanes), sign_even = hn::Neg(sign_odd);
  const V one = hn::Set(d, 1.0), two = hn::Set(d, 2.0);
  V ext = hn::Zero(d), sca = hn::Zero(d), gsca = hn::Zero(d);
  double back_re = 0, back_im = 0;
  const auto block = [&](std::size_t n, const double* pa, const double* pb) HWY_ATTR {
    const V nv = hn::Iota(d, static_cast<double>(n));
    const V f = hn::MulAdd(two, nv, one);  // 2n + 1
    V ar, ai, br, bi, a1r, a1i, b1r, b1i;
    hn::LoadInterleaved2(d, pa, ar, ai);
    hn::LoadInterleaved2(d, pb, br, bi);
    hn::LoadInterleaved2(d, pa + 2, a1r, a1i);  // a_{n+1}
    hn::LoadInterleaved2(d, pb + 2, b1r, b1i);
    ext = hn::MulAdd(f, hn::Add(ar, br), ext);
    const V norms = hn::MulAdd(ar, ar, hn::MulAdd(ai, ai, hn::MulAdd(br, br, hn::Mul(bi, bi))));
    sca = hn::MulAdd(f, norms, sca);
    const V fs = hn::Mul(f, n % 2 == 1 ? sign_odd : sign_even);
    back_re += hn::GetLane(hn::SumOfLanes(d, hn::Mul(fs, hn::Sub(ar, br))));
    back_im += hn::GetLane(hn::SumOfLanes(d, hn::Mul(fs, hn::Sub(ai, bi))));
    const V np1 = hn::Add(nv, one);
    const V cross = hn::MulAdd(ar, a1r, hn::MulAdd(ai, a1i, hn::MulAdd(br, b1r, hn::Mul(bi, b1i))));
    const V ab = hn::MulAdd(ar, br, hn::Mul(ai, bi));
    const V g1 = hn::Div(hn::Mul(nv, hn::Add(np1, one)), np1);  // n(n+2)/(n+1)
    const V g2 = hn::Div(f, hn::Mul(nv, np1));                    // (2n+1)/(n(n+1))
    gsca = hn::MulAdd(g1, cross, hn::MulAdd(g2, ab, gsca));
  };
  std::size_t n = 1;
  // Whole vectors while a_{n+lanes} (the last lane's a_{n+1}) is still inside the arrays; to the
  // end where they are zero-padded by a vector (CoefficientsKernel's output).
  const std::size_t whole = padded ? n_max + lanes : n_max;
  for (; n + lanes <= whole; n += lanes) block(n, a + 2 * (n - 1), b + 2 * (n - 1));
  if (!padded && n <= n_max) {
    HWY_ALIGN double ta[2 * ((HWY_MAX_BYTES / sizeof(double)) + 1)] = {};
    HWY_ALIGN double tb[2 * ((HWY_MAX_BYTES / sizeof(double)) + 1)] = {};
    const std::size_t rest = std::min(n_max + 1 - n, lanes);  // 1..lanes values
    for (std::size_t k = 0; k < 2 * rest; ++k) {
      ta[k] = a[2 * (n - 1) + k];
      tb[k] = b[2 * (n - 1) + k];
    }
    block(n, ta, tb);
  }
  out[0] = hn::GetLane(hn::SumOfLanes(d, ext));
  out[1] = hn::GetLane(hn::SumOfLanes(d, sca));
  out[2] = back_re;
  out[3] = back_im;
  out[4] = hn::GetLane(hn::SumOfLanes(d, gsca));
}

void SumsKernel(const double* HWY_RESTRICT a, const double* HWY_RESTRICT b, std::size_t n_max,
                double* HWY_RESTRICT out) {
  Sums(a, b, n_max, out);
}

// One sphere, one call: psi_k(mx) (k = -1..n_max+1), psi_n(x), chi_n(x), then a_n, b_n into a,
// b (interleaved, room for 2 (n_max + 2 lanes) doubles each), and the efficiency sums into `sums`
// if it is not null. Working arrays: p 2 (rows + kMaxMillerOrders), psi and chi rows doubles,
// rows = n_max + 2 lanes + 3.
template <bool kRealP, class Inverse>
HWY_INLINE void Solve(Cx z, const Inverse& zinv, double m_re, double m_im, double x, int n_max,
                      double* HWY_RESTRICT p, double* HWY_RESTRICT psi, double* HWY_RESTRICT chi,
                      double* HWY_RESTRICT a, double* HWY_RESTRICT b) {
  const hn::ScalableTag<double> d;
  const std::size_t lanes = hn::Lanes(d);
  const auto n = static_cast<std::size_t>(n_max);
  using T = std::conditional_t<kRealP, double, Cx>;
  T* pt = reinterpret_cast<T*>(p);
  // psi(x), chi(x) past n_max + 1 (read by the last vector of orders; PsiChi writes up to
  // n_max + 1 only), set before anything else so that no store is pending when they are read;
  // then psi(x), chi(x), then psi(mx), whose stores have retired by the time the kernel reads them.
  for (std::size_t k = n + 2; k < n + 2 + lanes; ++k) {
    psi[k] = 0;
    chi[k] = 1;
  }
  PsiChi(x, n_max + 1, psi, chi);
  std::vector<Rescale> rescales;
  bool exact = false;
  PsiAll(z, zinv, n_max + 1, pt, rescales, &exact);  // p[k] = psi_{k-1}(mx), k = 0..n_max+2
  Cx zh, zl;
  if constexpr (kRealP) {
    zh = Cx(zinv.hi, 0);
    zl = Cx(zinv.lo, 0);
  } else {
    zh = zinv.hi;
    zl = zinv.lo;
  }
  Coefficients<kRealP>(d, p + (kRealP ? 1 : 2), psi, chi, 1, n, m_re, m_im, x, zh, zl, a, b);
  // Where the scale of p changes between p[k] and p[k+1], orders k (its D) and k - 1 (its T)
  // mixed two scales: recomputed one lane at a time from p brought to one scale.
  const hn::CappedTag<double, 1> d1;
  for (const Rescale& r : rescales) {
    const std::size_t k = static_cast<std::size_t>(r.n);
    if (k < 1 || k > n + 1) continue;
    const std::size_t first = std::max<std::size_t>(1, k - 1), last = std::min(n, k);
    if (first > last) continue;
    // Window p[first .. last + 2], the orders <= k multiplied by 2^shift.
    T w[8];
    for (std::size_t i = first; i <= last + 2; ++i) {
      const T v = pt[i];
      w[i - first] = i <= k ? scaled(v, r.shift) : v;
    }
    const std::size_t count = last - first + 1;
    double wa[2 * 4] = {}, wb[2 * 4] = {};  // count + one zero lane, (re, im)
    Coefficients<kRealP>(d1, reinterpret_cast<const double*>(w), psi + first - 1, chi + first - 1, first, count,
                         m_re, m_im, x, zh, zl, wa, wb);
    for (std::size_t i = 0; i < 2 * count; ++i) {
      a[2 * (first - 1) + i] = wa[i];
      b[2 * (first - 1) + i] = wb[i];
    }
  }
}

void SolveKernel(double m_re, double m_im, double x, int n_max, double* HWY_RESTRICT p,
                 double* HWY_RESTRICT psi, double* HWY_RESTRICT chi, double* HWY_RESTRICT a,
                 double* HWY_RESTRICT b, double* HWY_RESTRICT sums) {
  if (m_im == 0) {
    const double z = m_re * x;
    Solve<true>(Cx(z, 0), InverseReal(z), m_re, m_im, x, n_max, p, psi, chi, a, b);
  } else {
    const Cx z = Cx(m_re, m_im) * x;
    Solve<false>(z, InverseComplex(z), m_re, m_im, x, n_max, p, psi, chi, a, b);
  }
  if (sums) Sums(a, b, static_cast<std::size_t>(n_max), sums, /*padded=*/true);
}

}  // namespace hydrolux::scatter::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <array>
#include <limits>
#include <string>
#include <vector>

#include "hydrolux/core/complex.hpp"
#include "hydrolux/core/error.hpp"
#include "hydrolux/core/math.hpp"
#include "hydrolux/scatter/mie.hpp"
#include "src/core/simd_dispatch.hpp"
#include "src/scatter/recurrences.hpp"

namespace hydrolux::scatter {

HYDROLUX_SIMD_EXPORT(SumsKernel);
HYDROLUX_SIMD_EXPORT(SolveKernel);

namespace {

constexpr const char* kContext = "the Lorenz-Mie solver";

void require_size_parameter(double x) {
  require_in_range("x", x, kMieMinSizeParameter, kMieMaxSizeParameter, kContext);
}

void require_index(Complex m) {
  if (m.imag() < 0)
    throw DomainError("m_imag", m.imag(), 0, kMieMaxIndex,
                      "the Lorenz-Mie solver, whose convention is m = n + ik with k >= 0 for an "
                      "absorbing sphere (Bohren & Huffman); an index written n - ik (MIEV0, van de "
                      "Hulst) must have its imaginary part negated, not be passed as it is");
  require_in_range("m_real", m.real(), 0.0, kMieMaxIndex, kContext);
  require_in_range("m_imag", m.imag(), 0.0, kMieMaxIndex, kContext);
  const double abs_m = std::sqrt(std::norm(m));  // no overflow: both parts are at most 1e3
  if (abs_m < kMieMinIndex)
    throw DomainError("m_abs", abs_m, kMieMinIndex, std::sqrt(2.0) * kMieMaxIndex, kContext);
}

// Padding after every kernel array: at least two vectors of any target compiled in (64 doubles:
// 2048-bit vectors; HWY_MAX_BYTES is only the last target's here).
constexpr std::size_t kPad = 64;

// Per-thread working arrays; they only grow.
struct Workspace {
  std::vector<double> p, psi, chi, a, b;
};
Workspace& workspace() {
  thread_local Workspace w;
  return w;
}

template <typename T>
T* grow(std::vector<T>& v, std::size_t size) {
  if (v.size() < size) v.resize(size);
  return v.data();
}

// a_n, b_n for n = 1..n_max into a, b (interleaved; room for 2 (n_max + kPad) doubles each), and
// the efficiency sums into `sums` unless it is null: one dispatched kernel.
void solve(Complex m, double x, int n_max, double* a, double* b, double* sums) {
  Workspace& w = workspace();
  const std::size_t rows = static_cast<std::size_t>(n_max) + kPad + 3;
  double* p = grow(w.p, 2 * (rows + detail::kMaxMillerOrders));
  double* psi = grow(w.psi, rows);
  double* chi = grow(w.chi, rows);
  HYDROLUX_SIMD_DISPATCH(SolveKernel)(m.real(), m.imag(), x, n_max, p, psi, chi, a, b, sums);
}

// The efficiencies from the sums of SumsKernel (see there).
MieEfficiencies efficiencies_from(const double* s, double x, Complex m) {
  const double x2 = x * x;
  MieEfficiencies q;
  q.qext = 2.0 / x2 * s[0];
  q.qsca = 2.0 / x2 * s[1];
  // A sphere with real m absorbs nothing: report exactly 0 rather than the rounding-level
  // difference of two sums (|qext - qsca| ~ 1e-15 qext there).
  q.qabs = m.imag() == 0 ? 0.0 : q.qext - q.qsca;
  q.qback = (s[2] * s[2] + s[3] * s[3]) / x2;
  q.g = q.qsca > 0 ? 4.0 / x2 * s[4] / q.qsca : 0.0;
  return q;
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

int mie_terms(double x) {
  require_size_parameter(x);
  // See mie.hpp: Wiscombe's count plus what Qback and the amplitudes near backscatter need,
  // and at least kMieMinTerms.
  const double cbrt = std::cbrt(x);
  return std::max(kMieMinTerms, static_cast<int>(x + kMieTermsCbrt * cbrt + kMieTermsConstant));
}

void mie_coefficients(Complex m, double x, MieCoefficients& out, int n_terms) {
  require_size_parameter(x);
  require_index(m);
  require_in_range("n_terms", n_terms, 0, 2e7, kContext);
  const int n_max = n_terms > 0 ? n_terms : mie_terms(x);
  const std::size_t size = static_cast<std::size_t>(n_max) + kPad;
  out.m = m;
  out.x = x;
  // The kernels write whole vectors: room for them, then trimmed (resize keeps the storage).
  out.a.resize(size);
  out.b.resize(size);
  solve(m, x, n_max, reinterpret_cast<double*>(out.a.data()), reinterpret_cast<double*>(out.b.data()), nullptr);
  out.a.resize(static_cast<std::size_t>(n_max));
  out.b.resize(static_cast<std::size_t>(n_max));
}

MieCoefficients mie_coefficients(Complex m, double x, int n_terms) {
  MieCoefficients c;
  mie_coefficients(m, x, c, n_terms);
  return c;
}

MieEfficiencies mie_efficiencies(const MieCoefficients& c) {
  require_size_parameter(c.x);
  if (c.a.size() != c.b.size()) throw Error("mie_efficiencies: a and b differ in length");
  double s[5] = {};
  if (c.terms() > 0)
    HYDROLUX_SIMD_DISPATCH(SumsKernel)(reinterpret_cast<const double*>(c.a.data()),
                                       reinterpret_cast<const double*>(c.b.data()),
                                       static_cast<std::size_t>(c.terms()), s);
  return efficiencies_from(s, c.x, c.m);
}

MieEfficiencies mie_efficiencies(Complex m, double x, int n_terms) {
  require_size_parameter(x);
  require_index(m);
  require_in_range("n_terms", n_terms, 0, 2e7, kContext);
  const int n_max = n_terms > 0 ? n_terms : mie_terms(x);
  Workspace& w = workspace();
  const std::size_t size = 2 * (static_cast<std::size_t>(n_max) + kPad);
  double* a = grow(w.a, size);
  double* b = grow(w.b, size);
  double s[5] = {};
  solve(m, x, n_max, a, b, s);
  return efficiencies_from(s, x, m);
}

MieBulkOptics mie_bulk_optics(Complex m, double wavenumber_per_m, const RadiusQuadrature& q, int threads) {
  require_index(m);
  require_in_range("wavenumber_per_m", wavenumber_per_m, 1e-300, 1e300, kContext);
  for (const double a : q.radius_m) require_size_parameter(wavenumber_per_m * a);
  // Each radius's cross sections into its own slot, then one ordered sum.
  std::vector<std::array<double, 5>> per(q.size());
  const auto run = [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t i = r.begin(); i != r.end(); ++i) {
      const double a = q.radius_m[i], area = kPi<double> * a * a;
      const MieEfficiencies e = mie_efficiencies(m, wavenumber_per_m * a);
      per[i] = {area * e.qext, area * e.qsca, area * e.qabs, area * e.qback, area * e.qsca * e.g};
    }
  };
  const int max_threads = tbb::this_task_arena::max_concurrency();
  const int use = threads <= 0 ? max_threads : std::min(threads, max_threads);
  if (use == 1 || q.size() < 2) {
    run(tbb::blocked_range<std::size_t>(0, q.size()));
  } else {
    tbb::task_arena arena(use);
    arena.execute([&] { tbb::parallel_for(tbb::blocked_range<std::size_t>(0, q.size(), 1), run); });
  }
  std::array<double, 5> sum{};
  for (std::size_t i = 0; i < q.size(); ++i)
    for (std::size_t k = 0; k < 5; ++k) sum[k] += q.weight[i] * per[i][k];
  MieBulkOptics out;
  out.extinction_per_m = sum[0];
  out.scattering_per_m = sum[1];
  out.absorption_per_m = sum[2];
  out.backscatter_per_m = sum[3];
  out.g = sum[1] > 0 ? sum[4] / sum[1] : 0.0;
  return out;
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
#endif  // HWY_ONCE
