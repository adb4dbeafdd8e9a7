// Lee tables: the standard table (512 radii 5-800 um log x 1024 angles 90-180, full Mie, 40
// wavelengths, the sun's disk, a 10% gamma spread) on every core, the same table in Airy theory, and
// one wavelength of the standard Mie work on one thread (the kernel's rate). Counters: evaluations
// (single-drop solutions), terms (partial waves summed), term_angles (terms x angles: the amplitude
// sums' inner loop), and their rate. Non-spherical drops: the standard table's axes in Airy theory
// with Beard-Chuang drops, one table per position angle around the bow (19: every 10 degrees), the
// sun 5 degrees up: what an artist's bow over its whole arc costs.
#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include <string>

#include "hydrolux/atmos/lee.hpp"

namespace {

using namespace hydrolux;

std::string fmt_label(int positions) {
  return "airy, beard-chuang, 512 x 1024 x " + std::to_string(positions) + " position(s), both cores";
}

void report(benchmark::State& state, const atmos::LeeTable& t) {
  state.counters["evaluations"] = double(t.work.evaluations);
  state.counters["terms"] = double(t.work.terms);
  state.counters["term_angles"] = double(t.work.term_angles);
  state.counters["term_angles_per_s"] =
      benchmark::Counter(double(t.work.term_angles), benchmark::Counter::kIsIterationInvariantRate);
}

// Args: theory (0 = Mie, 1 = Airy theory), stokes (0 = intensity only, 1 = with the Stokes Q): the
// two side by side give Q's cost.
void BM_StandardTable(benchmark::State& state) {
  atmos::LeeSpec s;  // the defaults are the standard table
  if (state.range(0) == 1) s.theory = scatter::parse_theory("airy");
  s.stokes = state.range(1) == 1;
  atmos::LeeTable t;
  for (auto _ : state) t = atmos::compute_lee_table(s);
  report(state, t);
  state.SetLabel(std::string(state.range(0) == 1 ? "airy" : "mie") + ", 512 x 1024, both cores" +
                 (s.stokes ? ", stokes" : ""));
}
BENCHMARK(BM_StandardTable)
    ->Args({0, 0})
    ->Args({0, 1})
    ->Args({1, 0})
    ->Args({1, 1})
    ->Unit(benchmark::kSecond)
    ->Iterations(1)
    ->UseRealTime();

// One wavelength (550 nm) of the standard Mie table on one thread: the per-core rate.
void BM_StandardTableOneWavelength(benchmark::State& state) {
  tbb::global_control one_thread(tbb::global_control::max_allowed_parallelism, 1);
  atmos::LeeSpec s;
  s.wavelength_min_nm = s.wavelength_max_nm = 550;
  s.threads = 1;
  atmos::LeeTable t;
  for (auto _ : state) t = atmos::compute_lee_table(s);
  report(state, t);
  state.SetLabel("mie, 512 x 1024, 550 nm only, one thread");
}
BENCHMARK(BM_StandardTableOneWavelength)->Unit(benchmark::kSecond)->Iterations(1)->UseRealTime();

// Arg: the number of position angles (1: the top only; 19: 0, 10, ..., 180 degrees).
void BM_BeardChuangBowOverPositions(benchmark::State& state) {
  atmos::LeeSpec s;
  s.theory = scatter::parse_theory("airy");
  s.shape = atmos::parse_drop_shape("beard-chuang");
  s.sun_elevation_deg = 5;
  const int positions = int(state.range(0));
  atmos::LeeTable t;
  std::int64_t evaluations = 0;
  for (auto _ : state) {
    evaluations = 0;
    for (int k = 0; k < positions; ++k) {
      s.position_deg = positions > 1 ? 180.0 * k / (positions - 1) : 0.0;
      t = atmos::compute_lee_table(s);
      evaluations += t.work.evaluations;
    }
  }
  state.counters["evaluations"] = double(evaluations);
  state.SetLabel(fmt_label(positions));
}
BENCHMARK(BM_BeardChuangBowOverPositions)->Arg(1)->Arg(19)->Unit(benchmark::kSecond)->Iterations(1)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
