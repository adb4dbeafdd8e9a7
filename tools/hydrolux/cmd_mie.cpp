// hydrolux mie: Lorenz-Mie scattering by one sphere. The flags give the index and size parameter (or the
// sphere and the light) and the angles; io/mie_job.hpp solves, writes and prints.
#include <fmt/format.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>
#include <optional>
#include <string_view>

#include "common.hpp"
#include "hydrolux/core/error.hpp"
#include "hydrolux/io/mie_job.hpp"
#include "hydrolux/scatter/params.hpp"
#include "hydrolux/scatter/sphere.hpp"
#include "params.hpp"
#include "progress.hpp"

namespace hydrolux::cli {

namespace {
// The numbers and switches are scatter/params.hpp's; the index, the physical form's radius,
// wavelength and media, the angles and the output are this command's.
struct MieArgs {
  std::shared_ptr<scatter::MieRequest> r = std::make_shared<scatter::MieRequest>();
  std::string m_text;
  std::optional<double> radius_um, wavelength_nm;
  std::string medium = "water", surrounding = "air";
  std::string angles = "0:180:181";
  bool json = false, quiet = false;
  std::optional<std::string> output;
};

int run_mie(const MieArgs& a) {
  io::MieJob job;
  job.request = *a.r;
  const scatter::MieRequest& r = job.request;
  const bool dimensionless = !a.m_text.empty() || r.x;
  const bool physical = a.radius_um || a.wavelength_nm;
  if (dimensionless && physical)
    throw Error("give either --m and --x, or --radius-um and --wavelength-nm (with --medium), not both");
  if (a.output && a.output->empty()) throw Error("-o: give a file name (.csv, .npy, .json or .nc)");
  if (r.no_angles && a.output) throw Error("-o writes the amplitudes; --no-angles computes none");
  if (r.no_angles && r.debye) throw Error("--debye restricts the amplitudes; --no-angles computes none");
  if (r.no_angles && r.mueller) throw Error("--mueller derives from the amplitudes; --no-angles computes none");
  if (physical) {
    if (!a.radius_um || !a.wavelength_nm) throw Error("--radius-um and --wavelength-nm go together");
    const auto sphere = medium_flag("--medium", a.medium);
    const auto outside = medium_flag("--surrounding", a.surrounding);
    check_temperature_flag(r.temperature_c, {sphere.get(), outside.get()});
    const auto p = scatter::sphere_problem(*a.radius_um, *a.wavelength_nm, *sphere, *outside, r.temperature_c);
    job.m = p.m;
    job.x = p.x;
    job.sphere = io::MieJob::Sphere{*a.radius_um, *a.wavelength_nm, a.medium, a.surrounding};
  } else {
    if (a.m_text.empty() || !r.x) throw Error("--m and --x go together (or use --radius-um and --wavelength-nm)");
    job.m = parse_complex(a.m_text, "--m");
    job.x = *r.x;
  }
  if (!r.no_angles) job.angles_deg = parse_angles_deg(a.angles, "--angles-deg");
  job.output = a.output;
  job.json = a.json;
  job.command_line = command_line();
  ProgressBar bar("mie", a.quiet);
  io::MieJobHooks hooks;
  hooks.out = [](std::string_view bytes) {
    if (std::fwrite(bytes.data(), 1, bytes.size(), stdout) != bytes.size())
      throw IoFailure(fmt::format("cannot write to standard output: {}", std::strerror(errno)));
  };
  hooks.progress = [&bar](double f, std::string_view label) { bar.update(f, label); };
  hooks.finish_progress = [&bar] { bar.finish(); };
  io::run_mie_job(job, hooks);
  return 0;
}
}  // namespace

Command add_mie(CLI::App& app) {
  auto args = std::make_shared<MieArgs>();
  auto* sub = add_job_command(app, "mie");
  Command cmd{sub,
              [args] { return run_mie(*args); },
              {{"x", "--x"},
               {"m_real", "--m (real part)"},
               {"m_imag", "--m (imaginary part)"},
               {"m_abs", "--m (its modulus)"},
               {"radius_um", "--radius-um"},
               {"wavelength_nm", "--wavelength-nm"},
               {"temperature_c", "--temperature-c"}}};
  // The declared parameters (x; temperature_c; no_angles, debye, mueller, threads) among this command's own.
  const auto params = scatter::mie_params();
  const auto declared = [&](std::size_t from, std::size_t count) {
    add_params(*sub, args->r, params.subspan(from, count), cmd.flags_for_quantity);
  };
  auto* m_opt = sub->add_option("--m", args->m_text,
                                 "Relative complex index n+ki (k >= 0 absorbing; n, k up to 1000, |m| >= 0.001), "
                                 "e.g. 1.333+1e-8i or 10+10i");
  declared(0, 1);
  sub->add_option("--radius-um", args->radius_um, "Sphere radius, micrometres")
      ->check(positive_number(1e6, "um"));
  sub->add_option("--wavelength-nm", args->wavelength_nm, "Vacuum wavelength, nanometres")
      ->check(positive_number(1e6, "nm"));
  auto* medium_opt =
      sub->add_option("--medium", args->medium, "Sphere medium (see hydrolux ior --list)")->capture_default_str();
  auto* surrounding_opt =
      sub->add_option("--surrounding", args->surrounding, "Surrounding medium (air, or const:1 for vacuum)")
          ->capture_default_str();
  declared(1, 1);
  // The dimensionless form takes m and x as they are: media flags would be silently ignored.
  for (auto* o : {m_opt, sub->get_option("--x")})
    o->excludes(medium_opt)->excludes(surrounding_opt)->excludes(sub->get_option("--temperature-c"));
  sub->add_option("--angles-deg", args->angles,
                  "Scattering angles, degrees (0 = forward): A:B:N for N angles from A to B (N from 2 to 1e6, or 1 with "
                  "A == B), or a list 0,10,90, strictly increasing or decreasing")
      ->capture_default_str();
  declared(2, 4);
  sub->add_option("-o,--output", args->output,
                  "Write S1, S2 to this file instead of printing them, by extension: .csv (theta_deg,s1_re,s1_im,"
                  "s2_re,s2_im[,s11,s12,s33,s34 with --mueller]), .npy (float64 array, one row per angle, the same "
                  "five or nine columns), .json (the --json object) or .nc (NetCDF-4 with CF attributes: the "
                  "efficiencies, S1, S2 as real and imaginary parts, the Mueller elements, the phase function "
                  "normalised to 1 over the sphere); written whole or not at all");
  sub->add_flag("--json", args->json,
                "Print one JSON object: x, m, n_terms, qext, qsca, qabs, qback, g, [debye_p,] angles_deg, "
                "s1, s2 ([re, im] pairs), [s11, s12, s33, s34 with --mueller] (with -o: \"output\", the file, "
                "instead of the arrays), compute_s (seconds of "
                "computation alone); streamed, so a million angles need no more memory than their values");
  sub->add_flag("-q,--quiet", args->quiet, "No progress bar on stderr");
  return cmd;
}

}  // namespace hydrolux::cli
