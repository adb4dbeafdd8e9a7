// hydrolux export: what an engine needs to draw the bow: the Lee tables (EXR, PNG, raw float32 and
// the JSON axes), the sun and sky parameters over the sun's elevation, and GLSL / HLSL that
// evaluate the sky, the bow, the secondary, the corona and the blend from them (docs/sky.md). The run
// over files is io/export_job.hpp's: this file registers the flags, calls the job and reports.
#include <fmt/format.h>

#include <memory>
#include <string_view>

#include "common.hpp"
#include "hydrolux/atmos/lee.hpp"
#include "hydrolux/io/export_job.hpp"
#include "hydrolux/scene/bow_tables.hpp"
#include "hydrolux/scene/sky_params.hpp"
#include "image_plugin.hpp"
#include "params.hpp"
#include "progress.hpp"

namespace hydrolux::cli {

namespace {

struct ExportArgs {
  CLI::App* sub = nullptr;
  std::shared_ptr<io::ExportJob> job = std::make_shared<io::ExportJob>();
  bool quiet = false;
};

int run_export(const ExportArgs& a) {
  io::ExportJob job = *a.job;
  const auto* sun_flag = a.sub->get_option_no_throw("--sun-elevation-deg");
  if (sun_flag && sun_flag->count() > 0) job.given.insert("sun_elevation_deg");
  ProgressBar bar("export", a.quiet);
  io::ExportJobHooks hooks;
  hooks.codec = image_codec();
  hooks.codec_ready = [] { (void)image_api(); };
  hooks.progress = [&bar](double f, std::string_view label) { bar.update(f, label); };
  hooks.finish_progress = [&bar] { bar.finish(); };
  const io::ExportJobResult r = io::run_export_job(job, hooks);
  if (!a.quiet) fmt::print(stderr, "{}\n", io::export_summary(job, r));
  return 0;
}

}  // namespace

Command add_export(CLI::App& app) {
  auto a = std::make_shared<ExportArgs>();
  auto* sub = a->sub = add_job_command(app, "export");
  sub->add_option("--dir", a->job->dir, "Output folder (created; files of the same names in it are replaced)")->required();
  Command cmd{sub, [a] { return run_export(*a); }, {}};
  // The declared parameters store straight into the job (shared_ptr aliasing its options).
  const auto options = std::shared_ptr<scene::ExportOptions>(a->job, &a->job->options);
  const auto params = scene::export_params();  // --radius-um, --size; then --sampling, --turbidity, --sun-elevation-deg
  add_params(*sub, options, params.first(2), cmd.flags_for_quantity);
  sub->add_option("--theory", a->job->theory, "mie, debye:P, airy or geometric[:P] (hydrolux lee --help) of the spheres' tables")->capture_default_str();
  sub->add_option("--shape", a->job->options.shape,
                  fmt::format("Drop shape: sphere (the spheres' tables only), spheroid:Q (axis ratio Q = polar / "
                              "equatorial in [{:g}, 1], axis vertical) or beard-chuang (falling drops, Q from the "
                              "radius; radii up to {:g} um): also rainbow_shaped.f32/.json, the bow of such drops by "
                              "Airy theory of their plane section (primary and secondary added) over the rainbow "
                              "table's radii (at most {} columns) and rows and position angles 0, 10, ..., 180 "
                              "degrees, for --sun-elevation-deg (docs/sky.md)",
                              atmos::kMinBowAxisRatio, scene::max_sky_radius_um(atmos::parse_drop_shape("beard-chuang")),
                              scene::kShapedTableMaxColumns))
      ->capture_default_str();
  add_params(*sub, options, params.subspan(2), cmd.flags_for_quantity);
  sub->add_flag("-q,--quiet", a->quiet, "No progress or summary on stderr");
  cmd.flags_for_quantity.insert(lee_table_quantities().begin(), lee_table_quantities().end());
  return cmd;
}

}  // namespace hydrolux::cli
