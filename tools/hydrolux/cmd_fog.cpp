// hydrolux fog: fog, haze or mist over a photograph, a folder of frames or a video (rain/fog.hpp;
// docs/fog.md). The options are declared in rain/fog.hpp, the run over files is io/fog_job.hpp's:
// this file registers the flags, calls the job and reports.
#include <fmt/format.h>

#include <memory>
#include <string>

#include "common.hpp"
#include "frame_hooks.hpp"
#include "hydrolux/io/fog_job.hpp"
#include "hydrolux/rain/fog.hpp"
#include "hydrolux/rain/params.hpp"
#include "params.hpp"
#include "progress.hpp"

namespace hydrolux::cli {

namespace {

struct FogArgs {
  std::shared_ptr<io::FogJob> job = std::make_shared<io::FogJob>();
  bool quiet = false;
};

int run_fog(FogArgs& a, const CLI::App& sub) {
  io::FogJob& job = *a.job;
  job.depth_scale_given = given(sub, rain::fog_param("depth_scale_m"));
  job.crf_given = given(sub, rain::rain_param("crf"));
  ProgressBar bar("fog", a.quiet);
  const io::FogJobResult r = io::run_fog_job(job, frame_hooks(bar));
  if (!a.quiet) fmt::print(stderr, "{}\n", io::fog_summary(r));
  return report_left_out(r.left_out, r.frames_total);
}

}  // namespace

Command add_fog(CLI::App& app) {
  auto a = std::make_shared<FogArgs>();
  auto* sub = add_job_command(app, "fog");
  sub->add_option("--image", a->job->image, "Input photograph (PNG, JPEG, EXR, TIFF, ...)");
  sub->add_option("--input-dir", a->job->input_dir, "A folder of frames in name order (one sky colour, from the first)");
  sub->add_option("--video", a->job->video,
                  "Input video (MP4, MOV, MKV, ...); frame rate and count are kept, one sky colour from the first frame");
  sub->add_option("-o,--output", a->job->output, "Output: .png/.exr with --image, .mp4/.mov/.mkv with --video");
  sub->add_option("--output-dir", a->job->output_dir, "Output folder for --input-dir (created; never the input folder)");
  sub->add_option("--depth", a->job->depth,
                  "Depth map for --image: camera z in metres (EXR), or a 16-bit PNG times --depth-scale-m; 0/inf = sky");
  sub->add_option("--depth-dir", a->job->depth_dir, "Depth maps for --input-dir: each frame's stem as .exr or .png");
  sub->add_option("--mask-out", a->job->mask_out,
                  "The fog's coverage 1 - t for --image: .png (16-bit linear) or .exr; foggy = clear t + sky (1 - t) + glow");
  sub->add_option("--mask-dir", a->job->mask_dir, "Folder for the masks of --input-dir (same names as the frames)");
  sub->add_option("--stats-json", a->job->stats_json, "The fog's optics, the camera and per-frame statistics as JSON");
  Command cmd{sub, {}, {}};
  add_params(*sub, std::shared_ptr<rain::FogOptions>(a->job, &a->job->options), rain::fog_params(), cmd.flags_for_quantity);
  add_params(*sub, std::shared_ptr<rain::FogFileOptions>(a->job, &a->job->files), rain::fog_file_params(),
             cmd.flags_for_quantity);
  add_params(*sub, std::shared_ptr<io::VideoFileOptions>(a->job, &a->job->video_files), io::video_file_params(),
             cmd.flags_for_quantity);
  sub->add_flag("-q,--quiet", a->quiet, "No progress or summary on stderr");
  cmd.run = [a, sub] { return run_fog(*a, *sub); };
  cmd.flags_for_quantity["width"] = "the input's width";
  cmd.flags_for_quantity["height"] = "the input's height";
  return cmd;
}

}  // namespace hydrolux::cli
