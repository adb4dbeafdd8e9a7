// hydrolux rain's per-frame cost at 1920 x 1080 and 25 mm/h (issue 12's goal: 10 frames per second on
// this machine's 2 cores): the whole frame (streaks, drop light, raster, composite) and its stages.
// The frame is a synthetic street-like picture (sky over a darker scene); its content does not change
// the cost, only the camera and the rain do.
#include <benchmark/benchmark.h>

#include <chrono>

#include "hydrolux/rain/rain.hpp"

namespace {

using namespace hydrolux;

Image test_frame(int w, int h) {
  Image img(w, h, 3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const bool sky = y < h * 2 / 5;
      const float v = sky ? 0.8f - 0.3f * float(y) / float(h) : 0.12f + 0.1f * float((x / 64 + y / 48) % 2);
      img.at(x, y, 0) = v * (sky ? 0.85f : 1.0f);
      img.at(x, y, 1) = v * (sky ? 0.92f : 0.95f);
      img.at(x, y, 2) = v * (sky ? 1.05f : 0.9f);
    }
  return img;
}

rain::RainRenderer make_renderer(double rate) {
  rain::RainSettings s;
  s.rain_rate_mmh = rate;
  s.wind_mps = 3;
  rain::RainCamera c;  // 1920 x 1080, 35 mm on a 36 mm sensor, 1/125 s
  return rain::RainRenderer(rain::RainField(s, c));
}

void BM_RainFrame(benchmark::State& state) {
  auto r = make_renderer(double(state.range(0)));
  const Image frame = test_frame(1920, 1080);
  std::int64_t k = 0;
  rain::RainFrame out;  // reused, as a sequence reuses it
  r.render_into(frame, nullptr, k++, false, out);  // the first frame allocates: not a frame's cost
  for (auto _ : state) {
    r.render_into(frame, nullptr, k++, false, out);
    benchmark::DoNotOptimize(out.image.pixels.data());
  }
  const rain::RainStats& st = out.stats;
  state.counters["drops_total"] = double(st.drops_total);
  state.counters["drops_in_view"] = double(st.drops_in_view);
  state.counters["fps"] = benchmark::Counter(double(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_RainFrame)->Arg(5)->Arg(25)->Arg(100)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(2);

void BM_RainStreaks(benchmark::State& state) {
  auto r = make_renderer(25);
  std::vector<rain::Streak> list;
  std::int64_t k = 0;
  for (auto _ : state) {
    r.streaks(k++, list);
    benchmark::DoNotOptimize(list.data());
  }
  state.counters["streaks"] = double(list.size());
}
BENCHMARK(BM_RainStreaks)->Unit(benchmark::kMillisecond)->UseRealTime();

// The drop light's update from a frame (the frame reduced, the grid's taps summed).
void BM_DropLightUpdate(benchmark::State& state) {
  rain::RainCamera c;
  rain::DropLight light(c, 1.333);
  const Image frame = test_frame(1920, 1080);
  for (auto _ : state) {
    light.update(frame);
    benchmark::DoNotOptimize(light.sky());
  }
}
BENCHMARK(BM_DropLightUpdate)->Unit(benchmark::kMillisecond)->UseRealTime();

// The field's set-up (classes, boxes, the velocity table) and the drop light's grid: once per run.
void BM_RainSetup(benchmark::State& state) {
  for (auto _ : state) {
    auto r = make_renderer(25);
    benchmark::DoNotOptimize(r.field().drop_count());
  }
}
BENCHMARK(BM_RainSetup)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
