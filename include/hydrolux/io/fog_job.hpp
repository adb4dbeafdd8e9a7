#pragma once
// A fog run over files, as `hydrolux fog` makes it: one photograph, a folder of frames or a video,
// with the optional mask (the fog's coverage 1 - t) and statistics. Fog is an effect of the frame
// driver (frame_driver.hpp), which owns the modes, the files and the left-out policy, as for rain.
#include <optional>
#include <string>
#include <vector>

#include "hydrolux/io/frame_driver.hpp"
#include "hydrolux/io/image_io.hpp"
#include "hydrolux/rain/fog.hpp"

namespace hydrolux::io {

// The paths as the CLI's flags name them (no --layer-out: fog has no layer of its own).
struct FogJob : FramePaths {
  rain::FogOptions options;
  rain::FogFileOptions files;
  VideoFileOptions video_files;  // --crf, for --video's output
  ParamUse given;  // what the door was given (FrameRequest::given)
};

using FogJobHooks = FrameHooks;

struct FogJobResult : FrameRunResult {
  rain::FogOptics optics;
  rain::FogStats last;  // the last frame's
};

// Error (bad input, before anything is written, or a folder's first frame), IoError, IoFailure as
// io/files.hpp says. A folder's or a video's sky colour is estimated from its first frame and kept
// for all; a video's frames lie on the ground plane (depth maps are for --image and --input-dir).
// What the fog names and takes (its files: io/frame_paths.hpp).
const EffectTraits& fog_traits();
FogJobResult run_fog_job(const FogJob& job, const FogJobHooks& hooks);
std::string fog_summary(const FogJobResult& result);

}  // namespace hydrolux::io
