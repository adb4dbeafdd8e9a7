// One core's double-precision FMA peak on this machine, with the widest SIMD target hydrolux picks
// at run time (hydrolux::simd, as the library's kernels): 24 independent accumulator chains of fused multiply-adds (enough to cover the FMA
// latency on every current x86 and Arm core). FLOP/s counts 2 per FMA per lane.

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "bench/bench_peak.cpp"  // NOLINT
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

HWY_BEFORE_NAMESPACE();
namespace bench_peak::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// Returns a value that depends on every FMA so nothing is optimised away.
double FmaLoop(std::size_t iterations, double* flops) {
  const hn::ScalableTag<double> d;
  using V = hn::Vec<decltype(d)>;
  const V a = hn::Set(d, 0.999999), b = hn::Set(d, 1e-7);
  V acc[24];
  for (int k = 0; k < 24; ++k) acc[k] = hn::Set(d, 1.0 + k);
  for (std::size_t i = 0; i < iterations; ++i) {
#pragma GCC unroll 24
    for (int k = 0; k < 24; ++k) acc[k] = hn::MulAdd(acc[k], a, b);  // fully unrolled: in registers
  }
  V sum = hn::Zero(d);
  for (int k = 0; k < 24; ++k) sum = hn::Add(sum, acc[k]);
  *flops = 2.0 * 24.0 * double(hn::Lanes(d)) * double(iterations);
  return hn::GetLane(sum);
}
const char* Target() { return hwy::TargetName(HWY_TARGET); }

}  // namespace bench_peak::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
#include <benchmark/benchmark.h>

#include <string>

#include "src/core/simd_dispatch.hpp"

namespace bench_peak {
HYDROLUX_SIMD_EXPORT(FmaLoop);
HYDROLUX_SIMD_EXPORT(Target);

void BM_PeakFma(benchmark::State& state) {
  double flops = 0, total = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(HYDROLUX_SIMD_DISPATCH(FmaLoop)(1 << 16, &flops));
    total += flops;
  }
  state.counters["flops"] = benchmark::Counter(total, benchmark::Counter::kIsRate);
  state.SetLabel(std::string(HYDROLUX_SIMD_DISPATCH(Target)()) + ", one core");
}
BENCHMARK(BM_PeakFma);
}  // namespace bench_peak

BENCHMARK_MAIN();
#endif
