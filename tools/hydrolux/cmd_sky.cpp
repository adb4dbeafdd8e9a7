// hydrolux sky: a rainbow (secondary, fogbow, corona) in a daylight scene, rendered per pixel from
// the Lee tables on the CPU: the reference the shaders and the web demo are checked against. The
// options are declared in scene/sky_params.hpp, the run over files is io/sky_job.hpp's: this file
// registers the flags, calls the job and reports.
#include <fmt/format.h>

#include <memory>
#include <string>

#include "common.hpp"
#include "hydrolux/atmos/lee.hpp"
#include "hydrolux/core/error.hpp"
#include "hydrolux/io/sky_job.hpp"
#include "hydrolux/scene/bow_tables.hpp"
#include "hydrolux/scene/sky_params.hpp"
#include "image_plugin.hpp"
#include "params.hpp"
#include "progress.hpp"

namespace hydrolux::cli {

namespace {

struct SkyArgs {
  std::shared_ptr<io::SkyJob> job = std::make_shared<io::SkyJob>();
  bool quiet = false;
};

int run_sky(SkyArgs& a, const CLI::App& sub) {
  io::SkyJob& job = *a.job;
  for (const auto& f : scene::sky_params())
    if (given(sub, f.param)) job.given.insert(std::string(f.param.name));
  ProgressBar bar("sky", a.quiet);
  io::SkyJobHooks hooks;
  hooks.codec = image_codec();
  hooks.codec_ready = [] { (void)image_api(); };  // a missing plugin is reported before the tables' work
  hooks.warn = [](const std::string& text) { warn(text); };
  hooks.progress = [&bar](double f, std::string_view label) { bar.update(f, label); };
  hooks.finish_progress = [&bar] { bar.finish(); };
  const io::SkyJobResult r = io::run_sky_job(job, hooks);
  if (!a.quiet) fmt::print(stderr, "{}\n", io::sky_summary(r));
  return 0;
}

}  // namespace

Command add_sky(CLI::App& app) {
  auto a = std::make_shared<SkyArgs>();
  auto* sub = add_job_command(app, "sky");
  Command cmd{sub, [a, sub] { return run_sky(*a, *sub); }, {}};
  const auto params = scene::sky_params();
  // The declared parameters store straight into the job (shared_ptr aliasing its options).
  const auto options = std::shared_ptr<scene::SkyOptions>(a->job, &a->job->options);
  const auto declared = [&](std::string_view first, std::string_view last) {
    add_params(*sub, options, fields_from(params, first, last), cmd.flags_for_quantity);
  };
  declared("sun_elevation_deg", "turbidity");
  sub->add_option("--lut", a->job->luts, "A Lee table .exr (with its .json beside it): a rainbow table, and optionally a corona table; repeat the flag");
  sub->add_option("--moisture", a->job->moisture, "Moisture mask image (red channel, 0-1, stretched over the frame): scales the rain per pixel");
  sub->add_option("--environment", a->job->environment, "Equirectangular HDR background (.exr/.hdr) in cd/m^2 instead of the analytic sky and ground");
  declared("environment_scale", "secondary");
  sub->add_option("--shape", a->job->options.shape,
                  fmt::format("Drop shape: sphere (the Mie tables), spheroid:Q (axis ratio Q = polar / equatorial in "
                              "[{:g}, 1], axis vertical) or beard-chuang (falling drops, Q from the radius; radii up to "
                              "{:g} um). Non-spherical drops' bow changes along its arc: computed by Airy theory of the "
                              "drops' plane section (primary, and the secondary unless --no-secondary) for the sun's "
                              "elevation at position angles 0, 10, ..., 180 degrees around the antisolar point and "
                              "interpolated between them; not with --lut (docs/sky.md)",
                              atmos::kMinBowAxisRatio,
                              scene::max_sky_radius_um(atmos::parse_drop_shape("beard-chuang"))))
      ->capture_default_str();
  declared("blend", "sampling");
  sub->add_option("-o,--output", a->job->output, "Output .png (tone-mapped) or .exr (cd/m^2)");
  sub->add_flag("-q,--quiet", a->quiet, "No progress or summary on stderr");
  cmd.flags_for_quantity.insert(lee_table_quantities().begin(), lee_table_quantities().end());
  return cmd;
}

}  // namespace hydrolux::cli
