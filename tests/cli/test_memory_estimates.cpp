// The memory estimates that let a frame job start are upper bounds of what it then takes (issue 37:
// rain at 8192x8192 was estimated at 5.0 GB and peaked at 5.77 GB; at 16384x16384 an estimate of
// 19.9 GB let it start on a 23 GB machine, where the kernel's OOM killer ended it 5 minutes in; fog
// and lens-drops estimated nothing). Each job is run through the CLI as a user runs it and its peak
// resident size (getrusage's ru_maxrss of the child) is compared with the library's estimate for that
// frame: the peak must not exceed it, and the estimate must stay within a factor 1/0.6 of the peak
// (a bound that refused half of what fits would be no better). The estimates were fitted at 1024^2 to
// 8192^2 (rain/budget.cpp, BENCHMARKS.md); 2048^2 is checked here, large enough that the pixels'
// share (~400 MB) outweighs the program's.
//
// Not under AddressSanitizer, whose shadow memory and quarantine multiply every allocation.
#include <gtest/gtest.h>
#include <sys/resource.h>

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "hydrolux/core/image.hpp"
#include "hydrolux/io/image_io.hpp"
#include "hydrolux/rain/lens_drops.hpp"
#include "hydrolux/rain/rain.hpp"
#include "support/asan.hpp"
#include "support/cli.hpp"

namespace {

namespace fs = std::filesystem;
using namespace hydrolux;

fs::path dir() {
  static const fs::path d = hydrolux::testing::temp_dir("hydrolux_memory_estimates");
  return d;
}

constexpr int kSide = 2048;

// An 8-bit PNG of kSide^2 that does not compress (a hash per value), as a photograph's noise does not.
[[maybe_unused]] const fs::path& noisy_png() {  // unused under ASan (its memory is not the program's)
  static const fs::path p = [] {
    Image img(kSide, kSide, 3);
    std::uint32_t h = 2166136261u;
    for (auto& v : img.pixels) {
      h = (h ^ 0x9e37u) * 16777619u;
      v = float((h >> 8) & 0xff) / 255.f * 0.8f;
    }
    const fs::path f = dir() / "noisy.png";
    io::write_image(f, img);
    return f;
  }();
  return p;
}

[[maybe_unused]] void expect_bound(const std::vector<std::string>& args, std::uint64_t estimate) {
  const auto r = hydrolux::testing::run_argv(args);
  ASSERT_EQ(r.code, 0) << r.err;
  ASSERT_GT(r.peak_rss_bytes, 0u);
  const double peak = double(r.peak_rss_bytes), est = double(estimate);
  EXPECT_LE(peak, est) << args[0] << ": peak " << peak / 1e6 << " MB, estimate " << est / 1e6 << " MB";
  EXPECT_GE(peak, 0.6 * est) << args[0] << ": peak " << peak / 1e6 << " MB, estimate " << est / 1e6 << " MB";
}

#if !HYDROLUX_TEST_ASAN

TEST(MemoryEstimates, RainPeakStaysUnderItsEstimate) {
  rain::RainCamera cam;
  cam.width = cam.height = kSide;
  expect_bound({"rain", "-q", "--image", noisy_png().string(), "-o", (dir() / "rain2.png").string(), "--mask-out",
                (dir() / "rain2_mask.png").string()},
               rain::estimated_render_bytes(cam, 3, false));
}

TEST(MemoryEstimates, FogPeakStaysUnderItsEstimate) {
  expect_bound({"fog", "-q", "--visibility-m", "200", "--image", noisy_png().string(), "-o", (dir() / "fog.png").string(),
                "--mask-out", (dir() / "fog_mask.png").string()},
               rain::estimated_fog_bytes(kSide, kSide, 3, true));
}

TEST(MemoryEstimates, LensDropsPeakStaysUnderItsEstimate) {
  const rain::LensDropSettings s;
  const double blur = rain::circle_of_confusion_mm(s.focal_mm, s.f_number, s.focus_m, s.glass_distance_m) /
                      s.sensor_width_mm * kSide;
  expect_bound({"lens-drops", "-q", "--image", noisy_png().string(), "-o", (dir() / "lens.png").string(), "--mask-out",
                (dir() / "lens_mask.png").string()},
               rain::estimated_lens_drops_bytes(kSide, kSide, 3, blur));
}

// A frame whose estimate exceeds the memory left is refused in one line naming the file and a size
// that would fit, before the work and with nothing written, in every frame job (rain did; fog and
// lens-drops ran until the allocator failed). A 600 MB address-space limit stands for a small machine
// (below ~400 MB the image plugin's libraries cannot even be loaded); a smooth 4096^2 PNG decodes
// within it and needs 1.2-1.6 GB to process.
TEST(MemoryEstimates, EveryFrameJobRefusesAFrameThatCannotFit) {
  const fs::path big = dir() / "big.png";
  {
    Image img(4096, 4096, 3);
    for (int y = 0; y < img.height; ++y)
      for (int x = 0; x < img.width; ++x)
        for (int c = 0; c < 3; ++c) img.at(x, y, c) = float(x + y + c) / 8192.f;
    io::write_image(big, img);
  }
  for (const std::string job : {"rain", "fog", "lens-drops"}) {
    SCOPED_TRACE(job);
    const fs::path out = dir() / (job + "_refused.png");
    std::vector<std::string> args = {job, "-q", "--image", big.string(), "-o", out.string()};
    if (job == "fog") args.insert(args.end(), {"--visibility-m", "200"});
    const auto r = hydrolux::testing::run_argv(args, [] {
      const rlimit lim{std::uint64_t(600) << 20, std::uint64_t(600) << 20};
      ::setrlimit(RLIMIT_AS, &lim);
    });
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_EQ(hydrolux::testing::lines(r.err), 1u) << r.err;
    EXPECT_NE(r.err.find("--image " + big.string() + ":"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("would fit"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(out));
  }
}

#endif

}  // namespace
