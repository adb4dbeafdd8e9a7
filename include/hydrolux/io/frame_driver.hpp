#pragma once
// The one driver of the frame jobs (`hydrolux rain`, `fog`, `lens-drops`): it owns what every such
// job does the same way, and an effect supplies only what it computes for a frame (pbrt-v4's
// Integrator / Film split; docs/architecture.md, "Frame driver and effects").
//
// The driver owns: the three modes (one photograph, a folder of frames in name order, a video), the
// files (every input and output declared before any work through io/files.hpp: nothing written over
// an input, no output half written), the pipelining of a folder or a video (one thread decodes the
// next frames, this one renders in order, one encodes and writes in order: the same bytes as one
// frame at a time), the left-out policy (a folder's frame that cannot be used after the first is
// written is named, warned and left out; the first frame's failure is bad input, nothing written; a
// video has no frame to leave out), the flags that only some modes use, the progress hooks, the
// negative input values said once, and the statistics file.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "hydrolux/core/params.hpp"
#include "hydrolux/io/image_io.hpp"
#include "hydrolux/rain/frame_paths.hpp"

namespace hydrolux::io {

// What to read and where the results go (rain/frame_paths.hpp: the paths declared, one table per effect).
using rain::FramePaths;

// The paths and how the files are encoded, as the driver takes them.
struct FrameRequest : FramePaths {
  int png_compression = 1;      // the deflate level of PNG outputs (kDefaultPngCompression)
  int crf = 18;                 // the H.264 quality of a video's output
  double depth_scale_m = 0.001; // metres per code of a PNG depth map
  // What the door was given of the job's parameters (the CLI records every flag): the driver refuses,
  // by the table's conditions (Param::only_with, not_with; ParamUse::report_unused), one the run
  // leaves unused. The states it holds: "video" in the video mode, "depth" and "depth_dir" where
  // those paths are given.
  ParamUse given;
};

enum class FrameMode { image, folder, video };

// The doors' hooks. `warn` gets one line each; `clear_progress` comes before a warning in the middle
// of a run. Every hook may be empty. Called from one thread at a time (the driver serialises them).
struct FrameHooks {
  ImageCodec codec;  // image_io.hpp: the library does not load OpenImageIO itself
  std::function<void(const std::string&)> warn;
  std::function<void(double, std::string_view)> progress;  // fraction done, "frame k/n"
  std::function<void()> clear_progress;
  std::function<void()> finish_progress;
};

// What an effect computed for one frame. The driver hands the same objects back frame after frame,
// so an effect may render into their buffers without allocating.
struct FrameOutput {
  Image image;                   // the result, linear, the input's channels
  Image mask;                    // 1 channel coverage in [0, 1] (--mask-out, --mask-dir)
  Image layer;                   // premultiplied RGBA (--layer-out), only when asked for
  nlohmann::json stats;          // the frame's statistics (--stats-json "frames")
  std::uint64_t negative_values = 0;  // input values read as 0 (said once, at the end of the run)
};

// The first frame of a sequence (or the photograph), before any frame is rendered.
struct SequenceStart {
  FrameMode mode = FrameMode::image;
  int width = 0, height = 0, channels = 0;
  double video_fps = 0;          // a video's own frame rate; 0 for still frames
  std::string input;             // the path given (--video's), for messages
  std::string origin;            // "--image a.png", "--input-dir in/f0.png", "--video v.mp4"
  bool depth = false;            // depth maps given (else the effect's ground plane)
  bool with_layer = false;
  double extra_bytes_per_pixel = 0;  // what the pipeline holds besides one frame (memory checks)
};

// What an effect names and supports.
struct EffectTraits {
  std::string noun;                // "rainy frames": "--output-dir: give the folder for the <noun> ..."
  bool one_size = true;            // every frame of a sequence the first one's size
  std::string folder_input_key = "input";  // the statistics' key for --input-dir's path
  // Its files, declared (rain/frame_paths.hpp): the CLI's flags and the batch's folder options. A path
  // not in the table is one the effect does not take (--layer-out but for rain, --depth for lens
  // drops), which a door leaves unset.
  std::span<const Field<FramePaths>> paths = {};
};

// One effect over frames. The driver calls, in order: check_options, check_mode (once the mode is
// known), validate (after every file is declared, before any folder is made or frame read),
// check_memory (each frame, from its header, before its pixels are decoded), prepare (the first
// frame), render (every frame, in order, on one thread), run_json (for --stats-json, at the end).
class FrameEffect {
 public:
  virtual ~FrameEffect() = default;
  virtual const EffectTraits& traits() const = 0;
  // Refusals of the effect's own options that need no files (Error naming the flag).
  virtual void check_options(const FrameRequest&) const {}
  // Refusals of the effect's own options in one mode (rain: --fps with a video, --size without
  // --image builtin).
  virtual void check_mode(const FrameRequest&, FrameMode) const {}
  // The settings checked before any folder is made or any frame read.
  virtual void validate() {}
  // Whether --image names a frame the effect makes itself instead of a file (rain's "builtin"), and
  // that frame (its memory checked by the effect).
  virtual bool synthetic(const FrameRequest&) const { return false; }
  virtual Image make_synthetic(const FrameRequest&, bool /*with_layer*/) const {
    throw std::logic_error("FrameEffect: no synthetic frame");
  }
  // Error "<origin>: ... needs about X of memory ..." when a frame this size cannot fit.
  virtual void check_memory(const std::string& origin, int width, int height, int channels, bool with_layer,
                            double extra_bytes_per_pixel) const = 0;
  virtual void prepare(const SequenceStart& start) = 0;
  // Frame k of the sequence (0 for a photograph): Error naming `origin` for a frame that cannot be
  // used (it is then left out of a folder once a frame is written).
  virtual void render(const Image& frame, const Image* depth, std::size_t k, bool with_layer,
                      const std::string& origin, FrameOutput& out) = 0;
  // The run's statistics (parameters, camera, ...); the driver adds "input", "frames", "left_out"
  // and, for a video, "video".
  virtual nlohmann::json run_json() const = 0;
};

// A job's request: its paths and how its files are encoded (the flags only some modes use, given or not).
FrameRequest frame_request(const FramePaths& paths, int png_compression, int crf, const ParamUse& given,
                           double depth_scale_m = 0.001);

// What every run reports; each job's result adds its effect's summary.
struct FrameRunResult {
  std::size_t frames = 0;             // written
  std::size_t frames_total = 0;       // of the input
  std::vector<std::string> left_out;  // a folder's frames that could not be used (after the first written)
  double seconds = 0;
};

// Runs `effect` over the request's frames. Error (bad input, before anything is written, or a
// folder's first frame), IoError, IoFailure (the system failed midway; nothing replaced) as
// io/files.hpp says.
FrameRunResult run_frames(const FrameRequest& request, FrameEffect& effect, const FrameHooks& hooks);

// The --crf row of rain's table for the effects whose own tables do not declare it (fog, lens drops).
struct VideoFileOptions {
  int crf = 18;
};
std::span<const Field<VideoFileOptions>> video_file_params();

}  // namespace hydrolux::io
