// hydrolux lee: Lee diagrams (colour over scattering angle and drop radius), corona and glory
// tables, as a linear EXR, a display PNG and a JSON sidecar; or one radius's profile as JSON. The run
// over files is io/lee_job.hpp's: this file registers the flags, checks the medium, calls the job and reports.
#include <fmt/format.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <iostream>
#include <memory>
#include <string_view>

#include "common.hpp"
#include "hydrolux/atmos/lee.hpp"
#include "hydrolux/atmos/lee_params.hpp"
#include "hydrolux/core/error.hpp"
#include "hydrolux/io/lee_job.hpp"
#include "hydrolux/optics/media.hpp"
#include "image_plugin.hpp"
#include "params.hpp"
#include "progress.hpp"

namespace hydrolux::cli {

namespace {

struct LeeArgs {
  // The declared values (atmos/lee_params.hpp) and the texts the flags set as they are (--theory, --radius-um, ...).
  std::shared_ptr<io::LeeJob> job = std::make_shared<io::LeeJob>();
  bool quiet = false;
  const CLI::App* sub = nullptr;  // which flags were given: refused where they have no effect
  std::map<std::string, std::string> flags;  // the command's flags_for_quantity: notes in the flags' words
};

int run_lee(const LeeArgs& a) {
  io::LeeJob job = *a.job;
  for (const std::string_view name : atmos::kShapeOnlyParams)
    if (given(*a.sub, atmos::lee_param(name))) job.given.insert(std::string(name));
  for (const std::string_view name : {"limb_darkening", "radius_scale"})
    if (given(*a.sub, atmos::lee_param(name))) job.given.insert(std::string(name));
  job.command_line = command_line();
  atmos::LeeSpec spec = io::lee_job_spec(job);

  const auto drop = medium_flag("--medium", job.medium);  // the media's flags in the CLI's words (common.hpp)
  check_temperature_flag(job.request.temperature_c, {drop.get()});
  ProgressBar bar("lee", a.quiet || job.json);
  io::LeeJobHooks hooks;
  hooks.codec = image_codec();
  hooks.codec_ready = [] { (void)image_api(); };  // image support loads before the work
  hooks.out = [](std::string_view text) {
    std::cout << text;
    std::cout.flush();
    if (!std::cout) throw IoFailure(fmt::format("cannot write to standard output: {}", std::strerror(errno)));
  };
  hooks.progress = [&bar](double f, std::string_view label) { bar.update(f, label); };
  hooks.finish_progress = [&bar] { bar.finish(); };
  // What the table will not resolve, said before the work in the flags' words (the sidecar and the
  // profile keep it too).
  hooks.warn = [&a](std::string_view note) {
    warn(spell_quantities(note, [&a](std::string_view q) {
      const auto it = a.flags.find(std::string(q));
      return it == a.flags.end() ? Param::flag_of(q) : it->second;
    }));
  };
  const io::LeeJobResult r = io::run_lee_job(job, std::move(spec), hooks);
  if (!r.written.empty() && !a.quiet) fmt::print(stderr, "{}\n", io::lee_summary(r));
  return 0;
}

}  // namespace

Command add_lee(CLI::App& app) {
  auto args = std::make_shared<LeeArgs>();
  auto* sub = add_job_command(app, "lee");
  args->sub = sub;
  Command cmd{sub, [args] { return run_lee(*args); }, {}};
  // The declared parameters store straight into the job (shared_ptr aliasing its request).
  const auto req = std::shared_ptr<atmos::LeeRequest>(args->job, &args->job->request);
  const auto declared = [&](std::string_view first, std::string_view last) {
    add_params(*sub, req, fields_from(atmos::lee_params(), first, last), cmd.flags_for_quantity);
  };
  declared("table", "table");
  sub->add_option("--theory", args->job->theory, "mie, debye:P (one Debye order), airy (primary; airy:3 secondary) or geometric[:P] (ray orders 0..P with diffraction)")
      ->capture_default_str();
  sub->add_option("--radius-um", args->job->radius_um,
                  fmt::format("Drop radii A:B in micrometres [{:g}, {:g}], or one radius R [table's default]; the "
                              "size parameter limits the largest: {:g} with Mie, --size-spread 0.1 and 380 nm",
                              atmos::kMinRadiusUm, atmos::kMaxRadiusUm,
                              atmos::max_radius_um(atmos::default_lee_spec(atmos::LeeTableKind::rainbow))));
  declared("radius_scale", "size");
  declared("sun_disk_deg", "size_spread");
  sub->add_option("--wavelengths-nm", args->job->wavelengths,
                  "Wavelengths A:B[:N] in nanometres [360, 830]; N samples (default one per 10 nm)")
      ->capture_default_str();
  declared("temperature_c", "temperature_c");
  sub->add_option("--shape", args->job->request.shape,
                  fmt::format("Drop shape: sphere, spheroid:Q (axis ratio Q = polar / equatorial in [{:g}, 1], axis "
                              "vertical) or beard-chuang (falling drops, Q from the radius); non-spherical drops need "
                              "--theory airy or airy:3 (docs/non-spherical.md)",
                              atmos::kMinBowAxisRatio))
      ->capture_default_str();
  declared("sun_elevation_deg", "canting_deg");
  sub->add_option("--medium", args->job->medium, "Drop medium (hydrolux ior --list)")->capture_default_str();
  sub->add_option("--sun", args->job->sun, "Light source: astm-g173-direct, blackbody:T (kelvin) or equal-energy")
      ->capture_default_str();
  sub->add_option("--color-space", args->job->color_space, "Linear RGB primaries: rec709 (sRGB) or rec2020")
      ->check(CLI::IsMember({"rec709", "srgb", "rec2020"}))
      ->capture_default_str();
  declared("sampling", "threads");
  sub->add_flag("--json", args->job->json,
                "Print one radius's profile (angle, RGB, luminance, XYZ; with --stokes Q's XYZ and dolp) as JSON on "
                "stdout");
  declared("stokes", "stokes");
  sub->add_option("-o,--output", args->job->output,
                  "Output .exr (the .png and .json are written beside it), or .nc: one NetCDF-4 file with CF "
                  "attributes (xarray.open_dataset, ncdump)");
  sub->add_flag("-q,--quiet", args->quiet, "No progress or summary on stderr");
  cmd.flags_for_quantity.insert(lee_table_quantities().begin(), lee_table_quantities().end());
  cmd.flags_for_quantity.insert({{"radius_um", "--radius-um"},
                                 {"wavelength_nm", "--wavelengths-nm"},
                                 {"wavelengths", "--wavelengths-nm"},
                                 {"temperature_k", "--sun"},
                                 {"m_imag", "--medium (its index relative to air)"},
                                 {"m_real", "--medium (its index relative to air)"}});
  args->flags = cmd.flags_for_quantity;
  return cmd;
}

}  // namespace hydrolux::cli
