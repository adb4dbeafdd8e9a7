#pragma once
// A drop's phase function as one job (`hydrolux phase`, Python's `hydrolux.phase`): the intensities
// i1 = |S1|^2 and i2 = |S2|^2 against scattering angle of one drop or a size distribution, by the
// theory of one's choice (theories.hpp), number-weighted over the drops (average_intensities), with
// the size-averaged Mueller elements S11, S12, S33, S34 on request (mueller.hpp). Bohren & Huffman's
// normalisation throughout: i / k^2 is the intensity per drop per unit incident irradiance at unit
// distance.
//
// The doors read their own text forms (the media by name, the angles as "A:B:N" or an array) and
// hand the library what they parsed; the theory and the size distribution are the library's texts
// (parse_theory, parse_size_distribution), read here. The numbers are PhaseRequest's, declared in
// scatter/params.hpp.
#include <cstddef>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "hydrolux/core/error.hpp"
#include "hydrolux/core/progress.hpp"
#include "hydrolux/scatter/mueller.hpp"
#include "hydrolux/scatter/params.hpp"
#include "hydrolux/scatter/size_distribution.hpp"
#include "hydrolux/scatter/sphere.hpp"
#include "hydrolux/scatter/theories.hpp"

namespace hydrolux::optics {
class Medium;
}

namespace hydrolux::scatter {

// Marshall-Palmer rain is averaged over drops of these radii (smaller ones scatter little light and
// larger ones break up).
inline constexpr double kPhaseRainMinRadiusUm = 50, kPhaseRainMaxRadiusUm = 3000;

struct PhaseJob {
  std::string theory = "mie";  // parse_theory: mie, debye:P, airy[:P], geometric[:P]
  // The drop's radius, or the mean radius of gamma and lognormal; Marshall-Palmer rain sets its own
  // radii and refuses one (PhaseJobError naming both).
  std::optional<double> radius_um;
  double wavelength_nm = 0;                 // in vacuum
  std::string size_distribution = "mono";  // parse_size_distribution: mono, gamma:W, lognormal:W, marshall-palmer:H
  std::shared_ptr<const optics::Medium> medium, surrounding;  // the drop's, and around it: both required
  std::vector<double> angles_deg;  // scattering angles in [0, 180] (0 forward), in the output's order
  PhaseRequest numbers;            // nodes, temperature_c, threads, mueller (scatter/params.hpp)
};

// One of the job's texts (or the radius they need) that cannot be read, or two fields that do not
// go together. The text names the fields between braces (ParamError): what() as the library and Python
// do ("theory: unknown theory 'x'; ...", "radius_um 10: size_distribution marshall-palmer:5 sets its own
// radii ..."), said() as a door does ("--radius-um 10: --size-distribution marshall-palmer:5 ...").
class PhaseJobError : public ParamError {
 public:
  enum class Field { theory, size_distribution, radius_um, nodes };
  // `rest`: the text after the field's name, with its separator (": ..." or " ..."), naming the fields
  // it mentions between braces ("{size_distribution}"). `also`: the other field of a combination refused.
  PhaseJobError(Field field, std::string_view rest, std::optional<Field> also = std::nullopt);
  Field field() const noexcept { return field_; }
  std::optional<Field> also() const noexcept { return also_; }
  static std::string_view field_name(Field field);

 private:
  Field field_;
  std::optional<Field> also_;
};

// The job's count of radii (numbers.nodes) given for one radius (mono), which has nothing to average:
// what plan_phase throws for a count other than the default, and a door for any count given.
PhaseJobError one_radius_nodes_error(int nodes, std::string_view size_distribution);

// The job's theory from its text (parse_theory): PhaseJobError for a name it does not know,
// DomainError "p" for an order out of range. plan_phase reads it so; a door that checks the theory
// before its own texts (the CLI, as it always has) may call it first.
Theory phase_theory(std::string_view text);

// What a job asks for, checked and prepared; no scattering computed yet (cheap).
struct PhasePlan {
  PhaseJob job;
  Theory theory;
  RadiusQuadrature quadrature;  // the drops averaged over: one radius for mono, or --nodes radii
  // Without --nodes, a distribution of many radii: averaged to the tolerance over [r_min, r_max] (m)
  // by refine_average_intensities, which chooses the radii.
  std::optional<SizeDistribution> refine;
  double r_min = 0, r_max = 0;
  std::string drops;            // "radius 10 um", "gamma distribution, mean radius 10 um, ..."
  SphereProblem problem;        // of the first radius: m, and x (the drop's for one radius)
};

// Checks the job before any work, in this order: the numbers in their declared ranges (DomainError
// naming nodes, temperature_c, threads), the theory (PhaseJobError; DomainError "p" for an order out
// of range), a temperature given when neither medium models one (Error naming temperature_c), the
// angles (DomainError "angles_deg" out of [0, 180]; Error "angles_deg: ..." unless strictly
// increasing or strictly decreasing, as parse::range_or_list reads them), the size distribution and
// the radius it needs (PhaseJobError; DomainError from the distribution's own checks, e.g.
// "radius_m"), the combinations that would ignore a field (PhaseJobError: a radius with
// Marshall-Palmer rain, which sets its own; a count of radii other than the default with mono),
// then the media at this wavelength (DomainError "wavelength_nm", "temperature_c", "radius_um").
PhasePlan plan_phase(PhaseJob job);

// Radii per unit of size parameter that average the Mie ripple of a size distribution to 1-5% on
// the mean over angles (6-24% at the worst angle; 64 radii: 8-18%, up to 100%), measured on gamma
// and lognormal cloud droplets of 2-10 um at 550 nm against 4096 radii (docs/mie.md, "Size
// averages").
inline constexpr double kRippleNodesPerUnitX = 8;

// A note for a Mie or Debye average over radii spread too thinly across the size parameters they
// cover (fewer than kRippleNodesPerUnitX / 2 per unit of x) when enough radii are within --nodes'
// range; nullopt otherwise (one radius, another theory, or rain's wide range where no allowed count
// would do). compute_phase adds it to the result's notes. `nodes_option` names the count in the
// advice ("give --nodes N or more").
std::optional<std::string> undersampled_ripple_note(const PhasePlan& plan, std::string_view nodes_option = "--nodes");

struct PhaseResult {
  std::vector<double> angles_deg;
  std::vector<double> i1, i2;    // number-weighted means of |S1|^2 (perpendicular), |S2|^2 (parallel)
  std::vector<double> intensity;  // (i1 + i2) / 2: the phase function in B&H's normalisation (S11)
  std::optional<MuellerElements> mueller;  // with numbers.mueller: the size-averaged S11, S12, S33, S34
  // What the output states about itself.
  std::string theory;  // theory_name(): "mie", "debye:2", "airy:2", "geometric:3"
  std::string drops;   // as PhasePlan::drops
  double wavelength_nm = 0;
  Complex m;                 // relative index at the first radius
  double x = 0;              // size parameter of the first radius (the drop's, for one radius)
  std::size_t radii = 0;     // radii averaged over
  RadiusQuadrature quadrature;  // those radii and their weights
  // The automatic average's tolerance, its last halving's largest change at any angle (relative to
  // S11 there: RefinedIntensities::last_change) and its estimated error per Mueller element
  // (RefinedIntensities::error); unset for one radius and --nodes.
  std::optional<double> tolerance, last_change;
  std::optional<MuellerErrors> error;
  // Mie: the grid shifted by kRefineCheckShift of the last spacing, its largest difference from the last
  // grid (RefinedIntensities::shifted_change); unset where it was not computed.
  std::optional<double> shifted_change;
  // Where the theory is out of its depth for this job, one line each (Airy theory away from its
  // rainbow angle, geometric optics at x < 100).
  std::vector<std::string> notes;
};

// The job's intensities: `progress` is called after each radius (and may throw to stop the work).
// Throws DomainError where a radius of the distribution leaves a theory's domain (x, m_real).
PhaseResult compute_phase(const PhasePlan& plan, const ProgressFn& progress = {});

// plan_phase, then compute_phase.
PhaseResult run_phase_job(PhaseJob job, const ProgressFn& progress = {});

}  // namespace hydrolux::scatter
