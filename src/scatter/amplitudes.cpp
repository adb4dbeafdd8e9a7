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
// Per-term constants, one cache line per n: c_n a_n, c_n b_n with c_n = (2n+1)/(n(n+1)), and the
// recurrence factors alpha_n = (2n-1)/(n-1), beta_n = n/(n-1), n, n+1.
struct Term {
  double a_re, a_im, b_re, b_im, alpha, beta, n, n1;
};
}  // namespace hydrolux::scatter::detail
#endif

HWY_BEFORE_NAMESPACE();
namespace hydrolux::scatter::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;
using detail::Term;

// For `count` values of mu >= 0 (a multiple of the lane count), writes S1(+mu), S2(+mu), S1(-mu),
// S2(-mu) as 8 arrays of `count` doubles: s1p re/im, s2p re/im, s1m re/im, s2m re/im.
void SumAmplitudes(const double* HWY_RESTRICT mu, std::size_t count, const Term* HWY_RESTRICT t,
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
    V pi_prev = hn::Zero(d);   // pi_{n-1}
    V pi = hn::Set(d, 1.0);    // pi_n, starting at pi_1 = 1
    // One term: tau_n = n mu pi_n - (n+1) pi_{n-1}, accumulate, then advance pi.
    auto term = [&](const Term& k, const Term& next, V& Pr, V& Pi, V& Qr, V& Qi, V& Rr, V& Ri, V& Ur,
                    V& Ui) HWY_ATTR {
      const V mu_pi = hn::Mul(m, pi);
      const V tau = hn::MulSub(hn::Set(d, k.n), mu_pi, hn::Mul(hn::Set(d, k.n1), pi_prev));
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
      // pi_{n+1} = alpha_{n+1} mu pi_n - beta_{n+1} pi_{n-1}: one FMA on the dependency chain.
      const V next_pi = hn::MulSub(hn::Set(d, next.alpha), mu_pi, hn::Mul(hn::Set(d, next.beta), pi_prev));
      pi_prev = pi;
      pi = next_pi;
    };
    // t has n_terms + 1 entries (the last is a sentinel for the final recurrence step).
    std::size_t n = 1;
    for (; n + 1 <= n_terms; n += 2) {
      term(t[n - 1], t[n], Por, Poi, Qor, Qoi, Ror, Roi, Uor, Uoi);      // odd n
      term(t[n], t[n + 1], Per, Pei, Qer, Qei, Rer, Rei, Uer, Uei);      // even n + 1
    }
    if (n == n_terms) term(t[n - 1], t[n], Por, Poi, Qor, Qoi, Ror, Roi, Uor, Uoi);
    // S1(mu) = P + Q; S1(-mu) = (Po - Pe) - (Qo - Qe); S2(mu) = R + U; S2(-mu) = (Ue - Uo)... see
    // header: pi terms change sign with even n, tau terms with odd n.
    const V p_sum_r = hn::Add(Por, Per), p_sum_i = hn::Add(Poi, Pei);
    const V q_sum_r = hn::Add(Qor, Qer), q_sum_i = hn::Add(Qoi, Qei);
    const V r_sum_r = hn::Add(Ror, Rer), r_sum_i = hn::Add(Roi, Rei);
    const V u_sum_r = hn::Add(Uor, Uer), u_sum_i = hn::Add(Uoi, Uei);
    const V p_alt_r = hn::Sub(Por, Per), p_alt_i = hn::Sub(Poi, Pei);  // pi-type: sign (-1)^(n-1)
    const V q_alt_r = hn::Sub(Qer, Qor), q_alt_i = hn::Sub(Qei, Qoi);  // tau-type: sign (-1)^n
    const V r_alt_r = hn::Sub(Rer, Ror), r_alt_i = hn::Sub(Rei, Roi);
    const V u_alt_r = hn::Sub(Uor, Uer), u_alt_i = hn::Sub(Uoi, Uei);
    hn::StoreU(hn::Add(p_sum_r, q_sum_r), d, out + 0 * stride + i);
    hn::StoreU(hn::Add(p_sum_i, q_sum_i), d, out + 1 * stride + i);
    hn::StoreU(hn::Add(r_sum_r, u_sum_r), d, out + 2 * stride + i);
    hn::StoreU(hn::Add(r_sum_i, u_sum_i), d, out + 3 * stride + i);
    hn::StoreU(hn::Add(p_alt_r, q_alt_r), d, out + 4 * stride + i);
    hn::StoreU(hn::Add(p_alt_i, q_alt_i), d, out + 5 * stride + i);
    hn::StoreU(hn::Add(r_alt_r, u_alt_r), d, out + 6 * stride + i);
    hn::StoreU(hn::Add(r_alt_i, u_alt_i), d, out + 7 * stride + i);
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

  // Per-term constants (+1 sentinel entry for the last recurrence step).
  std::vector<detail::Term> terms;
  terms.reserve(n_terms + 1);
  for (std::size_t k = 0; k <= n_terms; ++k) {
    const double n = double(k + 1);
    const double cn = (2 * n + 1) / (n * (n + 1));
    const Complex a = k < n_terms ? cn * c.a[k] : Complex(0);
    const Complex b = k < n_terms ? cn * c.b[k] : Complex(0);
    const double alpha = n > 1 ? (2 * n - 1) / (n - 1) : 0;
    const double beta = n > 1 ? n / (n - 1) : 0;
    terms.push_back({a.real(), a.imag(), b.real(), b.imag(), alpha, beta, n, n + 1});
  }

  // Unique |mu| values (merged within kMergeMu, see the header), padded to whole vectors.
  constexpr double kMergeMu = 1e-15;
  std::vector<double> abs_mu(mu.size());
  for (std::size_t i = 0; i < mu.size(); ++i) abs_mu[i] = std::abs(mu[i]);
  std::vector<double> unique = abs_mu;
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
    // The merged value nearest to |mu| (it lies within kMergeMu).
    auto it = std::lower_bound(unique.begin(), unique.begin() + std::ptrdiff_t(count), abs_mu[i] - kMergeMu);
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
