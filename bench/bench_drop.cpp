// Rendering a rain drop (Garg & Nayar's model) from the builtin environment, and the environment
// lookup alone. One thread (oneTBB limited to 1), so the numbers are per core.
#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include "hydrolux/drop/render.hpp"
#include "hydrolux/scene/environment.hpp"

namespace {

using namespace hydrolux;

void BM_BuiltinSkyLookup(benchmark::State& state) {
  const scene::BuiltinSky sky;
  Vec3 d = glm::normalize(Vec3{0.3, 0.2, 0.9});
  double sink = 0;
  for (auto _ : state) {
    sink += sky.radiance(d)[0];
    d = glm::normalize(Vec3{d.y, d.z + 0.01, d.x - 0.3});
  }
  benchmark::DoNotOptimize(sink);
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_BuiltinSkyLookup);

// A 256 x 256 image with the drop 40% of its width across, 4 x 4 samples per pixel, two internal
// reflections: ~1.1 M camera rays of which ~14% hit the drop. Arg: 1 = dispersive (3 indices).
void BM_RenderModel(benchmark::State& state) {
  tbb::global_control one_thread(tbb::global_control::max_allowed_parallelism, 1);
  const scene::BuiltinSky sky;
  drop::DropCamera cam;
  cam.width = cam.height = 256;
  drop::RenderOptions opt;
  const double mu = 1.333;
  const drop::ChannelIndex idx = state.range(0) ? drop::ChannelIndex{1.3314, 1.3343, 1.3385}
                                                : drop::ChannelIndex{mu, mu, mu};
  for (auto _ : state) benchmark::DoNotOptimize(drop::render_model(cam, sky, idx, opt));
  state.SetItemsProcessed(state.iterations() * 256 * 256 * 16);
  state.SetLabel("items = camera rays");
}
BENCHMARK(BM_RenderModel)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
