#pragma once
// What every frame command (rain, fog, lens-drops) does alike around its job: the driver's hooks
// (io/frame_driver.hpp: the image plugin, warnings on stderr with the progress bar erased first, the
// progress bar), the parameters given, and the run with its summary and exit code.
#include <fmt/format.h>

#include <memory>
#include <string>
#include <string_view>

#include "common.hpp"
#include "hydrolux/io/frame_driver.hpp"
#include "image_plugin.hpp"
#include "params.hpp"
#include "progress.hpp"

namespace hydrolux::cli {

inline io::FrameHooks frame_hooks(ProgressBar& bar) {
  io::FrameHooks hooks;
  hooks.codec = image_codec();  // the plugin loads on first use: a video run never loads OpenImageIO
  hooks.warn = [&bar](const std::string& text) {
    bar.clear();
    warn(text);
  };
  hooks.progress = [&bar](double f, std::string_view label) { bar.update(f, label); };
  hooks.clear_progress = [&bar] { bar.clear(); };
  hooks.finish_progress = [&bar] { bar.finish(); };
  return hooks;
}

// A frame command's arguments: the job its flags store into, and -q.
template <class Job>
struct FrameArgs {
  std::shared_ptr<Job> job = std::make_shared<Job>();
  bool quiet = false;
};

// What the user gave of the tables' parameters on `sub` (FrameRequest::given: the driver refuses by
// the tables' conditions those the run leaves unused).
template <class... Tables>
ParamUse given_on(const CLI::App& sub, Tables... tables) {
  ParamUse use(Door::cli);
  (record_given(sub, tables, use), ...);
  return use;
}

// Runs the job with a progress bar named `name`, says its summary on stderr unless -q, and exits 0,
// or 1 when frames were left out (report_left_out).
template <class Job, class Run, class Summary>
int run_frame_command(const FrameArgs<Job>& a, std::string_view name, Run run, Summary summary) {
  ProgressBar bar(std::string(name), a.quiet);
  const auto r = run(*a.job, frame_hooks(bar));
  if (!a.quiet) fmt::print(stderr, "{}\n", summary(r));
  return report_left_out(r.left_out, r.frames_total);
}

}  // namespace hydrolux::cli
