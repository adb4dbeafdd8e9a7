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

Command add_fog(CLI::App& app) {
  auto a = std::make_shared<FrameArgs<io::FogJob>>();
  auto* sub = add_job_command(app, "fog");
  Command cmd{sub, {}, {}};
  add_params(*sub, std::shared_ptr<io::FramePaths>(a->job), io::fog_traits().paths, cmd.flags_for_quantity);
  add_params(*sub, std::shared_ptr<rain::FogOptions>(a->job, &a->job->options), rain::fog_params(), cmd.flags_for_quantity);
  add_params(*sub, std::shared_ptr<rain::FogFileOptions>(a->job, &a->job->files), rain::fog_file_params(),
             cmd.flags_for_quantity);
  add_params(*sub, std::shared_ptr<io::VideoFileOptions>(a->job, &a->job->video_files), io::video_file_params(),
             cmd.flags_for_quantity);
  sub->add_flag("-q,--quiet", a->quiet, "No progress or summary on stderr");
  cmd.run = [a, sub] {
    a->job->given = given_on(*sub, rain::fog_params(), rain::fog_file_params(), io::video_file_params());
    return run_frame_command(*a, "fog", io::run_fog_job, io::fog_summary);
  };
  cmd.flags_for_quantity["width"] = "the input's width";
  cmd.flags_for_quantity["height"] = "the input's height";
  return cmd;
}

}  // namespace hydrolux::cli
