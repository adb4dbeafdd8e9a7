#pragma once
// A rain run over files, as `hydrolux rain` makes it: one photograph (or the built-in scene), a
// folder of frames, or a video, with its optional outputs (mask, layer, statistics). Every file is
// declared before any work (io/files.hpp): nothing is written over an input, no output is left half
// written. The doors only translate: the CLI parses its flags into a RainJob and prints what the
// hooks and the result say.
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "hydrolux/io/image_io.hpp"
#include "hydrolux/rain/params.hpp"

namespace hydrolux::io {

// What to rain on and where the results go, as the CLI's flags name them (messages quote them so).
struct RainJob {
  // Exactly one of image ("builtin": the built-in street scene, of `size`), input_dir, video.
  std::optional<std::string> image, input_dir, video;
  std::optional<std::string> size;  // "WxH" of the built-in scene
  std::optional<std::string> depth, depth_dir;
  std::optional<std::string> output, output_dir, mask_out, mask_dir, layer_out, stats_json;
  rain::RainOptions options;
  rain::RainFileOptions files;
  // Options whose defaults mean nothing in some modes: given by the user, they must be used.
  bool crf_given = false, depth_scale_given = false;
};

struct RainJobHooks {
  ImageCodec codec;  // image_io.hpp: the library does not load OpenImageIO itself
  std::function<void(const std::string&)> warn;                  // one line each
  std::function<void(double, std::string_view)> progress;         // fraction done, "frame k/n"; may be empty
  std::function<void()> clear_progress;                           // before a warning in the middle of a run
  std::function<void()> finish_progress;
};

struct RainJobResult {
  std::size_t frames = 0;              // written
  std::size_t frames_total = 0;        // of the input
  std::vector<std::string> left_out;   // frames of a folder that could not be used (after the first written)
  double rate_mmh = 0;
  std::uint64_t drops = 0;             // in the field
  rain::RainStats last;                // the last frame's
  double seconds = 0;
};

// Runs the job. Error (bad input, before anything is written, or a folder's first frame), IoError,
// IoFailure (the system failed midway; nothing replaced) as io/files.hpp says.
RainJobResult run_rain_job(const RainJob& job, const RainJobHooks& hooks);

// The one line a run's summary is (the CLI prints it unless quiet).
std::string rain_summary(const RainJobResult& result);

}  // namespace hydrolux::io
