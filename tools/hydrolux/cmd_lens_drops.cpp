// hydrolux lens-drops: water drops on the lens or windshield over a photograph, a folder of frames or a video
// (rain/lens_drops.hpp; docs/lens-drops.md). The options are declared in rain/lens_drops.hpp and
// io/lens_drops_job.hpp; the run over files is io/lens_drops_job.hpp's: this file registers the
// flags, calls the job and reports.
#include <fmt/format.h>

#include <memory>
#include <string>

#include "common.hpp"
#include "frame_hooks.hpp"
#include "hydrolux/io/lens_drops_job.hpp"
#include "hydrolux/rain/lens_drops.hpp"
#include "hydrolux/rain/params.hpp"
#include "params.hpp"
#include "progress.hpp"

namespace hydrolux::cli {

namespace {

struct LensDropsArgs {
  std::shared_ptr<io::LensDropsJob> job = std::make_shared<io::LensDropsJob>();
  bool quiet = false;
};

}  // namespace

Command add_lens_drops(CLI::App& app) {
  auto a = std::make_shared<LensDropsArgs>();
  auto* sub = add_job_command(app, "lens_drops");
  sub->add_option("--image", a->job->image, "Input photograph (PNG, JPEG, EXR, TIFF, ...)");
  sub->add_option("--input-dir", a->job->input_dir, "A folder of frames in name order (frame k: the drops of --seed + k)");
  sub->add_option("--video", a->job->video,
                  "Input video (MP4, MOV, MKV, ...); frame rate and count are kept (frame k: the drops of --seed + k)");
  sub->add_option("-o,--output", a->job->output, "Output: .png/.exr with --image, .mp4/.mov/.mkv with --video");
  sub->add_option("--output-dir", a->job->output_dir, "Output folder for --input-dir (created; never the input folder)");
  sub->add_option("--mask-out", a->job->mask_out,
                  "The drops' defocused coverage for --image: .png (16-bit linear) or .exr; out = clean (1 - mask) + drops");
  sub->add_option("--mask-dir", a->job->mask_dir, "Folder for the masks of --input-dir (same names as the frames)");
  sub->add_option("--stats-json", a->job->stats_json, "The drops' settings and per-frame statistics as JSON");
  Command cmd{sub, {}, {}};
  add_params(*sub, std::shared_ptr<rain::LensDropSettings>(a->job, &a->job->settings), rain::lens_drops_params(),
             cmd.flags_for_quantity);
  add_params(*sub, std::shared_ptr<rain::LensDropsFileOptions>(a->job, &a->job->files), rain::lens_drops_file_params(),
             cmd.flags_for_quantity);
  add_params(*sub, std::shared_ptr<io::VideoFileOptions>(a->job, &a->job->video_files), io::video_file_params(),
             cmd.flags_for_quantity);
  sub->add_flag("-q,--quiet", a->quiet, "No progress or summary on stderr");
  cmd.run = [a, sub] {
    a->job->crf_given = given(*sub, rain::rain_param("crf"));
    ProgressBar bar("lens-drops", a->quiet);
    const auto r = io::run_lens_drops_job(*a->job, frame_hooks(bar));
    if (!a->quiet) fmt::print(stderr, "{}\n", io::lens_drops_summary(r));
    return report_left_out(r.left_out, r.frames_total);
  };
  return cmd;
}

}  // namespace hydrolux::cli
