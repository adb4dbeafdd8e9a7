// hydrolux rain: physically based rain streaks over a photograph, a folder of frames or a video
// (rain/rain.hpp; docs/rain.md). The options are declared in rain/params.hpp, the run over files is
// io/rain_job.hpp's: this file registers the flags, calls the job and reports.
#include <fmt/format.h>

#include <memory>
#include <string>

#include "common.hpp"
#include "frame_hooks.hpp"
#include "hydrolux/core/error.hpp"
#include "hydrolux/io/rain_job.hpp"
#include "hydrolux/rain/params.hpp"
#include "params.hpp"
#include "progress.hpp"

namespace hydrolux::cli {

namespace {

struct RainArgs {
  std::shared_ptr<io::RainJob> job = std::make_shared<io::RainJob>();
  bool quiet = false;
};

int run_rain(RainArgs& a, const CLI::App& sub) {
  io::RainJob& job = *a.job;
  job.crf_given = given(sub, rain::rain_param("crf"));
  job.depth_scale_given = given(sub, rain::rain_param("depth_scale_m"));
  ProgressBar bar("rain", a.quiet);
  const io::RainJobResult r = io::run_rain_job(job, frame_hooks(bar));
  if (!a.quiet) fmt::print(stderr, "{}\n", io::rain_summary(r));
  return report_left_out(r.left_out, r.frames_total);
}

}  // namespace

Command add_rain(CLI::App& app) {
  auto a = std::make_shared<RainArgs>();
  auto* sub = add_job_command(app, "rain");
  sub->add_option("--image", a->job->image, "Input photograph (PNG, JPEG, EXR, TIFF, ...), or 'builtin' for the built-in street scene");
  sub->add_option("--size", a->job->size, "Size WxH of --image builtin [1280x720]")->check(size_validator());
  sub->add_option("--input-dir", a->job->input_dir, "A folder of frames in name order: one rain field across them");
  sub->add_option("--video", a->job->video, "Input video (MP4, MOV, MKV, ...); frame rate and count are kept");
  sub->add_option("-o,--output", a->job->output, "Output: .png/.exr with --image, .mp4/.mov/.mkv with --video");
  sub->add_option("--output-dir", a->job->output_dir, "Output folder for --input-dir (created; never the input folder)");
  sub->add_option("--depth", a->job->depth, "Depth map for --image: camera z in metres (EXR), or a 16-bit PNG times --depth-scale-m; 0/inf = sky");
  sub->add_option("--depth-dir", a->job->depth_dir, "Depth maps for --input-dir: each frame's stem as .exr or .png (as --depth)");
  sub->add_option("--mask-out", a->job->mask_out, "The rain's alpha for --image: .png (16-bit linear) or .exr; rainy = clear (1 - alpha) + layer");
  sub->add_option("--mask-dir", a->job->mask_dir, "Folder for the masks of --input-dir (same names as the frames)");
  sub->add_option("--layer-out", a->job->layer_out, "The rain layer for --image as a premultiplied RGBA .exr (linear)");
  sub->add_option("--stats-json", a->job->stats_json, "Parameters, seed, the field and per-frame statistics as JSON");
  Command cmd{sub, {}, {}};
  // The declared parameters store straight into the job (shared_ptr aliasing its members).
  add_params(*sub, std::shared_ptr<rain::RainOptions>(a->job, &a->job->options), rain::rain_params(),
             cmd.flags_for_quantity);
  add_params(*sub, std::shared_ptr<rain::RainFileOptions>(a->job, &a->job->files), rain::rain_file_params(),
             cmd.flags_for_quantity);
  sub->add_flag("-q,--quiet", a->quiet, "No progress or summary on stderr");
  cmd.run = [a, sub] { return run_rain(*a, *sub); };
  // The quantities the library names that are not a flag of their own.
  cmd.flags_for_quantity["width"] = "the input's width";
  cmd.flags_for_quantity["height"] = "the input's height";
  cmd.flags_for_quantity["sensor_width_mm"] = "--sensor-width-mm (or --pixel-pitch-um x the image width)";
  return cmd;
}

}  // namespace hydrolux::cli
