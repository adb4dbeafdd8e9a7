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
  job.given = ParamUse(Door::cli);
  record_given(sub, rain::fog_params(), job.given);
  record_given(sub, rain::fog_file_params(), job.given);
  record_given(sub, io::video_file_params(), job.given);
  ProgressBar bar("fog", a.quiet);
  const io::FogJobResult r = io::run_fog_job(job, frame_hooks(bar));
  if (!a.quiet) fmt::print(stderr, "{}\n", io::fog_summary(r));
  return report_left_out(r.left_out, r.frames_total);
}

}  // namespace

Command add_fog(CLI::App& app) {
  auto a = std::make_shared<FogArgs>();
  auto* sub = add_job_command(app, "fog");
  add_frame_paths(*sub, a->job, io::fog_traits());
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
