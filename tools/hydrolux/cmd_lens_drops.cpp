// hydrolux lens-drops: water drops on the lens or windshield over a photograph or a folder of frames
// (rain/lens_drops.hpp; docs/lens-drops.md). The options are declared in rain/lens_drops.hpp and
// io/lens_drops_job.hpp; the run over files is io/lens_drops_job.hpp's: this file registers the
// flags, calls the job and reports.
#include <fmt/format.h>

#include <memory>
#include <string>

#include "common.hpp"
#include "hydrolux/io/lens_drops_job.hpp"
#include "hydrolux/rain/lens_drops.hpp"
#include "image_plugin.hpp"
#include "params.hpp"

namespace hydrolux::cli {

namespace {

struct LensDropsArgs {
  std::shared_ptr<io::LensDropsJob> job = std::make_shared<io::LensDropsJob>();
  bool quiet = false;
};

}  // namespace

Command add_lens_drops(CLI::App& app) {
  auto a = std::make_shared<LensDropsArgs>();
  auto* sub = app.add_subcommand(
      "lens-drops",
      "Water drops on the lens or windshield over a photograph or a folder of frames: spherical caps on a glass plane "
      "in front of the camera, each refracting the scene behind it (Snell and Fresnel at the exact cap), defocused by "
      "the aperture's circle of confusion, with their coverage mask. Deterministic for a --seed (docs/lens-drops.md).");
  sub->add_option("--image", a->job->image, "Input photograph (PNG, JPEG, EXR, TIFF, ...)");
  sub->add_option("--input-dir", a->job->input_dir, "A folder of frames in name order (frame k: the drops of --seed + k)");
  sub->add_option("-o,--output", a->job->output, "Output image for --image (.png or .exr)");
  sub->add_option("--output-dir", a->job->output_dir, "Output folder for --input-dir (created; never the input folder)");
  sub->add_option("--mask-out", a->job->mask_out,
                  "The drops' defocused coverage for --image: .png (16-bit linear) or .exr; out = clean (1 - mask) + drops");
  sub->add_option("--mask-dir", a->job->mask_dir, "Folder for the masks of --input-dir (same names as the frames)");
  Command cmd{sub, {}, {}};
  add_params(*sub, std::shared_ptr<rain::LensDropSettings>(a->job, &a->job->settings), rain::lens_drops_params(),
             cmd.flags_for_quantity);
  add_params(*sub, std::shared_ptr<rain::LensDropsFileOptions>(a->job, &a->job->files), rain::lens_drops_file_params(),
             cmd.flags_for_quantity);
  sub->add_flag("-q,--quiet", a->quiet, "No summary on stderr");
  cmd.run = [a] {
    const auto r = io::run_lens_drops_job(*a->job, image_codec(), [](const std::string& text) { warn(text); });
    if (!a->quiet) fmt::print(stderr, "{}\n", io::lens_drops_summary(r));
    return report_left_out(r.left_out, r.frames_total);
  };
  return cmd;
}

}  // namespace hydrolux::cli
