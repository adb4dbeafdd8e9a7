// Fast Mie amplitude sums: Highway SIMD across angles, parity-split sums for +-mu, oneTBB blocks.
// See include/hydrolux/scatter/amplitudes.hpp for the method.

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "src/scatter/amplitudes.cpp"  // NOLINT
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <vector>

#include "hydrolux/scatter/amplitudes.hpp"

// This file is compiled once per SIMD target (foreach_target re-includes it): shared types are
// defined once, outside the per-target namespaces.
#ifndef HYDROLUX_SCATTER_AMPLITUDES_TERM
#define HYDROLUX_SCATTER_AMPLITUDES_TERM
namespace hydrolux::scatter::detail {
// Per-term constants: c_n a_n, c_n b_n with c_n = (2n+1)/(n(n+1)), n, and r_n = (n+1)/n for
// Wiscombe's form of the Legendre recurrence (see SumAmplitudes).
struct Term {
  double a_re, a_im, b_re, b_im, n, r;
};
// Where SumAmplitudes writes. Scratch mode (scratch != nullptr): S1(+mu), S2(+mu), S1(-mu),
// S2(-mu) as 4 arrays of complex values, `stride` values apart. Direct mode, for a grid symmetric
// about 90 degrees: key k is |mu[k]| for k in the first half, and the results go straight into
// s1, s2 (complex, n values): S at the sign of mu[k] to index k, S at the other sign to n-1-k.
struct AmplitudeOut {
  double* scratch = nullptr;
  std::size_t stride = 0;
  double *s1 = nullptr, *s2 = nullptr;
  const double* mu = nullptr;
  std::size_t n = 0;
};
}  // namespace hydrolux::scatter::detail
#endif

HWY_BEFORE_NAMESPACE();
namespace hydrolux::scatter::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;
using detail::AmplitudeOut;
using detail::Term;

// For the `count` keys |mu| at keys[first..first+count) (count a multiple of the lane count),
// S1(+mu), S2(+mu), S1(-mu), S2(-mu), written as `out` says (detail::AmplitudeOut).
void SumAmplitudes(const double* HWY_RESTRICT keys, std::size_t first, std::size_t count,
                   const Term* HWY_RESTRICT terms, std::size_t n_terms, const AmplitudeOut& out) {
  const hn::ScalableTag<double> d;
  const std::size_t lanes = hn::Lanes(d);
  using V = hn::Vec<decltype(d)>;
  for (std::size_t i = first; i < first + count; i += lanes) {
    const V m = hn::LoadU(d, keys + i);
    // Accumulators by parity of n: P = sum c a pi, Q = sum c b tau (S1), R = sum c a tau,
    // U = sum c b pi (S2); suffix o/e for odd/even n, r/i for real/imaginary part.
    V Por = hn::Zero(d), Poi = hn::Zero(d), Qor = hn::Zero(d), Qoi = hn::Zero(d);
    V Ror = hn::Zero(d), Roi = hn::Zero(d), Uor = hn::Zero(d), Uoi = hn::Zero(d);
    V Per = hn::Zero(d), Pei = hn::Zero(d), Qer = hn::Zero(d), Qei = hn::Zero(d);
    V Rer = hn::Zero(d), Rei = hn::Zero(d), Uer = hn::Zero(d), Uei = hn::Zero(d);
    // Running S1(+mu), S1(-mu), S2(+mu), S2(-mu) (re, im): the parity accumulators are folded in
    // every kBlock terms, so they never grow beyond one block's worth. Near backscatter pi_n keeps
    // its sign, the parity sums of a whole series would reach x^2 while S ~ x, and subtracting
    // them at the end would lose x * 1e-16 relative (4e-9 at x = 1e5).
    V s1p_r = hn::Zero(d), s1p_i = hn::Zero(d), s1m_r = hn::Zero(d), s1m_i = hn::Zero(d);
    V s2p_r = hn::Zero(d), s2p_i = hn::Zero(d), s2m_r = hn::Zero(d), s2m_i = hn::Zero(d);
    const auto fold = [&]() HWY_ATTR {
      // pi-type terms (P, U) change sign with even n under mu -> -mu, tau-type (Q, R) with odd n.
      s1p_r = hn::Add(s1p_r, hn::Add(hn::Add(Por, Per), hn::Add(Qor, Qer)));
      s1p_i = hn::Add(s1p_i, hn::Add(hn::Add(Poi, Pei), hn::Add(Qoi, Qei)));
      s1m_r = hn::Add(s1m_r, hn::Add(hn::Sub(Por, Per), hn::Sub(Qer, Qor)));
      s1m_i = hn::Add(s1m_i, hn::Add(hn::Sub(Poi, Pei), hn::Sub(Qei, Qoi)));
      s2p_r = hn::Add(s2p_r, hn::Add(hn::Add(Ror, Rer), hn::Add(Uor, Uer)));
      s2p_i = hn::Add(s2p_i, hn::Add(hn::Add(Roi, Rei), hn::Add(Uoi, Uei)));
      s2m_r = hn::Add(s2m_r, hn::Add(hn::Sub(Rer, Ror), hn::Sub(Uor, Uer)));
      s2m_i = hn::Add(s2m_i, hn::Add(hn::Sub(Rei, Roi), hn::Sub(Uoi, Uei)));
      Por = Poi = Qor = Qoi = Ror = Roi = Uor = Uoi = hn::Zero(d);
      Per = Pei = Qer = Qei = Rer = Rei = Uer = Uei = hn::Zero(d);
    };
    constexpr std::size_t kBlock = 16;  // terms per fold (even, so a block holds whole odd/even pairs)
    // The angle functions in Wiscombe's form (MIEV0; Wiscombe 1980): with s = mu pi_n and
    // t = s - pi_{n-1},  tau_n = n t - pi_{n-1}  and  pi_{n+1} = s + r_n t,  r_n = (n+1)/n.
    // The rounded r_n multiplies t ~ n rather than pi_n ~ n^2, so near mu = +-1 (where pi_n grows
    // like n^2 and the sums cancel down to ~x) the recurrence stays at rounding; at mu = +-1 it is
    // exact. s is carried as s_{n+1} = mu s + (mu r_n) t, keeping two operations on the chain.
    V pi_prev = hn::Zero(d);   // pi_{n-1}
    V pi = hn::Set(d, 1.0);    // pi_n, starting at pi_1 = 1
    V s = m;                   // mu pi_n
    auto term = [&](const Term& k, V& Pr, V& Pi, V& Qr, V& Qi, V& Rr, V& Ri, V& Ur, V& Ui) HWY_ATTR {
      const V t = hn::Sub(s, pi_prev);
      const V tau = hn::MulSub(hn::Set(d, k.n), t, pi_prev);
      const V ar = hn::Set(d, k.a_re), ai = hn::Set(d, k.a_im);
      const V br = hn::Set(d, k.b_re), bi = hn::Set(d, k.b_im);
      Pr = hn::MulAdd(ar, pi, Pr);
      Pi = hn::MulAdd(ai, pi, Pi);
      Qr = hn::MulAdd(br, tau, Qr);
      Qi = hn::MulAdd(bi, tau, Qi);
      Rr = hn::MulAdd(ar, tau, Rr);
      Ri = hn::MulAdd(ai, tau, Ri);
      Ur = hn::MulAdd(br, pi, Ur);
      Ui = hn::MulAdd(bi, pi, Ui);
      const V r = hn::Set(d, k.r);
      const V next_pi = hn::MulAdd(r, t, s);
      s = hn::MulAdd(hn::Mul(m, r), t, hn::Mul(m, s));
      pi_prev = pi;
      pi = next_pi;
    };
    std::size_t n = 1;
    for (; n + 1 <= n_terms; n += 2) {
      term(terms[n - 1], Por, Poi, Qor, Qoi, Ror, Roi, Uor, Uoi);  // odd n
      term(terms[n], Per, Pei, Qer, Qei, Rer, Rei, Uer, Uei);      // even n + 1
      if ((n + 1) % kBlock == 0) fold();
    }
    if (n == n_terms) term(terms[n - 1], Por, Poi, Qor, Qoi, Ror, Roi, Uor, Uoi);
    fold();
    if (out.scratch) {
      double* o = out.scratch;
      const std::size_t stride = out.stride;
      hn::StoreInterleaved2(s1p_r, s1p_i, d, o + 2 * (0 * stride + i));
      hn::StoreInterleaved2(s2p_r, s2p_i, d, o + 2 * (1 * stride + i));
      hn::StoreInterleaved2(s1m_r, s1m_i, d, o + 2 * (2 * stride + i));
      hn::StoreInterleaved2(s2m_r, s2m_i, d, o + 2 * (3 * stride + i));
      continue;
    }
    // Direct: index i+j takes the sign of mu[i+j]; index n-1-i-j the other, stored as one block
    // at n-i-lanes in reversed lane order. (mu = -0.0 counts as +0.)
    const auto positive = hn::Ge(hn::LoadU(d, out.mu + i), hn::Zero(d));
    const std::size_t back = 2 * (out.n - i - lanes);
    hn::StoreInterleaved2(hn::Reverse(d, hn::IfThenElse(positive, s1m_r, s1p_r)),
                          hn::Reverse(d, hn::IfThenElse(positive, s1m_i, s1p_i)), d, out.s1 + back);
    hn::StoreInterleaved2(hn::Reverse(d, hn::IfThenElse(positive, s2m_r, s2p_r)),
                          hn::Reverse(d, hn::IfThenElse(positive, s2m_i, s2p_i)), d, out.s2 + back);
    hn::StoreInterleaved2(hn::IfThenElse(positive, s1p_r, s1m_r), hn::IfThenElse(positive, s1p_i, s1m_i), d,
                          out.s1 + 2 * i);
    hn::StoreInterleaved2(hn::IfThenElse(positive, s2p_r, s2m_r), hn::IfThenElse(positive, s2p_i, s2m_i), d,
                          out.s2 + 2 * i);
  }
}

// One pass over the angles' mu: bit 0 of the result set if any lies outside [-1, 1] (or is NaN),
// bit 1 if the grid is not symmetric about 90 degrees (|mu[i] + mu[n-1-i]| > merge for some i).
int ScanMu(const double* HWY_RESTRICT mu, std::size_t n, double merge) {
  const hn::ScalableTag<double> d;
  const std::size_t lanes = hn::Lanes(d);
  const auto one = hn::Set(d, 1.0), tol = hn::Set(d, merge);
  auto bad = hn::Zero(d), asym = hn::Zero(d);  // lane-wise maxima of violations
  std::size_t i = 0;
  for (; i + lanes <= n; i += lanes) {
    const auto v = hn::LoadU(d, mu + i);
    // |v| <= 1 is false for NaN: the violation 1 - (|v| <= 1) is then counted.
    bad = hn::Or(bad, hn::IfThenZeroElse(hn::Le(hn::Abs(v), one), one));
  }
  int flags = 0;
  for (; i < n; ++i)
    if (!(mu[i] >= -1.0 && mu[i] <= 1.0)) flags |= 1;
  if (!hn::AllTrue(d, hn::Eq(bad, hn::Zero(d)))) flags |= 1;
  const std::size_t half = n / 2;
  i = 0;
  for (; i + lanes <= half; i += lanes) {
    // mu[n-1-i-j] for j = 0..lanes-1, reversed into lane order j.
    const auto a = hn::LoadU(d, mu + i);
    const auto b = hn::Reverse(d, hn::LoadU(d, mu + n - i - lanes));
    asym = hn::Or(asym, hn::IfThenZeroElse(hn::Le(hn::Abs(hn::Add(a, b)), tol), one));
  }
  for (; i < half; ++i)
    if (!(std::abs(mu[i] + mu[n - 1 - i]) <= merge)) flags |= 2;
  if (!hn::AllTrue(d, hn::Eq(asym, hn::Zero(d)))) flags |= 2;
  if (n % 2 == 1 && !(std::abs(mu[half]) <= merge)) flags |= 2;
  return flags;
}

std::size_t LaneCount() { return hn::Lanes(hn::ScalableTag<double>()); }
const char* TargetName() { return hwy::TargetName(HWY_TARGET); }

}  // namespace hydrolux::scatter::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <atomic>
#include <mutex>

#include "src/core/simd_dispatch.hpp"

namespace hydrolux::scatter {

HYDROLUX_SIMD_EXPORT(SumAmplitudes);
HYDROLUX_SIMD_EXPORT(LaneCount);
HYDROLUX_SIMD_EXPORT(ScanMu);
HYDROLUX_SIMD_EXPORT(TargetName);

std::string simd_target() { return HYDROLUX_SIMD_DISPATCH(TargetName)(); }

namespace {

// Per-thread scratch of mie_amplitudes; it only grows.
struct AmplitudeScratch {
  std::vector<detail::Term> terms;
  std::vector<std::uint32_t> order, id;
  std::vector<double> key, unique, out;
};
AmplitudeScratch& scratch() {
  thread_local AmplitudeScratch s;
  return s;
}

// The evaluation keys. A grid symmetric about 90 degrees (mu[n-1-i] = -mu[i] within kMergeMu, as
// 0..180 degrees in equal steps) is the common case and needs no search: unique[k] = |mu[k]| for
// the first half, k < (n+1)/2, whose results serve mu[k] and mu[n-1-k]; *mirror is set.
// Otherwise unique[0..count) are the keys in increasing order, merged where consecutive keys are
// within kMergeMu (see the header), and id[i] is the key of mu[i]. Returns count.
constexpr double kMergeMu = 1e-15;
std::size_t merge_keys(std::span<const double> mu, int flags, AmplitudeScratch& sc, bool* mirror) {
  const std::size_t n = mu.size();
  double* unique = sc.unique.data();
  *mirror = (flags & 2) == 0;
  if (*mirror) {
    const std::size_t half = (n + 1) / 2;
    for (std::size_t k = 0; k < half; ++k) unique[k] = std::abs(mu[k]);
    return half;
  }
  sc.key.resize(n);
  sc.order.resize(n);
  sc.id.resize(n);
  double* key = sc.key.data();
  std::uint32_t* order = sc.order.data();
  std::uint32_t* id = sc.id.data();
  int rises = 0, falls = 0;
  for (std::size_t i = 0; i < n; ++i) key[i] = std::abs(mu[i]);
  for (std::size_t i = 1; i < n; ++i) {
    rises |= mu[i] > mu[i - 1];
    falls |= mu[i] < mu[i - 1];
  }
  const bool down = !rises, up = !falls;
  std::size_t count = 0;
  double last = -1;
  const auto assign = [&](std::uint32_t i) {
    if (key[i] - last > kMergeMu) unique[count++] = key[i];
    last = key[i];
    id[i] = static_cast<std::uint32_t>(count - 1);
  };
  if (down || up) {
    // Monotone: the run whose |mu| falls (read backwards from split - 1 to 0) and the run whose
    // |mu| rises (split to n - 1), merged.
    std::size_t split = 0;
    while (split < n && ((mu[split] >= 0) == down)) ++split;
    std::ptrdiff_t i = static_cast<std::ptrdiff_t>(split) - 1;
    std::size_t j = split, k = 0;
    while (i >= 0 && j < n) {
      if (key[i] <= key[j])
        order[k++] = static_cast<std::uint32_t>(i--);
      else
        order[k++] = static_cast<std::uint32_t>(j++);
    }
    while (i >= 0) order[k++] = static_cast<std::uint32_t>(i--);
    while (j < n) order[k++] = static_cast<std::uint32_t>(j++);
  } else {
    for (std::size_t i = 0; i < n; ++i) order[i] = static_cast<std::uint32_t>(i);
    std::sort(order, order + n, [&](std::uint32_t a, std::uint32_t b) { return key[a] < key[b]; });
  }
  for (std::size_t k = 0; k < n; ++k) assign(order[k]);
  return count;
}

}  // namespace

void mie_amplitudes(const MieCoefficients& c, std::span<const double> mu, std::span<Complex> s1,
                    std::span<Complex> s2, int threads, const ProgressFn& progress) {
  if (s1.size() != mu.size() || s2.size() != mu.size())
    throw std::invalid_argument("mie_amplitudes: mu, s1 and s2 must have the same size");
  if (mu.empty()) return;
  // One SIMD pass: outside [-1, 1] (NaN too)? symmetric about 90 degrees?
  const int flags = HYDROLUX_SIMD_DISPATCH(ScanMu)(mu.data(), mu.size(), kMergeMu);
  if (flags & 1) throw std::invalid_argument("mie_amplitudes: mu must lie in [-1, 1]");
  const std::size_t n_terms = c.a.size();
  AmplitudeScratch& sc = scratch();

  // Per-term constants.
  sc.terms.resize(n_terms);
  for (std::size_t k = 0; k < n_terms; ++k) {
    const double n = double(k + 1);
    const double cn = (2 * n + 1) / (n * (n + 1));
    const Complex a = cn * c.a[k];
    const Complex b = cn * c.b[k];
    sc.terms[k] = {a.real(), a.imag(), b.real(), b.imag(), n, (n + 1) / n};
  }

  // Evaluation keys |mu| (one pass gives S at +mu and -mu).
  const std::size_t lanes = HYDROLUX_SIMD_DISPATCH(LaneCount)();
  const std::size_t n = mu.size();
  if (n > std::numeric_limits<std::uint32_t>::max())
    throw std::invalid_argument("mie_amplitudes: more than 2^32 - 1 angles");
  sc.unique.resize(n + lanes);
  bool mirror = false;
  const std::size_t count = merge_keys(mu, flags, sc, &mirror);
  // Whole vectors of keys. A mirror grid's results go straight into s1, s2, except those of
  // its last, partial vector (scratch, copied below); other grids' all go to scratch.
  const std::size_t padded = (count + lanes - 1) / lanes * lanes;
  for (std::size_t k = count; k < padded; ++k) sc.unique[k] = sc.unique[count - 1];
  const std::size_t direct = mirror ? count / lanes * lanes : 0;
  sc.out.resize(8 * padded);  // S1(+mu), S2(+mu), S1(-mu), S2(-mu), complex
  const double* unique = sc.unique.data();
  const detail::Term* terms = sc.terms.data();
  double* out = sc.out.data();
  detail::AmplitudeOut to_scratch, to_result;
  to_scratch.scratch = out;
  to_scratch.stride = padded;
  to_result.s1 = reinterpret_cast<double*>(s1.data());
  to_result.s2 = reinterpret_cast<double*>(s2.data());
  to_result.mu = mu.data();
  to_result.n = n;

  // Blocks of a few vectors, run in parallel.
  const std::size_t block = 2 * lanes;
  const std::size_t blocks = (padded + block - 1) / block;
  // Progress, when the job is long enough to show: reported by whichever thread finishes a block
  // and finds no other thread reporting.
  const bool report = progress && double(n_terms) * double(count) > 1e9;
  std::atomic<std::size_t> blocks_done{0};
  std::mutex report_mutex;
  const auto run = [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t b = r.begin(); b != r.end(); ++b) {
      const std::size_t begin = b * block, end = std::min(begin + block, padded);
      // The direct part of this block, then the rest to scratch.
      const std::size_t split = std::clamp(direct, begin, end);
      if (split > begin)
        HYDROLUX_SIMD_DISPATCH(SumAmplitudes)(unique, begin, split - begin, terms, n_terms, to_result);
      if (end > split)
        HYDROLUX_SIMD_DISPATCH(SumAmplitudes)(unique, split, end - split, terms, n_terms, to_scratch);
      if (report) {
        const std::size_t done = blocks_done.fetch_add(1) + 1;
        std::unique_lock lock(report_mutex, std::try_to_lock);
        if (lock) progress(double(done) / double(blocks), "amplitudes");
      }
    }
  };
  const int max_threads = tbb::this_task_arena::max_concurrency();
  const int use = threads <= 0 ? max_threads : std::min(threads, max_threads);
  // Below ~2e5 term x angle products (~0.1 ms on one core) waking threads costs more than it saves:
  // the default 181 angles at x = 1 took 60 us on two threads, 13 us on one (BENCHMARKS.md).
  const bool small = double(n_terms) * double(padded) < 2e5;
  if (use == 1 || blocks == 1 || small) {
    run(tbb::blocked_range<std::size_t>(0, blocks));
  } else if (use == max_threads) {  // the caller's arena as it is: no arena to set up per call
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, blocks, 1), run);
  } else {
    tbb::task_arena arena(use);
    arena.execute([&] { tbb::parallel_for(tbb::blocked_range<std::size_t>(0, blocks, 1), run); });
  }

  // +mu or -mu results (mu = -0.0 is +0: same).
  const Complex* plus = reinterpret_cast<const Complex*>(out);
  const Complex* minus = plus + 2 * padded;
  if (mirror) {
    for (std::size_t k = direct; k < count; ++k) {
      const bool positive = mu[k] >= 0;
      s1[n - 1 - k] = (positive ? minus : plus)[k];
      s2[n - 1 - k] = (positive ? minus : plus)[k + padded];
      s1[k] = (positive ? plus : minus)[k];
      s2[k] = (positive ? plus : minus)[k + padded];
    }
    return;
  }
  const std::uint32_t* id = sc.id.data();
  for (std::size_t i = 0; i < n; ++i) {
    const Complex* base = (mu[i] >= 0 ? plus : minus) + id[i];
    s1[i] = base[0];
    s2[i] = base[padded];
  }
}

std::vector<double> mie_phase_function(const MieCoefficients& c, std::span<const double> mu, int threads) {
  std::vector<Complex> s1(mu.size()), s2(mu.size());
  mie_amplitudes(c, mu, s1, s2, threads);
  const double scale = 2 / (c.x * c.x * mie_efficiencies(c).qsca);
  std::vector<double> p(mu.size());
  for (std::size_t i = 0; i < mu.size(); ++i) p[i] = scale * (std::norm(s1[i]) + std::norm(s2[i]));
  return p;
}

}  // namespace hydrolux::scatter
#endif  // HWY_ONCE
