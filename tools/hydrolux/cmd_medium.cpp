// hydrolux medium: a population of drops as a renderer's participating medium (issue 28): Mitsuba 3's
// homogeneous medium with a tabphase, or pbrt-v4's homogeneous medium with Henyey-Greenstein. The job
// is the library's (scatter/renderer_export.hpp): this file reads the flags, words the errors with
// them, reserves the output before the work and writes it at the end.
#include <fmt/format.h>

#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <utility>

#include "common.hpp"
#include "drop_flags.hpp"
#include "hydrolux/core/error.hpp"
#include "hydrolux/io/files.hpp"
#include "hydrolux/scatter/params.hpp"
#include "hydrolux/scatter/renderer_export.hpp"
#include "params.hpp"
#include "progress.hpp"

namespace hydrolux::cli {

namespace {

struct MediumArgs {
  std::shared_ptr<scatter::MediumRequest> r = std::make_shared<scatter::MediumRequest>();
  DropFlags drops;
  std::optional<std::string> format;
  std::string name{scatter::kDefaultMediumName};
  std::string output;
  bool quiet = false;
  const CLI::App* sub = nullptr;  // which flags were given: refused where they have no effect
};

int run_medium(const MediumArgs& a) {
  // The file first: its format (from --format or the extension), then reserved before any work.
  const std::string ext = io::lower_extension(a.output);
  const auto from_ext = scatter::renderer_format_for_extension(ext);
  if (!from_ext)
    throw Error(fmt::format("-o {}: the medium is written as .xml (Mitsuba 3) or .pbrt (pbrt-v4); give one of "
                            "those extensions",
                            printable(a.output)));
  scatter::RendererFormat format = *from_ext;
  if (a.format) {
    format = scatter::parse_renderer_format(*a.format);  // checked by the option's validator
    if (format != *from_ext)
      throw Error(fmt::format("--format {}: -o {} is a {} file; give {}", *a.format, printable(a.output),
                              scatter::renderer_format_name(*from_ext),
                              format == scatter::RendererFormat::mitsuba3 ? ".xml" : ".pbrt"));
  }
  scatter::MediumJob job;
  fill_drops(job, a.drops, a.r->temperature_c);
  job.numbers = *a.r;
  const scatter::MediumPlan plan = scatter::plan_medium(std::move(job));
  refuse_unused_size_flags(*a.sub, scatter::medium_params(), a.drops);
  io::FileSet files;
  io::OutputFile& out = files.output("-o", a.output);
  ProgressBar bar("medium", a.quiet);
  const scatter::MediumOptics optics = scatter::compute_medium(plan, bar.callback());
  bar.finish();
  out.write(scatter::renderer_medium_text(optics, format, a.name));
  files.commit();
  // The file's notes, said once more in the flags' words.
  for (const auto& note : optics.notes) warn(spell_quantities(note, [](std::string_view q) { return Param::flag_of(q); }));
  if (!a.quiet) {
    const auto& t = optics.phase;
    std::size_t i550 = 0;
    while (i550 + 1 < optics.wavelength_nm.size() && optics.wavelength_nm[i550] < 550) ++i550;
    fmt::print(stderr, "{}: {} values{}, L1 error {:.3g}{}; {}\n", a.output, t.size(),
               t.cut_intervals > 0 ? fmt::format(", forward cut {:.3g} deg ({:.3g} of the light)", t.cut_deg,
                                                 t.cut_fraction)
                                   : std::string(),
               t.l1_error, t.target_met ? "" : " (above --max-error)",
               format == scatter::RendererFormat::pbrt_v4
                   ? fmt::format("Henyey-Greenstein g {:.4g}, L1 error {:.3g}", t.hg_g, t.hg_l1)
                   : fmt::format("extinction {:.4g} m^-1 at {:g} nm", optics.extinction_per_m[i550],
                                 optics.wavelength_nm[i550]));
  }
  return 0;
}

}  // namespace

Command add_medium(CLI::App& app) {
  auto args = std::make_shared<MediumArgs>();
  auto* sub = add_job_command(app, "medium");
  args->sub = sub;
  Command cmd{sub,
              [args] { return run_medium(*args); },
              {{"radius_m", "--radius-um (m)"},
               {"wavelength_nm", "--medium/--surrounding (their data's wavelengths)"}}};
  add_drop_size_flags(*sub, args->drops, ", its own count: no --radius-um, --number-per-cm3 or --lwc-g-m3",
                      cmd.flags_for_quantity);
  add_media_flags(*sub, args->drops);
  add_params(*sub, args->r, scatter::medium_params(), cmd.flags_for_quantity);
  sub->add_option("--format", args->format, "mitsuba3 or pbrt-v4 (default: from the extension of -o)")
      ->check(CLI::IsMember({"mitsuba3", "pbrt-v4"}));
  sub->add_option("--name", args->name, "The medium's id (Mitsuba) or name (pbrt): 1-64 of A-Z a-z 0-9 _ . -")
      ->capture_default_str()
      ->check(CLI::Validator(
          [](std::string& v) {
            return scatter::valid_medium_name(v) ? std::string()
                                                 : "'" + printable(v) + "' is not 1-64 of A-Z a-z 0-9 _ . -";
          },
          "NAME"));
  sub->add_option("-o,--output", args->output, "Output file: .xml (Mitsuba 3) or .pbrt (pbrt-v4)")->required();
  sub->add_flag("-q,--quiet", args->quiet, "No progress or summary on stderr");
  return cmd;
}

}  // namespace hydrolux::cli
