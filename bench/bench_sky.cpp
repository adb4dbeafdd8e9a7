// hydrolux sky's per-frame cost at 1280 x 720 after the tables are loaded: the whole composite
// (sky, ground, bow, curtain, blend) per mode, the bow colour alone, and the cube map's bake. The
// tables are hydrolux sky's 500 um rainbow profile computed once, by Airy theory (its values do
// not change the cost).
#include <benchmark/benchmark.h>

#include "hydrolux/atmos/lee.hpp"
#include "hydrolux/scene/bow_tables.hpp"
#include "hydrolux/scene/compositor.hpp"

namespace {

using namespace hydrolux;

const scene::BowSlice& rainbow_slice() {
  static const scene::BowSlice s = [] {
    atmos::LeeSpec spec = scene::bow_table_spec(atmos::LeeTableKind::rainbow, 500);
    spec.theory = scatter::parse_theory("airy:3");  // the fast theory: the cost under test is the frame's
    spec.stokes = true;                              // for the polariser's frames (unused by the others)
    return scene::compute_bow_slice(spec);
  }();
  return s;
}

scene::SkySettings settings(int mode) {
  scene::SkySettings s;
  s.mode = scene::BowMode(mode);
  return s;
}

const char* label(int mode) {
  return mode == 0 ? "per-pixel, 1280x720, both cores" : mode == 1 ? "cube-map 512, 1280x720, both cores"
                                                                   : "half-dome 90x180, 1280x720, both cores";
}

// Arg: 0 per-pixel, 1 cube map, 2 half dome.
void BM_SkyFrame(benchmark::State& state) {
  const scene::SkyCompositor comp(settings(int(state.range(0))), rainbow_slice(), {});
  Image frame;
  for (auto _ : state) {
    comp.render_into(frame);
    benchmark::DoNotOptimize(frame.pixels.data());
  }
  state.SetLabel(label(int(state.range(0))));
  state.counters["pixels_per_s"] = benchmark::Counter(1280.0 * 720.0, benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_SkyFrame)->Arg(0)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

// The same through a polariser (hydrolux sky --polarizer-deg 30): each pixel's filter angle, the
// sky's degree of polarisation and the bow's Q looked up besides I.
void BM_SkyFramePolarizer(benchmark::State& state) {
  scene::SkySettings s = settings(int(state.range(0)));
  s.polarizer_deg = 30;
  const scene::SkyCompositor comp(s, rainbow_slice(), {});
  Image frame;
  for (auto _ : state) {
    comp.render_into(frame);
    benchmark::DoNotOptimize(frame.pixels.data());
  }
  state.SetLabel(label(int(state.range(0))));
  state.counters["pixels_per_s"] = benchmark::Counter(1280.0 * 720.0, benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_SkyFramePolarizer)->Arg(0)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_BowColour(benchmark::State& state) {
  const scene::SkyCompositor comp(settings(int(state.range(0))), rainbow_slice(), {});
  for (auto _ : state) benchmark::DoNotOptimize(comp.bow_colour());
  state.SetLabel(label(int(state.range(0))));
}
BENCHMARK(BM_BowColour)->Arg(0)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

// Building the compositor: the sun and sky parameters, and the cube map's bake or the dome's mesh.
void BM_SkySetup(benchmark::State& state) {
  for (auto _ : state) {
    const scene::SkyCompositor comp(settings(int(state.range(0))), rainbow_slice(), {});
    benchmark::DoNotOptimize(comp.sun_direction());
  }
  state.SetLabel(label(int(state.range(0))));
}
BENCHMARK(BM_SkySetup)->Arg(0)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
BENCHMARK_MAIN();
