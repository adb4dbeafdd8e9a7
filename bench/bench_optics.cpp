// Interface optics throughput: Fresnel (dielectric fast path, full amplitudes, conductor),
// refraction, and medium lookups.
#include <benchmark/benchmark.h>

#include <vector>

#include "hydrolux/core/random.hpp"
#include "hydrolux/optics/fresnel.hpp"
#include "hydrolux/optics/media.hpp"
#include "hydrolux/optics/snell.hpp"

namespace {

using namespace hydrolux;

std::vector<double> cosines(std::size_t n) {
  Rng rng(7);
  std::vector<double> c(n);
  for (auto& v : c) v = 2 * rng.uniform() - 1;
  return c;
}

void BM_FrDielectric(benchmark::State& state) {
  const auto c = cosines(4096);
  for (auto _ : state) {
    double sum = 0;
    for (double v : c) sum += optics::fr_dielectric(v, 1.333);
    benchmark::DoNotOptimize(sum);
  }
  state.SetItemsProcessed(state.iterations() * std::int64_t(c.size()));
}
BENCHMARK(BM_FrDielectric);

void BM_FresnelDielectricAmplitudes(benchmark::State& state) {
  auto c = cosines(4096);
  for (auto& v : c) v = std::abs(v);
  for (auto _ : state) {
    double sum = 0;
    for (double v : c) sum += optics::fresnel_dielectric(v, 1.0, 1.333).T;
    benchmark::DoNotOptimize(sum);
  }
  state.SetItemsProcessed(state.iterations() * std::int64_t(c.size()));
}
BENCHMARK(BM_FresnelDielectricAmplitudes);

void BM_FrConductor(benchmark::State& state) {
  auto c = cosines(4096);
  for (auto& v : c) v = std::abs(v);
  const std::complex<double> gold(0.43, 2.455);
  for (auto _ : state) {
    double sum = 0;
    for (double v : c) sum += optics::fr_conductor(v, gold);
    benchmark::DoNotOptimize(sum);
  }
  state.SetItemsProcessed(state.iterations() * std::int64_t(c.size()));
}
BENCHMARK(BM_FrConductor);

void BM_Refract(benchmark::State& state) {
  Rng rng(9);
  std::vector<Vec3> w(4096);
  for (auto& v : w) {
    const double z = 2 * rng.uniform() - 1, phi = 2 * kPi<> * rng.uniform(), r = std::sqrt(1 - z * z);
    v = {r * std::cos(phi), r * std::sin(phi), z};
  }
  const Vec3 n{0, 0, 1};
  for (auto _ : state) {
    double sum = 0;
    for (const auto& v : w)
      if (auto t = optics::refract(v, n, 1.333)) sum += t->wt.z;
    benchmark::DoNotOptimize(sum);
  }
  state.SetItemsProcessed(state.iterations() * std::int64_t(w.size()));
}
BENCHMARK(BM_Refract);

void BM_MediumIndex(benchmark::State& state) {
  const char* names[] = {"water", "gold", "bk7"};
  const auto m = optics::find_medium(names[state.range(0)]);
  double l = 400;
  for (auto _ : state) {
    benchmark::DoNotOptimize(m->index(l));
    l = l < 700 ? l + 0.37 : 400;
  }
  state.SetLabel(names[state.range(0)]);
}
BENCHMARK(BM_MediumIndex)->DenseRange(0, 2);

}  // namespace

BENCHMARK_MAIN();
