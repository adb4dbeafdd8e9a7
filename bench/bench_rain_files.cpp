// hydrolux rain over a folder of files, end to end as a user runs it (issue 27): 1920 x 1080 PNG
// frames in, PNG frames out, at 25 mm/h, through io::run_rain_job (what `hydrolux rain --input-dir
// IN --output-dir OUT` calls, without the process start): the checked reads, the decode, the render,
// the encode and the checked atomic writes, the three overlapping over neighbouring frames. Next to
// bench_rain's BM_RainFrame/25 (the render alone, frames in memory).
//
// The input: kFrames frames of the built-in street scene with a camera's noise (each value times
// 1 + 0.02 n, n normal, a seed per frame), written as most tools write PNG (zlib level 6, libpng's
// adaptive filters): about 3 MB a frame, as a photograph's PNG is, where the noiseless scene would
// compress to a tenth and flatter the codec's share. Arg: the output's --png-compression.
//
// HYDROLUX_BENCH_WRITE_FRAMES=DIR writes the input frames into DIR and exits (to time the CLI itself
// over the same frames: BENCHMARKS.md, "Rain over a folder of frames, end to end").
#include <benchmark/benchmark.h>

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "hydrolux/color/srgb.hpp"
#include "hydrolux/io/files.hpp"
#include "hydrolux/io/image_io.hpp"
#include "hydrolux/io/rain_job.hpp"
#include "hydrolux/rain/rain.hpp"

namespace {

using namespace hydrolux;
namespace fs = std::filesystem;

constexpr int kFrames = 12;

void write_frames(const fs::path& dir) {
  fs::create_directories(dir);
  rain::RainCamera cam;  // 1920 x 1080
  const Image scene = rain::builtin_scene(cam);
  for (int k = 0; k < kFrames; ++k) {
    Image frame = scene;
    std::mt19937_64 rng(std::uint64_t(1000 + k));
    std::normal_distribution<float> noise(0.0f, 0.02f);
    for (float& v : frame.pixels) v *= 1.0f + noise(rng);
    char name[32];
    std::snprintf(name, sizeof name, "frame_%04d.png", k);
    io::write_file(dir / name, io::encode_image(frame, io::ImageFormat::png, io::PngOptions{8, 6}));
  }
}

class Folder {
 public:
  Folder() : root_(fs::temp_directory_path() / ("hydrolux_bench_rain_files_" + std::to_string(::getpid()))) {
    write_frames(root_ / "in");
  }
  ~Folder() {
    std::error_code ec;
    fs::remove_all(root_, ec);
  }
  fs::path in() const { return root_ / "in"; }
  fs::path out() const { return root_ / "out"; }

 private:
  fs::path root_;
};

const Folder& folder() {
  static const Folder f;
  return f;
}

void BM_RainFolderPng(benchmark::State& state) {
  const Folder& f = folder();
  io::RainJob job;
  job.input_dir = f.in().string();
  job.output_dir = f.out().string();
  job.options.settings.rain_rate_mmh = 25;
  job.options.settings.wind_mps = 3;
  job.files.png_compression = int(state.range(0));
  io::RainJobHooks hooks;
  hooks.codec = {&io::decode_image, &io::encode_image};
  std::uintmax_t out_bytes = 0;
  for (auto _ : state) {
    state.PauseTiming();
    fs::remove_all(f.out());
    state.ResumeTiming();
    const io::RainJobResult r = io::run_rain_job(job, hooks);
    if (r.frames != std::size_t(kFrames)) state.SkipWithError("frames left out");
    state.PauseTiming();
    out_bytes = 0;
    for (const auto& e : fs::directory_iterator(f.out())) out_bytes += e.file_size();
    state.ResumeTiming();
  }
  std::uintmax_t in_bytes = 0;
  for (const auto& e : fs::directory_iterator(f.in())) in_bytes += e.file_size();
  state.counters["fps"] = benchmark::Counter(double(state.iterations()) * kFrames, benchmark::Counter::kIsRate);
  state.counters["MB_in"] = double(in_bytes) / kFrames / 1e6;
  state.counters["MB_out"] = double(out_bytes) / kFrames / 1e6;
}
BENCHMARK(BM_RainFolderPng)->Arg(1)->Arg(6)->Arg(0)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);

// The stages on their own, one thread: decoding one input frame (read from memory), and encoding one
// frame of the input's content at a level (the sRGB table and zlib).
void BM_DecodeFrame(benchmark::State& state) {
  const std::string bytes = io::read_file(folder().in() / "frame_0000.png");
  for (auto _ : state) benchmark::DoNotOptimize(io::decode_image(bytes, "frame").image.pixels.data());
}
BENCHMARK(BM_DecodeFrame)->Unit(benchmark::kMillisecond);

void BM_EncodeFrame(benchmark::State& state) {
  const Image frame = io::decode_image(io::read_file(folder().in() / "frame_0000.png"), "frame").image;
  std::size_t bytes = 0;
  for (auto _ : state) bytes = io::encode_image(frame, io::ImageFormat::png, {8, int(state.range(0))}).size();
  state.counters["MB"] = double(bytes) / 1e6;
}
BENCHMARK(BM_EncodeFrame)->Arg(0)->Arg(1)->Arg(2)->Arg(3)->Arg(6)->Unit(benchmark::kMillisecond);

// The 8-bit sRGB encode alone (the table), per frame.
void BM_Srgb8Codes(benchmark::State& state) {
  const Image frame = io::decode_image(io::read_file(folder().in() / "frame_0000.png"), "frame").image;
  std::vector<std::uint8_t> codes(frame.pixels.size());
  for (auto _ : state) {
    io::srgb8_codes(frame.pixels.data(), frame.pixels.size(), codes.data());
    benchmark::DoNotOptimize(codes.data());
  }
}
BENCHMARK(BM_Srgb8Codes)->Unit(benchmark::kMillisecond);

// The same codes through the curve, as encode_image computed them before the table.
void BM_Srgb8CodesCurve(benchmark::State& state) {
  const Image frame = io::decode_image(io::read_file(folder().in() / "frame_0000.png"), "frame").image;
  std::vector<std::uint8_t> codes(frame.pixels.size());
  for (auto _ : state) {
    for (std::size_t i = 0; i < codes.size(); ++i)
      codes[i] = std::uint8_t(std::lround(color::srgb_encode(double(frame.pixels[i])) * 255.0));
    benchmark::DoNotOptimize(codes.data());
  }
}
BENCHMARK(BM_Srgb8CodesCurve)->Unit(benchmark::kMillisecond);

}  // namespace

int main(int argc, char** argv) {
  if (const char* dir = std::getenv("HYDROLUX_BENCH_WRITE_FRAMES")) {
    write_frames(dir);
    return 0;
  }
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
