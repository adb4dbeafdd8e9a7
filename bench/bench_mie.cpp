// Mie throughput: coefficients, and the S1/S2 sums over angles (the dominant cost) on one core and
// on all cores, fast path against the scalar reference. Reports term x angle evaluations per
// second: one evaluation is one n for one angle (both mu and -mu count when they pair up).
#include <benchmark/benchmark.h>

#include <cmath>
#include <vector>

#include "hydrolux/scatter/amplitudes.hpp"
#include "hydrolux/scatter/mie.hpp"

namespace {

using namespace hydrolux::scatter;

std::vector<double> grid(int n) {
  std::vector<double> mu(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) mu[std::size_t(i)] = std::cos(3.141592653589793 * i / (n - 1));
  return mu;
}

void BM_MieCoefficients(benchmark::State& state) {
  const double x = double(state.range(0));
  for (auto _ : state) benchmark::DoNotOptimize(mie_coefficients({1.333, 1e-8}, x));
  state.SetLabel("x=" + std::to_string(state.range(0)));
}
BENCHMARK(BM_MieCoefficients)->Arg(100)->Arg(1000)->Arg(10000)->Arg(100000)->Unit(benchmark::kMillisecond);

// S1, S2 at x = 10 000 on 1801 angles 0..180: range(0) = threads (0 = all).
void BM_MieAmplitudes(benchmark::State& state) {
  const auto c = mie_coefficients({1.333, 1e-8}, 10000.0);
  const auto mu = grid(1801);
  std::vector<Complex> s1(mu.size()), s2(mu.size());
  const int threads = int(state.range(0));
  for (auto _ : state) {
    mie_amplitudes(c, mu, s1, s2, threads);
    benchmark::DoNotOptimize(s1.data());
  }
  state.counters["term_angles_per_s"] = benchmark::Counter(
      double(c.terms()) * double(mu.size()) * double(state.iterations()), benchmark::Counter::kIsRate);
  state.SetLabel(simd_target() + (threads == 1 ? ", 1 thread" : ", all threads"));
}
BENCHMARK(BM_MieAmplitudes)->Arg(1)->Arg(0)->Unit(benchmark::kMillisecond)->UseRealTime();

// The whole job the issue times: coefficients + S1/S2 at 1801 angles for x = 10 000, one core.
void BM_MieFullX10000(benchmark::State& state) {
  const auto mu = grid(1801);
  std::vector<Complex> s1(mu.size()), s2(mu.size());
  for (auto _ : state) {
    const auto c = mie_coefficients({1.333, 1e-8}, 10000.0);
    mie_amplitudes(c, mu, s1, s2, 1);
    benchmark::DoNotOptimize(s1.data());
  }
}
BENCHMARK(BM_MieFullX10000)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_MieAmplitudesReference(benchmark::State& state) {
  const auto c = mie_coefficients({1.333, 1e-8}, 10000.0);
  const auto mu = grid(1801);
  std::vector<Complex> s1(mu.size()), s2(mu.size());
  for (auto _ : state) {
    mie_amplitudes_reference(c, mu, s1, s2);
    benchmark::DoNotOptimize(s1.data());
  }
  state.counters["term_angles_per_s"] = benchmark::Counter(
      double(c.terms()) * double(mu.size()) * double(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_MieAmplitudesReference)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
