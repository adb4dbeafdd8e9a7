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

Command add_lens_drops(CLI::App& app) {
  auto a = std::make_shared<FrameArgs<io::LensDropsJob>>();
  auto* sub = add_job_command(app, "lens_drops");
  Command cmd{sub, {}, {}};
  add_params(*sub, std::shared_ptr<io::FramePaths>(a->job), io::lens_drops_traits().paths, cmd.flags_for_quantity);
  add_params(*sub, std::shared_ptr<rain::LensDropSettings>(a->job, &a->job->settings), rain::lens_drops_params(),
             cmd.flags_for_quantity);
  add_params(*sub, std::shared_ptr<rain::LensDropsFileOptions>(a->job, &a->job->files), rain::lens_drops_file_params(),
             cmd.flags_for_quantity);
  add_params(*sub, std::shared_ptr<io::VideoFileOptions>(a->job, &a->job->video_files), io::video_file_params(),
             cmd.flags_for_quantity);
  sub->add_flag("-q,--quiet", a->quiet, "No progress or summary on stderr");
  cmd.run = [a, sub] {
    a->job->given = given_on(*sub, rain::lens_drops_params(), rain::lens_drops_file_params(), io::video_file_params());
    return run_frame_command(*a, "lens-drops", io::run_lens_drops_job, io::lens_drops_summary);
  };
  return cmd;
}

}  // namespace hydrolux::cli
