// hydrolux phase: scattered intensity against angle for one drop, by the theory of one's choice. The
// job is the library's (scatter/phase_job.hpp, as Python's hydrolux.phase): this file reads the
// flags, words the errors with them and prints.
#include <fmt/format.h>

#include <memory>
#include <optional>
#include <string>
#include <utility>

#include "common.hpp"
#include "drop_flags.hpp"
#include "hydrolux/core/error.hpp"
#include "hydrolux/scatter/params.hpp"
#include "hydrolux/scatter/phase_job.hpp"
#include "params.hpp"
#include "progress.hpp"

namespace hydrolux::cli {

namespace {
// The numbers are scatter/params.hpp's; the theory, the drops, the light, the media, the angles
// and the output are this command's.
struct PhaseArgs {
  std::shared_ptr<scatter::PhaseRequest> r = std::make_shared<scatter::PhaseRequest>();
  std::string theory = "mie";
  DropFlags drops;
  double wavelength_nm = 0;
  std::string angles = "0:180:181";
  bool csv = false;
  bool quiet = false;
  const CLI::App* sub = nullptr;  // which flags were given: refused where they have no effect
};

int run_phase(const PhaseArgs& a) {
  scatter::PhaseJob job;
  // The flags in the order they have always been checked: the theory, then this door's own texts
  // in its words (the media, the temperature for them, the angles), then the rest of the job.
  (void)scatter::phase_theory(a.theory);
  fill_drops(job, a.drops, a.r->temperature_c);
  job.angles_deg = parse_angles_deg(a.angles, "--angles-deg");
  job.theory = a.theory;
  job.wavelength_nm = a.wavelength_nm;
  job.numbers = *a.r;
  const scatter::PhasePlan plan = scatter::plan_phase(std::move(job));
  refuse_unused_size_flags(*a.sub, scatter::phase_params(), a.drops);
  ProgressBar bar("phase", a.quiet || (plan.quadrature.size() < 2 && !plan.refine));
  const auto result = scatter::compute_phase(plan, bar.callback());
  bar.finish();
  const auto& mm = result.mueller;

  if (a.csv) {
    for (const auto& note : result.notes) warn(note);  // the table has no header to hold them
    fmt::print("theta_deg,i1,i2,i{}\n", mm ? ",s11,s12,s33,s34" : "");
  } else {
    fmt::print("# theory {}, {}, wavelength {:g} nm: m = {:.6g}{:+.3g}i{}\n", result.theory, result.drops,
               result.wavelength_nm, result.m.real(), result.m.imag(),
               result.radii == 1 ? fmt::format(", x = {:.6g}", result.x) : std::string());
    if (result.radii > 1)
      fmt::print("# number-weighted mean over {} radii{}\n", result.radii,
                 result.last_change
                     ? fmt::format(" (chosen for --tolerance {:g}% at every angle; the last halving moved it {:.2g}% at "
                                   "most{}; estimated error at the worst angle, relative to S11 there: S11 {:.2g}%, "
                                   "S12 {:.2g}%, S33 {:.2g}%, S34 {:.2g}%)",
                                   100 * *result.tolerance, 100 * *result.last_change,
                                   result.shifted_change
                                       ? fmt::format(", a grid shifted by {:.2f} of its spacing differs by {:.2g}% at most",
                                                     scatter::kRefineCheckShift, 100 * *result.shifted_change)
                                       : std::string(),
                                   100 * result.error->s11, 100 * result.error->s12, 100 * result.error->s33,
                                   100 * result.error->s34)
                     : std::string());
    for (const auto& note : result.notes) fmt::print("# {}\n", note);
    fmt::print("# i1 = |S1|^2 (perpendicular), i2 = |S2|^2 (parallel), i = (i1 + i2) / 2 "
               "(Bohren & Huffman normalisation)\n");
    if (mm)
      fmt::print("# Mueller elements S11 = (i2 + i1) / 2, S12 = (i2 - i1) / 2, S33 = Re <S2 S1*>, S34 = Im <S2 S1*> "
                 "(Bohren & Huffman eq. 4.77)\n");
    fmt::print("{:>10}  {:>16}  {:>16}  {:>16}{}\n", "theta_deg", "i1", "i2", "i",
               mm ? fmt::format("  {:>16}  {:>16}  {:>16}  {:>16}", "S11", "S12", "S33", "S34") : std::string());
  }
  for (std::size_t k = 0; k < result.angles_deg.size(); ++k) {
    const double theta_deg = result.angles_deg[k], i1 = result.i1[k], i2 = result.i2[k], i = result.intensity[k];
    if (a.csv)
      fmt::print("{},{:.10e},{:.10e},{:.10e}", theta_deg, i1, i2, i);
    else
      fmt::print("{:>10.4f}  {:>16.9e}  {:>16.9e}  {:>16.9e}", theta_deg, i1, i2, i);
    if (mm && a.csv)
      fmt::print(",{:.10e},{:.10e},{:.10e},{:.10e}", mm->s11[k], mm->s12[k], mm->s33[k], mm->s34[k]);
    else if (mm)
      fmt::print("  {:>16.9e}  {:>16.9e}  {:>16.9e}  {:>16.9e}", mm->s11[k], mm->s12[k], mm->s33[k], mm->s34[k]);
    fmt::print("\n");
  }
  return 0;
}
}  // namespace

Command add_phase(CLI::App& app) {
  auto args = std::make_shared<PhaseArgs>();
  auto* sub = add_job_command(app, "phase");
  args->sub = sub;
  Command cmd{sub,
              [args] { return run_phase(*args); },
              {{"wavelength_nm", "--wavelength-nm"},
               {"temperature_c", "--temperature-c"},
               {"p", "--theory (order P)"}}};
  // The declared parameters (nodes, tolerance; temperature_c; threads; mueller) among this command's own.
  const auto params = scatter::phase_params();
  const auto declared = [&](std::size_t from, std::size_t count = 1) {
    add_params(*sub, args->r, params.subspan(from, count), cmd.flags_for_quantity);
  };
  sub->add_option("--theory", args->theory,
                  "mie, debye:P (Debye order P: 0 diffraction + reflection, 2 primary rainbow, 3 "
                  "secondary), airy (primary rainbow; airy:P for order P), geometric (rays of orders "
                  "0-3 with interference; geometric:P for orders 0..P)")
      ->capture_default_str();
  add_drop_size_flags(*sub, args->drops, ": no --radius-um", cmd.flags_for_quantity);
  declared(0, 2);  // --nodes, --tolerance (which replace one another)
  sub->add_option("--wavelength-nm", args->wavelength_nm, "Vacuum wavelength, nanometres")
      ->required()
      ->check(positive_number(1e6, "nm"));
  add_media_flags(*sub, args->drops);
  declared(2);  // --temperature-c
  sub->add_option("--angles-deg", args->angles,
                  "Scattering angles, degrees (0 = forward): A:B:N (N >= 2, or 1 with A == B) or a list 0,10,90, "
                  "strictly increasing or decreasing")
      ->capture_default_str();
  declared(3);  // --threads
  sub->add_flag("--csv", args->csv,
                "Comma-separated output with a header row: theta_deg,i1,i2,i[,s11,s12,s33,s34 with --mueller]");
  declared(4);  // --mueller
  sub->add_flag("-q,--quiet", args->quiet, "No progress on stderr");
  return cmd;
}

}  // namespace hydrolux::cli
