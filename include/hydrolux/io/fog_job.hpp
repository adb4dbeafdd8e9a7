#pragma once
// A fog run over files, as `hydrolux fog` makes it: one photograph or a folder of frames, with the
// optional mask (the fog's coverage 1 - t) and statistics. Every file is declared before any work
// (io/files.hpp), as rain_job.hpp's runs do.
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "hydrolux/io/image_io.hpp"
#include "hydrolux/rain/fog.hpp"

namespace hydrolux::io {

struct FogJob {
  std::optional<std::string> image, input_dir;  // exactly one
  std::optional<std::string> depth, depth_dir;
  std::optional<std::string> output, output_dir, mask_out, mask_dir, stats_json;
  rain::FogOptions options;
  rain::FogFileOptions files;
  bool depth_scale_given = false;
};

struct FogJobHooks {
  ImageCodec codec;
  std::function<void(const std::string&)> warn;
  std::function<void(double, std::string_view)> progress;
  std::function<void()> finish_progress;
};

struct FogJobResult {
  std::size_t frames = 0, frames_total = 0;
  std::vector<std::string> left_out;
  rain::FogOptics optics;
  rain::FogStats last;
  double seconds = 0;
};

// Error (bad input, before anything is written, or a folder's first frame), IoError, IoFailure as
// io/files.hpp says. A folder's sky colour is estimated from its first frame and kept for all.
FogJobResult run_fog_job(const FogJob& job, const FogJobHooks& hooks);
std::string fog_summary(const FogJobResult& result);

}  // namespace hydrolux::io
