// hydrolux detect-rain and hydrolux rain-eval: rain found in a folder of frames (Garg & Nayar 2004), and
// masks scored against the true ones (rain/detect.hpp, io/detect_job.hpp; docs/rain-detection.md). The
// options are declared there; this file registers the flags, calls the jobs and reports.
#include <fmt/format.h>

#include <iostream>
#include <memory>
#include <span>
#include <string>
#include <string_view>

#include "common.hpp"
#include "hydrolux/io/detect_job.hpp"
#include "hydrolux/rain/detect.hpp"
#include "image_plugin.hpp"
#include "params.hpp"
#include "progress.hpp"

namespace hydrolux::cli {

namespace {

// A job over a folder of frames with its declared paths and settings as flags, -q, a progress bar and its
// summary on stderr: detect-rain and remove-rain.
template <class Job, class Paths, class Settings, class Run, class Summary>
Command add_folder_job(CLI::App& app, std::string_view job_name, std::string_view label,
                       std::span<const Field<Paths>> paths, std::span<const Field<Settings>> settings, Run run,
                       Summary summary) {
  auto job = std::make_shared<Job>();
  auto quiet = std::make_shared<bool>(false);
  auto* sub = add_job_command(app, job_name);
  Command cmd{sub, {}, {}};
  add_params(*sub, std::shared_ptr<Paths>(job), paths, cmd.flags_for_quantity);
  add_params(*sub, std::shared_ptr<Settings>(job, &job->settings), settings, cmd.flags_for_quantity);
  sub->add_flag("-q,--quiet", *quiet, "No progress or summary on stderr");
  cmd.run = [job, quiet, label = std::string(label), run, summary] {
    ProgressBar bar(label, *quiet);
    io::DetectHooks hooks{image_codec(), [&bar](double f, std::string_view text) { bar.update(f, text); }};
    const auto r = run(*job, hooks);
    bar.finish();
    if (!*quiet) fmt::print(stderr, "{}\n", summary(*job, r));
    return 0;
  };
  return cmd;
}

}  // namespace

Command add_detect_rain(CLI::App& app) {
  return add_folder_job<io::DetectJob>(app, "detect_rain", "detect-rain", rain::detect_path_params(),
                                       rain::detect_params(), io::run_detect_job, io::detect_summary);
}

Command add_remove_rain(CLI::App& app) {
  return add_folder_job<io::RemoveJob>(app, "remove_rain", "remove-rain", rain::remove_path_params(),
                                       rain::remove_params(), io::run_remove_job, io::remove_summary);
}

Command add_rain_eval(CLI::App& app) {
  auto job = std::make_shared<io::EvalJob>();
  auto json = std::make_shared<bool>(false);
  auto* sub = add_job_command(app, "rain_eval");
  Command cmd{sub, {}, {}};
  add_params(*sub, std::shared_ptr<rain::EvalPaths>(job), rain::eval_path_params(), cmd.flags_for_quantity);
  add_params(*sub, std::shared_ptr<rain::EvalSettings>(job, &job->settings), rain::eval_params(),
             cmd.flags_for_quantity);
  add_params(*sub, std::shared_ptr<rain::DetectSettings>(job, &job->detector), rain::eval_detector_params(),
             cmd.flags_for_quantity);
  auto quiet = std::make_shared<bool>(false);
  sub->add_flag("-q,--quiet", *quiet, "No progress on stderr");
  sub->add_flag("--json", *json, "Print the report as JSON on stdout (else a summary line per frame and overall)");
  cmd.run = [job, json, quiet] {
    ProgressBar bar("rain-eval", *quiet || !job->input_dir);
    const io::EvalReport r =
        io::run_eval_job(*job, image_codec(), [&bar](double f, std::string_view text) { bar.update(f, text); });
    bar.finish();
    if (*json) {
      std::cout << io::eval_json(*job, r);
      return 0;
    }
    const auto line = [](std::string_view name, const rain::Confusion& c) {
      fmt::print("{:<24} precision {:.4f}  recall {:.4f}  F1 {:.4f}  IoU {:.4f}  (TP {}, FP {}, FN {}, ignored {})\n",
                 name, c.precision(), c.recall(), c.f1(), c.iou(), c.true_positive, c.false_positive,
                 c.false_negative, c.ignored);
    };
    for (const auto& [name, c] : r.frames) line(name, c);
    line("overall", r.overall);
    for (const auto& [method, points] : r.pr) {
      fmt::print("PR curve, {}:", method);
      for (const auto& p : points)
        fmt::print(" c {:g}: P {:.3f} R {:.3f};", p.min_change_grey, p.scores.precision(), p.scores.recall());
      fmt::print("\n");
    }
    if (r.removal_overall)
      fmt::print("removal: PSNR {:.2f} dB in the rain, {:.2f} dB outside it (sRGB codes 0-255)\n",
                 r.removal_overall->psnr_in(), r.removal_overall->psnr_out());
    if (!r.unmatched.empty())
      warn(fmt::format("--pred-dir {}: {} mask{} without a namesake in --truth-dir, not scored", job->pred_dir,
                       r.unmatched.size(), r.unmatched.size() == 1 ? "" : "s"));
    return 0;
  };
  return cmd;
}

}  // namespace hydrolux::cli
