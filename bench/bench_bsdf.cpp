// Google Benchmark of the microfacet BSDFs: f, pdf and sample for Torrance-Sparrow (GGX and
// Beckmann, gold conductor Fresnel) and the rough dielectric (water, eta 1.333), plus the two
// visible-normal samplers on their own. Inputs are pre-generated (fixed seed) and cycled, so the
// timings exclude random-number generation.
//
// Run: build/bin/bench_bsdf [--benchmark_filter=Rough]
#include <benchmark/benchmark.h>

#include <array>
#include <complex>
#include <cstddef>

#include "hydrolux/core/random.hpp"
#include "hydrolux/optics/bsdf.hpp"

namespace {

using hydrolux::Rng;
using hydrolux::Vec3;
using namespace hydrolux::optics;

constexpr std::size_t kInputs = 1024;  // a power of two, cycled with a mask

struct Inputs {
  std::array<Vec3, kInputs> wo, wi;
  std::array<double, kInputs> uc, u1, u2;
};

// Directions uniform on the sphere (wo) and pairs on either side (wi), seeded.
const Inputs& inputs() {
  static const Inputs in = [] {
    Inputs r;
    Rng rng(2024);
    const auto sphere = [&rng] {
      const double z = 1.0 - 2.0 * rng.uniform();
      const double s = std::sqrt(std::max(0.0, 1.0 - z * z));
      const double phi = 2.0 * hydrolux::kPi<double> * rng.uniform();
      return Vec3(s * std::cos(phi), s * std::sin(phi), z);
    };
    for (std::size_t i = 0; i < kInputs; ++i) {
      r.wo[i] = sphere();
      r.wi[i] = sphere();
      r.uc[i] = rng.uniform();
      r.u1[i] = rng.uniform();
      r.u2[i] = rng.uniform();
    }
    return r;
  }();
  return in;
}

MicrofacetModel model_of(const benchmark::State& state) {
  return state.range(0) == 0 ? MicrofacetModel::TrowbridgeReitz : MicrofacetModel::Beckmann;
}

const char* label_of(const benchmark::State& state) {
  return state.range(0) == 0 ? "GGX" : "Beckmann";
}

TorranceSparrow make_ts(const benchmark::State& state) {
  return TorranceSparrow(MicrofacetDistribution::make(model_of(state), 0.3, 0.3),
                         Fresnel::conductor({0.25, 2.98}));
}

RoughDielectric make_rough(const benchmark::State& state) {
  return RoughDielectric(MicrofacetDistribution::make(model_of(state), 0.3, 0.3), 1.333);
}

// f and pdf on same-side pairs for the BRDF (wi flipped to wo's side), arbitrary pairs otherwise.
template <typename Make>
void bench_f(benchmark::State& state, Make make, bool same_side) {
  const auto bxdf = make(state);
  const Inputs& in = inputs();
  std::size_t i = 0;
  for (auto _ : state) {
    const Vec3& wo = in.wo[i];
    Vec3 wi = in.wi[i];
    if (same_side && wi.z * wo.z < 0) wi.z = -wi.z;
    benchmark::DoNotOptimize(bxdf.f(wo, wi, TransportMode::Radiance));
    i = (i + 1) & (kInputs - 1);
  }
  state.SetLabel(label_of(state));
}

template <typename Make>
void bench_pdf(benchmark::State& state, Make make, bool same_side) {
  const auto bxdf = make(state);
  const Inputs& in = inputs();
  std::size_t i = 0;
  for (auto _ : state) {
    const Vec3& wo = in.wo[i];
    Vec3 wi = in.wi[i];
    if (same_side && wi.z * wo.z < 0) wi.z = -wi.z;
    benchmark::DoNotOptimize(bxdf.pdf(wo, wi));
    i = (i + 1) & (kInputs - 1);
  }
  state.SetLabel(label_of(state));
}

template <typename Make>
void bench_sample(benchmark::State& state, Make make) {
  const auto bxdf = make(state);
  const Inputs& in = inputs();
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(
        bxdf.sample(in.wo[i], in.uc[i], {in.u1[i], in.u2[i]}, TransportMode::Radiance));
    i = (i + 1) & (kInputs - 1);
  }
  state.SetLabel(label_of(state));
}

void BM_TorranceSparrow_f(benchmark::State& s) { bench_f(s, make_ts, true); }
void BM_TorranceSparrow_pdf(benchmark::State& s) { bench_pdf(s, make_ts, true); }
void BM_TorranceSparrow_sample(benchmark::State& s) { bench_sample(s, make_ts); }
void BM_RoughDielectric_f(benchmark::State& s) { bench_f(s, make_rough, false); }
void BM_RoughDielectric_pdf(benchmark::State& s) { bench_pdf(s, make_rough, false); }
void BM_RoughDielectric_sample(benchmark::State& s) { bench_sample(s, make_rough); }

void BM_VisibleNormalSample(benchmark::State& state) {
  const auto d = MicrofacetDistribution::make(model_of(state), 0.3, 0.3);
  const Inputs& in = inputs();
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(d.sample_visible_normal(in.wo[i], in.u1[i], in.u2[i]));
    i = (i + 1) & (kInputs - 1);
  }
  state.SetLabel(label_of(state));
}

// Arg 0: GGX, 1: Beckmann.
BENCHMARK(BM_TorranceSparrow_f)->Arg(0)->Arg(1);
BENCHMARK(BM_TorranceSparrow_pdf)->Arg(0)->Arg(1);
BENCHMARK(BM_TorranceSparrow_sample)->Arg(0)->Arg(1);
BENCHMARK(BM_RoughDielectric_f)->Arg(0)->Arg(1);
BENCHMARK(BM_RoughDielectric_pdf)->Arg(0)->Arg(1);
BENCHMARK(BM_RoughDielectric_sample)->Arg(0)->Arg(1);
BENCHMARK(BM_VisibleNormalSample)->Arg(0)->Arg(1);

}  // namespace

BENCHMARK_MAIN();
