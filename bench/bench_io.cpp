// The cost of the safe file path (io/files.hpp): a checked, synced, renamed write against a plain
// unsynced stream write of the same bytes; reading a file whole; encoding and decoding images in
// memory (io/image_io.hpp). Files go to the system's temporary folder.
#include <benchmark/benchmark.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "hydrolux/io/files.hpp"
#include "hydrolux/io/image_io.hpp"

namespace {

namespace fs = std::filesystem;

fs::path scratch(const char* name) {
  return fs::temp_directory_path() / (std::string("hydrolux_bench_io_") + std::to_string(::getpid()) + "_" + name);
}

hydrolux::Image test_image(int size) {
  hydrolux::Image img(size, size, 4);
  for (std::size_t i = 0; i < img.pixels.size(); ++i) img.pixels[i] = float((i * 2654435761u) % 1000) / 1000.f;
  return img;
}

// The safe path: temporary file, checked writes, fsync, close, rename, folder fsync.
void safe_write(benchmark::State& state) {
  const std::string bytes(std::size_t(state.range(0)), 'x');
  const fs::path p = scratch("safe.bin");
  for (auto _ : state) hydrolux::io::write_file(p, bytes);
  state.SetBytesProcessed(int64_t(state.iterations()) * state.range(0));
  fs::remove(p);
}
BENCHMARK(safe_write)->Arg(64 << 10)->Arg(1 << 20)->Arg(16 << 20)->Unit(benchmark::kMillisecond)->UseRealTime();

// What the code did before: std::ofstream straight to the target, no sync, no checks.
void plain_write(benchmark::State& state) {
  const std::string bytes(std::size_t(state.range(0)), 'x');
  const fs::path p = scratch("plain.bin");
  for (auto _ : state) {
    std::ofstream out(p, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), std::streamsize(bytes.size()));
  }
  state.SetBytesProcessed(int64_t(state.iterations()) * state.range(0));
  fs::remove(p);
}
BENCHMARK(plain_write)->Arg(64 << 10)->Arg(1 << 20)->Arg(16 << 20)->Unit(benchmark::kMillisecond)->UseRealTime();

void read_whole_file(benchmark::State& state) {
  const fs::path p = scratch("read.bin");
  hydrolux::io::write_file(p, std::string(std::size_t(state.range(0)), 'r'));
  for (auto _ : state) benchmark::DoNotOptimize(hydrolux::io::read_file(p));
  state.SetBytesProcessed(int64_t(state.iterations()) * state.range(0));
  fs::remove(p);
}
BENCHMARK(read_whole_file)->Arg(16 << 20)->Unit(benchmark::kMillisecond);

void encode(benchmark::State& state) {
  const auto format = state.range(1) ? hydrolux::io::ImageFormat::exr : hydrolux::io::ImageFormat::png;
  const auto img = test_image(int(state.range(0)));
  for (auto _ : state) benchmark::DoNotOptimize(hydrolux::io::encode_image(img, format));
}
BENCHMARK(encode)->Args({512, 0})->Args({512, 1})->Unit(benchmark::kMillisecond);

void decode(benchmark::State& state) {
  const auto format = state.range(1) ? hydrolux::io::ImageFormat::exr : hydrolux::io::ImageFormat::png;
  const std::string bytes = hydrolux::io::encode_image(test_image(int(state.range(0))), format);
  for (auto _ : state) benchmark::DoNotOptimize(hydrolux::io::decode_image(bytes, "bench"));
}
BENCHMARK(decode)->Args({512, 0})->Args({512, 1})->Unit(benchmark::kMillisecond);

// The structural walk alone (io::image_structure_problem), which decode runs before the codec.
void structure_walk(benchmark::State& state) {
  const auto format = state.range(1) ? hydrolux::io::ImageFormat::exr : hydrolux::io::ImageFormat::png;
  const std::string bytes = hydrolux::io::encode_image(test_image(int(state.range(0))), format);
  const hydrolux::io::ImageLimits limits;
  for (auto _ : state) benchmark::DoNotOptimize(hydrolux::io::image_structure_problem(format, bytes, limits));
}
BENCHMARK(structure_walk)->Args({512, 0})->Args({512, 1})->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
