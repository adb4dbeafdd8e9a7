#pragma once
// Fast Mie amplitude sums S1(theta), S2(theta) (conventions in mie.hpp).
//
// The cost of Mie at large x is the double sum over terms n = 1..N (N ~ x) and angles. This path:
// - vectorises across angles with Google Highway, dispatched at run time to the widest instruction
//   set the CPU has (AVX-512, AVX2, SSE4, NEON, ... or scalar);
// - evaluates each |mu| once for both mu and -mu, using pi_n(-mu) = (-1)^(n-1) pi_n(mu) and
//   tau_n(-mu) = (-1)^n tau_n(mu) (Bohren & Huffman eq. 4.48): even and odd n are summed apart,
//   so a grid symmetric about 90 degrees costs half. |mu| values closer than 1e-15 (cos(theta)
//   and -cos(pi - theta) in floating point) are evaluated once: the change in S is below
//   x * 1e-15 relative, 1e-10 at x = 1e5. The parity sums are folded into S(+mu) and S(-mu)
//   every 16 terms, so they stay small even near backscatter (where pi_n keeps its sign);
// - keeps the Legendre recurrence in registers, in Wiscombe's form (exact at mu = +-1, accurate
//   near it, where B&H's eq. 4.47 form loses x * 1e-16);
// - runs blocks of angles in parallel with oneTBB.
// mie_amplitudes_reference (mie.hpp) is the scalar reference it is tested against.
#include <span>
#include <string>
#include <vector>

#include "hydrolux/core/progress.hpp"
#include "hydrolux/scatter/mie.hpp"

namespace hydrolux::scatter {

// S1, S2 at the given mu = cos(theta) (any order, duplicates allowed). threads: 0 = all cores,
// otherwise at most that many. Spans must have equal sizes and mu must lie in [-1, 1] (else
// std::invalid_argument). A grid symmetric about 90 degrees (the usual 0..180 in equal steps) or
// monotone costs O(angles) to organise; any other order is sorted. `progress`, if given, is called
// with the fraction done (from one thread at a time, not always the caller's) when there is enough
// work to report (about 1e9 term x angle evaluations).
void mie_amplitudes(const MieCoefficients& c, std::span<const double> mu, std::span<Complex> s1,
                    std::span<Complex> s2, int threads = 0, const ProgressFn& progress = {});

// The normalised phase function p(theta) = 2 (|S1|^2 + |S2|^2) / (x^2 Qsca) of unpolarised light at
// the given mu, so that (1/4pi) int p dOmega = 1 (mie.hpp), through the fast path.
std::vector<double> mie_phase_function(const MieCoefficients& c, std::span<const double> mu, int threads = 0);

// The SIMD instruction set mie_amplitudes dispatches to on this CPU, e.g. "AVX3" or "AVX2".
std::string simd_target();

}  // namespace hydrolux::scatter
