#pragma once
// A lens-drops run over files, as `hydrolux lens-drops` makes it: one photograph, or a folder of
// frames, with its optional masks. Every file is declared before any work (io/files.hpp): nothing
// is written over an input, no output is left half written. The CLI parses its flags into a
// LensDropsJob and prints the summary.
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "hydrolux/core/params.hpp"
#include "hydrolux/io/image_io.hpp"
#include "hydrolux/rain/lens_drops.hpp"

namespace hydrolux::io {

// What to put drops on and where the results go, as the CLI's flags name them.
struct LensDropsJob {
  // Exactly one of image, input_dir.
  std::optional<std::string> image, input_dir;
  std::optional<std::string> output, output_dir, mask_out, mask_dir;
  rain::LensDropSettings settings;
  rain::LensDropsFileOptions files;
};

struct LensDropsJobResult {
  std::size_t frames = 0;       // written
  std::size_t frames_total = 0;  // in the folder (1 for --image)
  std::vector<std::string> left_out;  // a folder's frames that could not be used (named, warned)
  std::size_t drops = 0;        // the last frame's
  double coverage = 0;          // the last frame's sharp coverage
  double blur_diameter_px = 0;  // the last frame's circle of confusion at the glass
  double seconds = 0;
};

// Runs the job: Error (bad input, before anything is written), IoError, IoFailure as io/files.hpp
// says. A folder's frame k gets the drops of seed + k (each frame its own drops); a frame that
// cannot be read is named and left out once one frame is written, as rain and fog do (the first
// frame's failure is bad input: Error, nothing written). `warn` gets one line each.
LensDropsJobResult run_lens_drops_job(const LensDropsJob& job, const ImageCodec& codec,
                                      const std::function<void(const std::string&)>& warn);

std::string lens_drops_summary(const LensDropsJobResult& result);

}  // namespace hydrolux::io
