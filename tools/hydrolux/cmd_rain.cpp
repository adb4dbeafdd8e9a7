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

Command add_rain(CLI::App& app) {
  auto a = std::make_shared<FrameArgs<io::RainJob>>();
  auto* sub = add_job_command(app, "rain");
  Command cmd{sub, {}, {}};
  add_params(*sub, std::shared_ptr<io::FramePaths>(a->job), io::rain_traits().paths, cmd.flags_for_quantity);
  sub->add_option("--size", a->job->size, "Size WxH of --image builtin [1280x720]")->check(size_validator());
  // The declared parameters store straight into the job (shared_ptr aliasing its members).
  add_params(*sub, std::shared_ptr<rain::RainOptions>(a->job, &a->job->options), rain::rain_params(),
             cmd.flags_for_quantity);
  add_params(*sub, std::shared_ptr<rain::RainFileOptions>(a->job, &a->job->files), rain::rain_file_params(),
             cmd.flags_for_quantity);
  sub->add_flag("-q,--quiet", a->quiet, "No progress or summary on stderr");
  cmd.run = [a, sub] {
    a->job->given = given_on(*sub, rain::rain_params(), rain::rain_file_params());
    return run_frame_command(*a, "rain", io::run_rain_job, io::rain_summary);
  };
  // The quantities the library names that are not a flag of their own.
  cmd.flags_for_quantity["width"] = "the input's width";
  cmd.flags_for_quantity["height"] = "the input's height";
  return cmd;
}

}  // namespace hydrolux::cli
