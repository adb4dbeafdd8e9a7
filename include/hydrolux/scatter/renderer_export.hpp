#pragma once
// A population of drops as a participating medium for a renderer (`hydrolux medium`, issue 28):
// the size-averaged Lorenz-Mie phase function, the extinction and the single-scattering albedo, in
// Mitsuba 3's and pbrt-v4's own forms and units (docs/renderer-export.md).
//
// What the renderers take (read from their sources, cited in docs/renderer-export.md):
// - Mitsuba 3, medium "homogeneous": sigma_t in inverse scene units times the float `scale`, and
//   `albedo` (bounded to [0, 1] where given as a colour); phase "tabphase": one comma-separated
//   `values` string, points uniform in cos(theta) from -1 (back-scattering) to +1 (forward), the
//   physics convention, interpolated linearly in cos(theta) and normalised by Mitsuba itself so
//   that 2 pi times the trapezoid integral is 1.
// - pbrt-v4, medium "homogeneous": spectra sigma_a and sigma_s (per scene unit, unbounded) times
//   the float `scale`, and one Henyey-Greenstein `g` (clamped by pbrt to [-0.99, 0.99]); pbrt-v4
//   has no tabulated phase function, so the closest form is HG with the phase's own asymmetry
//   parameter, whose error against hydrolux's phase this job states.
//
// The physics (Bohren & Huffman 1983, ch. 4; mie.hpp): for drops of number density n(r), the
// extinction sigma_t = int C_ext(r) n(r) dr (m^-1), likewise sigma_s and sigma_a, and the phase
// function per steradian p(mu) = <i>(mu) / (k^2 <C_sca>) with i = (|S1|^2 + |S2|^2) / 2, <> the
// number-weighted mean and k = 2 pi n_surrounding / lambda; 2 pi int p dmu = 1.
//
// The table: N values uniform in mu. Its error is estimated as the L1 distance over the sphere,
// 2 pi int |p_table - p| dmu, between the table as the renderer interpolates it (linear in mu,
// normalised) and hydrolux's phase, from three more values of p inside every interval (Simpson's
// rule on the quarter points) plus the normalisation's mismatch. The forward diffraction peak of a
// drop of size parameter x is ~ (3.8 / x)^2 / 2 wide in 1 - mu, so a grid uniform in mu resolves
// it only with N of a few x^2 values: fog (x ~ 100) with tens of thousands, rain (x ~ 10^4) never.
// For those, a forward cut: the light scattered into a cone of half-angle theta_c about the forward
// direction (the last grid intervals), beyond the fraction a flat cap keeps, is treated as not
// scattered at all (sigma_s and sigma_t reduced by f sigma_s), in the manner of the delta-M method
// (Wiscombe 1977, J. Atmos. Sci. 34, 1408): for a renderer that light goes straight on, deviated
// by less than theta_c in truth. The job states theta_c and f.
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "hydrolux/core/params.hpp"
#include "hydrolux/core/progress.hpp"
#include "hydrolux/scatter/mie.hpp"
#include "hydrolux/scatter/phase_job.hpp"

namespace hydrolux::optics {
class Medium;
}

namespace hydrolux::scatter {

enum class RendererFormat { mitsuba3, pbrt_v4 };
// "mitsuba3" or "pbrt-v4"; UnknownNameError naming the valid ones.
RendererFormat parse_renderer_format(std::string_view text);
std::string_view renderer_format_name(RendererFormat format);
// The format a file name's extension implies: ".xml" Mitsuba 3, ".pbrt" pbrt-v4; nullopt otherwise.
std::optional<RendererFormat> renderer_format_for_extension(std::string_view lower_extension);

// The spectral grid of the coefficients: 360 to 830 nm every 10 nm, the visible range both
// renderers sample (pbrt-v4's Lambda_min / Lambda_max, Mitsuba's CIE range). pbrt-v4 reads a
// spectrum as zero outside its points, so the grid spans the whole range.
inline constexpr double kExportMinNm = 360, kExportMaxNm = 830, kExportStepNm = 10;
// The automatic table sizes: 2^k + 1 values from 257 to 65537 (a 65537-value table is ~0.8 MB of
// text); a table of a given size may have up to 2^20 + 1.
inline constexpr int kAutoMinValues = 257, kAutoMaxValues = 65537, kMaxTableValues = 1048577;
// The largest forward cut the automatic choice makes, degrees: a cone narrower than a pixel of most
// renders (a 60-degree view 1920 pixels wide has 0.03-degree pixels; glows around lights are wider
// than 2 degrees only in thick fog, where multiple scattering dominates them).
inline constexpr double kAutoMaxCutDeg = 2.0;
inline constexpr double kWaterDensityGM3 = 1e6;

// The numbers a user sets (declared once: medium_params()).
struct MediumRequest {
  std::optional<double> number_per_cm3;  // drops per cm^3 (or lwc_g_m3); Marshall-Palmer rain: neither
  std::optional<double> lwc_g_m3;        // liquid water content, g/m^3
  double phase_wavelength_nm = 550;      // the one table's wavelength
  std::optional<double> values;          // the table's size; unset: the smallest 2^k + 1 that meets max_error
  double max_error = 0.05;               // the L1 error the automatic choices aim at
  // Unset: none, unless the forward peak is beyond the largest automatic table (size parameter of
  // the effective radius above ~280: 3.3 x^2 > 4 * 65537) or the last table tried (65537 values,
  // or the size given) falls short of max_error; then the smallest cut up to kAutoMaxCutDeg that
  // meets max_error (or the one of least error).
  std::optional<double> forward_cut_deg;
  double scene_unit_m = 1;                // one scene unit, metres: the renderers' `scale`
  // The spectra's size average, relative, at every wavelength; unset: kSpectraTolerance. Refused for one
  // radius, which has nothing to average.
  std::optional<double> spectra_tolerance;
  // Radii in the phase's size average (Gauss-Legendre in ln r). Unset: gamma and lognormal drops take
  // kMediumStartNodes, doubled until the average moves by at most half of max_error (L1 over the
  // sphere) when they are doubled again (compute_medium; at most kMediumMaxChosenNodes); Marshall-Palmer
  // rain takes kMediumStartNodes.
  std::optional<int> nodes;
  std::optional<double> temperature_c;
  int threads = 0;
};
std::span<const Field<MediumRequest>> medium_params();
// A parameter by name; throws std::logic_error for a name not declared.
const Param& medium_param(std::string_view name);

struct MediumJob {
  // The drop's radius, or the mean radius of gamma and lognormal; Marshall-Palmer rain ignores it.
  std::optional<double> radius_um;
  std::string size_distribution = "mono";  // parse_size_distribution
  std::shared_ptr<const optics::Medium> medium, surrounding;  // both required
  MediumRequest numbers;
};

struct MediumPlan {
  MediumJob job;
  PhasePlan phase;          // the drops (quadrature, description) at the phase wavelength
  double number_per_m3 = 0;  // drops per m^3
  double weight_scale = 1;  // phase.quadrature's weights times this are drops per m^3
  // The radii of the liquid water content (drops per m^3), and of the spectra for one radius:
  // kSpectralNodes of them, or the phase's if more.
  RadiusQuadrature spectral;
  // A distribution's spectra average over radii they choose (refine_bulk_optics) to
  // MediumRequest::spectra_tolerance: n(r) spectra_scale drops per m^3 per m over [spectra_r_min, spectra_r_max].
  // A fixed count left +-1.5% noise across the spectrum of 10 um fog at 64 radii, 0.1% at 1024.
  std::optional<SizeDistribution> spectra_drops;
  double spectra_r_min = 0, spectra_r_max = 0, spectra_scale = 1;
};
inline constexpr double kSpectraTolerance = 0.005;  // MediumRequest::spectra_tolerance's default
inline constexpr int kSizeCheckPoints = 4097;
// The phase's radii when MediumRequest::nodes is unset: from kMediumStartNodes, doubled while the
// average over them is more than max_error * kMediumSizeShare (L1 over the sphere) from the average over
// twice as many; the table then aims at what is left of max_error. Measured against 8192-16384 radii on
// cloud droplets and fog (gamma 2-20 um, widths 0.05-0.5; lognormal:0.3 10 um): the distance to twice the
// radii is 1.0-1.7 times the true error of the count chosen (docs/renderer-export.md).
inline constexpr int kMediumStartNodes = 64, kMediumMaxChosenNodes = kMaxQuadratureNodes / 2;
inline constexpr double kMediumSizeShare = 0.5;
// Rain's phase (renderer_export.cpp, smoothed_rain_phase): each radius's intensity averaged over angle
// with a Hann window of half-width kRainSmoothingPeriods 2 pi / x, at most kRainSmoothingAngleRatio
// times theta, sampled kRainSmoothingPoints times per half-width, before the size average. Chosen
// against Marshall-Palmer rain averaged over 134,841 radii (docs/renderer-export.md, "Rain"): without
// the cap at 0.5 theta, twice the width blurred the phase at 1 degree by a third; 8 points per
// half-width moved the default table by 2.6e-4 in L1 from 4 (0.6% at its worst value).
inline constexpr double kRainSmoothingPeriods = 1, kRainSmoothingAngleRatio = 0.5;
inline constexpr int kRainSmoothingPoints = 4;
// Rain's drops (x ~ 10^3 to 10^4) ripple far less (extinction within 0.1% of 2 + 2 x^(-2/3)) and each
// costs ~x terms: 256 radii over 50-3000 um.
inline constexpr int kSpectralNodes = 1024, kSpectralRainNodes = 256;

// Checks the job before any work: the declared numbers in their ranges (DomainError naming them),
// the drops as plan_phase checks them (PhaseJobError for the size distribution and the radius),
// the count (Error naming number_per_cm3 / lwc_g_m3: one of them for mono, gamma and lognormal,
// neither for Marshall-Palmer), and the media at every wavelength of the grid.
MediumPlan plan_medium(MediumJob job);

struct TabulatedPhase {
  std::vector<double> values;  // p per steradian at mu_j = -1 + 2 j / (N - 1), as exported (normalised)
  std::vector<double> exact;   // hydrolux's p at the same points (before the cut and the normalisation)
  double normalisation = 1;    // values[j] = exact[j] * normalisation below the cut
  double l1_error = 0;         // estimated L1 distance over the sphere, table (as interpolated) vs phase
  // l1_error plus the size average's own (MediumOptics::phase_size_l1) <= max_error (for a size given by
  // the user: always true).
  bool target_met = true;
  int cut_intervals = 0;       // grid intervals in the forward cone
  double cut_deg = 0;          // the cone's half-angle
  double cut_fraction = 0;     // f: of the scattered light, the part the cut makes unscattered
  double g = 0;                // asymmetry parameter of the exported (cut) phase
  // pbrt-v4's Henyey-Greenstein with g (clamped to 0.99 as pbrt does) against the same phase:
  double hg_g = 0, hg_l1 = 0, hg_forward_ratio = 0, hg_backward_ratio = 0;
  std::size_t size() const { return values.size(); }
};

struct MediumOptics {
  std::vector<double> wavelength_nm;  // the grid
  // Physical (uncut), m^-1, and the asymmetry parameter, per wavelength.
  std::vector<double> extinction_per_m, scattering_per_m, absorption_per_m, g;
  // As exported (after the forward cut), m^-1; albedo = sigma_s / sigma_t.
  std::vector<double> sigma_t_per_m, sigma_s_per_m, sigma_a_per_m, albedo;
  double phase_wavelength_nm = 0;
  MieBulkOptics at_phase_wavelength;  // physical, m^-1
  TabulatedPhase phase;
  std::string drops;  // "gamma distribution, mean radius 10 um, ..."
  double number_per_m3 = 0, lwc_g_m3 = 0;
  double scene_unit_m = 1;
  std::string media;  // "water in air" (and the temperature)
  // Where the phase is less accurate than asked: a count of radii given (or rain's) too few for the Mie
  // ripple (phase_job.hpp's undersampled_ripple_note), or whose size average is more than half of
  // max_error from twice as many. Parameters named between braces ({nodes}): each door spells them
  // (core/error.hpp's spell_quantities); the files state them in the library's names, the CLI warns.
  std::vector<std::string> notes;
  // A distribution's spectra: the largest estimated error over the wavelengths (relative, of the
  // extinction and of g; refine_bulk_optics) and the radii they took; unset for one radius.
  std::optional<double> spectra_error_extinction, spectra_error_g;
  std::size_t spectra_radii = 0;
  double spectra_tolerance = 0;  // what they were chosen for (MediumRequest::spectra_tolerance)
  // The phase's size average's own error, estimated (gamma and lognormal drops): the L1 distance over
  // the sphere, on kSizeCheckPoints values uniform in cos theta, between the phase over the job's radii
  // and over twice as many (the same rule; at most kMaxQuadratureNodes), each normalised. Measured
  // against 8192-16384 radii: 1.0-1.7 times the true distance for the counts chosen, 1.2-1.6 for 64 radii
  // (cloud droplets 2-20 um). A note says when it is more than its share of --max-error. Marshall-Palmer
  // rain keeps its radii (doubling them at x up to 34,000 would take minutes each time), each radius's
  // intensity smoothed over angle first (phase_smoothed; kRainSmoothingPeriods), and states the distance
  // to the same smoothed average over half its radii, outside the table's forward cut (the light within
  // it is not scattered), each phase normalised there. Unset for one radius and the largest counts.
  std::optional<double> phase_size_l1;
  std::size_t phase_radii = 0;       // the radii the phase averages over
  bool phase_radii_chosen = false;   // chosen by the doubling (MediumRequest::nodes unset), not given
  bool phase_radii_rain = false;     // rain's kMediumStartNodes (MediumRequest::nodes unset), not given
  bool phase_smoothed = false;       // rain: each radius smoothed over angle; phase_size_l1 against half the radii
};

// The spectra, then the table (growing it and choosing the cut as the request says). `progress`
// from 0 to 1; it may throw to stop the work.
MediumOptics compute_medium(const MediumPlan& plan, const ProgressFn& progress = {});
MediumOptics run_medium_job(MediumJob job, const ProgressFn& progress = {});

// A medium's name in the files: 1 to 64 of A-Z a-z 0-9 _ . -
bool valid_medium_name(std::string_view name);
inline constexpr std::string_view kDefaultMediumName = "hydrolux_medium";

// The file's text: a Mitsuba 3 XML file whose root is the medium (load it with mi.load_file, or put
// <include filename="..." name="interior"/> inside a shape), or a pbrt-v4 MakeNamedMedium
// statement. Each begins with a comment stating the drops, the units, the grid and the errors.
std::string mitsuba3_medium_xml(const MediumOptics& optics, std::string_view name);
std::string pbrt_v4_medium(const MediumOptics& optics, std::string_view name);
std::string renderer_medium_text(const MediumOptics& optics, RendererFormat format, std::string_view name);

// The phase a renderer evaluates: Mitsuba's tabphase of `values` at mu (linear interpolation,
// normalised by the trapezoid integral), and pbrt-v4's Henyey-Greenstein (g clamped to
// [-0.99, 0.99]); mu = cos of the scattering angle, 1 forward; per steradian.
double tabphase_eval(std::span<const double> values, double mu);
double henyey_greenstein(double g, double mu);

}  // namespace hydrolux::scatter
