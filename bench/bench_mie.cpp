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

const Complex kWater(1.333, 1e-8);

// The efficiencies alone (no angles): range(0) = x.
void BM_MieEfficiencies(benchmark::State& state) {
  const double x = double(state.range(0));
  for (auto _ : state) benchmark::DoNotOptimize(mie_efficiencies(kWater, x));
  state.SetLabel("x=" + std::to_string(state.range(0)) + ", " + std::to_string(mie_terms(x)) + " terms");
}
BENCHMARK(BM_MieEfficiencies)->RangeMultiplier(10)->Range(1, 1000000)->Unit(benchmark::kMicrosecond);

// The coefficients into a reused MieCoefficients.
void BM_MieCoefficients(benchmark::State& state) {
  const double x = double(state.range(0));
  MieCoefficients c;
  for (auto _ : state) {
    mie_coefficients(kWater, x, c);
    benchmark::DoNotOptimize(c.a.data());
  }
  state.SetLabel("x=" + std::to_string(state.range(0)));
}
BENCHMARK(BM_MieCoefficients)->RangeMultiplier(10)->Range(1, 1000000)->Unit(benchmark::kMicrosecond);

// The whole job of the side-by-side comparison with MIEV0 (BENCHMARKS.md): coefficients,
// efficiencies and S1/S2 at 1801 angles 0..180 degrees, one thread: range(0) = x.
void BM_MieFull(benchmark::State& state) {
  const double x = double(state.range(0));
  const auto mu = grid(1801);
  std::vector<Complex> s1(mu.size()), s2(mu.size());
  MieCoefficients c;
  for (auto _ : state) {
    mie_coefficients(kWater, x, c);
    benchmark::DoNotOptimize(mie_efficiencies(c));
    mie_amplitudes(c, mu, s1, s2, 1);
    benchmark::DoNotOptimize(s1.data());
  }
  state.SetLabel("x=" + std::to_string(state.range(0)));
}
BENCHMARK(BM_MieFull)->RangeMultiplier(10)->Range(1, 100000)->Unit(benchmark::kMicrosecond)->UseRealTime();

// S1, S2 at x = 10 000 on 1801 angles 0..180: range(0) = threads (0 = all).
void BM_MieAmplitudes(benchmark::State& state) {
  const auto c = mie_coefficients(kWater, 10000.0);
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

void BM_MieAmplitudesReference(benchmark::State& state) {
  const auto c = mie_coefficients(kWater, 10000.0);
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
