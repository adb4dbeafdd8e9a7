#pragma once
// A rain run over files, as `hydrolux rain` makes it: one photograph (or the built-in scene), a
// folder of frames, or a video, with its optional outputs (mask, layer, statistics). Rain is an
// effect of the frame driver (frame_driver.hpp), which owns the modes, the files and the left-out
// policy. The doors only translate: the CLI parses its flags into a RainJob and prints what the
// hooks and the result say.
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "hydrolux/io/frame_driver.hpp"
#include "hydrolux/io/image_io.hpp"
#include "hydrolux/rain/params.hpp"

namespace hydrolux::io {

// What to rain on and where the results go, as the CLI's flags name them (messages quote them so).
// Exactly one of image ("builtin": the built-in street scene, of `size`), input_dir, video.
struct RainJob : FramePaths {
  std::optional<std::string> size;  // "WxH" of the built-in scene
  rain::RainOptions options;
  rain::RainFileOptions files;
  // Options whose defaults mean nothing in some modes: given by the user, they must be used.
  ParamUse given;  // what the door was given (FrameRequest::given)
};

// The doors' hooks (frame_driver.hpp): the codec, warnings, progress.
using RainJobHooks = FrameHooks;

// The frames written, of the input, left out (a folder's, after the first written) and the time, and
// the rain's summary.
struct RainJobResult : FrameRunResult {
  double rain_rate_mmh = 0;
  std::uint64_t drops = 0;             // in the field
  rain::RainStats last;                // the last frame's
};

// Runs the job. Error (bad input, before anything is written, or a folder's first frame), IoError,
// IoFailure (the system failed midway; nothing replaced) as io/files.hpp says.
// What the rain names and takes (its files: io/frame_paths.hpp).
const EffectTraits& rain_traits();
RainJobResult run_rain_job(const RainJob& job, const RainJobHooks& hooks);

// The one line a run's summary is (the CLI prints it unless quiet).
std::string rain_summary(const RainJobResult& result);

}  // namespace hydrolux::io
