// Fast Mie amplitude sums: Highway SIMD across angles, parity-split sums for +-mu, oneTBB blocks.
// See include/hydrolux/scatter/amplitudes.hpp for the method.

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "src/scatter/amplitudes.cpp"  // NOLINT
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

#include <algorithm>
#include <cmath>
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
}  // namespace hydrolux::scatter::detail
#endif

HWY_BEFORE_NAMESPACE();
namespace hydrolux::scatter::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;
using detail::Term;

// For `count` values of mu >= 0 (a multiple of the lane count), writes S1(+mu), S2(+mu), S1(-mu),
// S2(-mu) as 8 arrays of `count` doubles: s1p re/im, s2p re/im, s1m re/im, s2m re/im.
void SumAmplitudes(const double* HWY_RESTRICT mu, std::size_t count, const Term* HWY_RESTRICT terms,
                   std::size_t n_terms, double* HWY_RESTRICT out, std::size_t stride) {
  const hn::ScalableTag<double> d;
  const std::size_t lanes = hn::Lanes(d);
  using V = hn::Vec<decltype(d)>;
  for (std::size_t i = 0; i < count; i += lanes) {
    const V m = hn::LoadU(d, mu + i);
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
    hn::StoreU(s1p_r, d, out + 0 * stride + i);
    hn::StoreU(s1p_i, d, out + 1 * stride + i);
    hn::StoreU(s2p_r, d, out + 2 * stride + i);
    hn::StoreU(s2p_i, d, out + 3 * stride + i);
    hn::StoreU(s1m_r, d, out + 4 * stride + i);
    hn::StoreU(s1m_i, d, out + 5 * stride + i);
    hn::StoreU(s2m_r, d, out + 6 * stride + i);
    hn::StoreU(s2m_i, d, out + 7 * stride + i);
  }
}

std::size_t LaneCount() { return hn::Lanes(hn::ScalableTag<double>()); }
const char* TargetName() { return hwy::TargetName(HWY_TARGET); }

}  // namespace hydrolux::scatter::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

namespace hydrolux::scatter {

HWY_EXPORT(SumAmplitudes);
HWY_EXPORT(LaneCount);
HWY_EXPORT(TargetName);

std::string simd_target() { return HWY_DYNAMIC_DISPATCH(TargetName)(); }

void mie_amplitudes(const MieCoefficients& c, std::span<const double> mu, std::span<Complex> s1,
                    std::span<Complex> s2, int threads) {
  if (s1.size() != mu.size() || s2.size() != mu.size())
    throw std::invalid_argument("mie_amplitudes: mu, s1 and s2 must have the same size");
  if (mu.empty()) return;
  const std::size_t n_terms = c.a.size();

  // Per-term constants.
  std::vector<detail::Term> terms;
  terms.reserve(n_terms);
  for (std::size_t k = 0; k < n_terms; ++k) {
    const double n = double(k + 1);
    const double cn = (2 * n + 1) / (n * (n + 1));
    const Complex a = cn * c.a[k];
    const Complex b = cn * c.b[k];
    terms.push_back({a.real(), a.imag(), b.real(), b.imag(), n, (n + 1) / n});
  }

  // Evaluation keys |mu| (one pass gives S at +mu and -mu), merged within kMergeMu (see the
  // header).
  constexpr double kMergeMu = 1e-15;
  for (const double m : mu)
    if (!(m >= -1.0 && m <= 1.0)) throw std::invalid_argument("mie_amplitudes: mu must lie in [-1, 1]");
  std::vector<double> keys(mu.size());
  for (std::size_t i = 0; i < mu.size(); ++i) keys[i] = std::abs(mu[i]);
  std::vector<double> unique = keys;
  std::sort(unique.begin(), unique.end());
  unique.erase(std::unique(unique.begin(), unique.end(),
                           [](double a, double b) { return b - a <= kMergeMu; }),
               unique.end());
  const std::size_t lanes = HWY_DYNAMIC_DISPATCH(LaneCount)();
  const std::size_t count = unique.size();
  const std::size_t padded = (count + lanes - 1) / lanes * lanes;
  unique.resize(padded, unique.back());
  std::vector<double> out(8 * padded);

  // Blocks of a few vectors, run in parallel.
  const std::size_t block = 2 * lanes;
  const std::size_t blocks = (padded + block - 1) / block;
  const auto run = [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t b = r.begin(); b != r.end(); ++b) {
      const std::size_t begin = b * block, len = std::min(block, padded - begin);
      HWY_DYNAMIC_DISPATCH(SumAmplitudes)(unique.data() + begin, len, terms.data(), n_terms,
                                          out.data() + begin, padded);
    }
  };
  const int max_threads = tbb::this_task_arena::max_concurrency();
  const int use = threads <= 0 ? max_threads : std::min(threads, max_threads);
  if (use == 1 || blocks == 1) {
    run(tbb::blocked_range<std::size_t>(0, blocks));
  } else {
    tbb::task_arena arena(use);
    arena.execute([&] { tbb::parallel_for(tbb::blocked_range<std::size_t>(0, blocks, 1), run); });
  }

  for (std::size_t i = 0; i < mu.size(); ++i) {
    // The merged key nearest to this one (it lies within kMergeMu).
    auto it = std::lower_bound(unique.begin(), unique.begin() + std::ptrdiff_t(count), keys[i] - kMergeMu);
    if (it == unique.begin() + std::ptrdiff_t(count)) --it;
    const std::size_t u = static_cast<std::size_t>(it - unique.begin());
    const std::size_t off = mu[i] >= 0 ? 0 : 4;  // +mu or -mu results (mu = -0.0 is +0: same)
    s1[i] = {out[(off + 0) * padded + u], out[(off + 1) * padded + u]};
    s2[i] = {out[(off + 2) * padded + u], out[(off + 3) * padded + u]};
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
