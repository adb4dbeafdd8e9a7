#pragma once
// A lens-drops run over files, as `hydrolux lens-drops` makes it: one photograph, a folder of frames
// or a video, with its optional masks and statistics. Drops on the lens are an effect of the frame
// driver (frame_driver.hpp), which owns the modes, the files and the left-out policy, as for rain
// and fog. The CLI parses its flags into a LensDropsJob and prints the summary.
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "hydrolux/core/params.hpp"
#include "hydrolux/io/frame_driver.hpp"
#include "hydrolux/io/image_io.hpp"
#include "hydrolux/rain/lens_drops.hpp"

namespace hydrolux::io {

// What to put drops on and where the results go, as the CLI's flags name them.
// The paths as the CLI's flags name them (no depth maps, no --layer-out).
struct LensDropsJob : FramePaths {
  rain::LensDropSettings settings;
  rain::LensDropsFileOptions files;
  VideoFileOptions video_files;  // --crf, for --video's output
  ParamUse given;  // what the door was given (FrameRequest::given)
};

struct LensDropsJobResult : FrameRunResult {
  std::size_t drops = 0;        // the last frame's
  double coverage = 0;          // the last frame's sharp coverage
  double blur_diameter_px = 0;  // the last frame's circle of confusion at the glass
};

// Runs the job: Error (bad input, before anything is written), IoError, IoFailure as io/files.hpp
// says. Frame k of a folder or a video gets the drops of seed + k (each frame its own drops); a
// folder's frame that cannot be read is named and left out once one frame is written, as for rain
// and fog (the first frame's failure is bad input: Error, nothing written).
// What the lens drops name and take (their files: io/frame_paths.hpp).
const EffectTraits& lens_drops_traits();
LensDropsJobResult run_lens_drops_job(const LensDropsJob& job, const FrameHooks& hooks);

std::string lens_drops_summary(const LensDropsJobResult& result);

}  // namespace hydrolux::io
