#pragma once
// One entry point for the single-drop theories, so callers (the CLI, LUT builders) choose one by
// name: Lorenz-Mie (exact), one Debye order (exact, one path class), Airy theory of the rainbow
// (approximate, near a rainbow) and geometric optics with interference (approximate, large x).
// All return S1, S2 in the normalisation of mie.hpp, so their intensities compare directly.
#include <algorithm>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "hydrolux/core/progress.hpp"
#include "hydrolux/optics/media.hpp"
#include "hydrolux/scatter/mie.hpp"
#include "hydrolux/scatter/size_distribution.hpp"

namespace hydrolux::scatter {

enum class TheoryKind { Mie, Debye, Airy, Geometric };

struct Theory {
  TheoryKind kind = TheoryKind::Mie;
  int p = 0;  // Debye: the order; Airy: the rainbow order (2 primary, 3 secondary); geometric:
              // the highest ray order summed (0..p)
};

// "mie", "debye:P" (P in 0..1000), "airy" (= airy:2), "airy:P" (P in 2..20), "geometric"
// (= geometric:3: orders 0..3 plus Fraunhofer diffraction), "geometric:P" (P in 0..50).
// Throws UnknownNameError (bad name) or DomainError ("p", bad order).
Theory parse_theory(std::string_view text);
std::string theory_name(const Theory& t);

// S1, S2 at the scattering angles theta_rad (radians, 0 forward) for relative index m and size
// parameter x. threads: 0 = all cores (Mie and Debye; the approximations are single-threaded).
// Airy theory is meaningful near its rainbow angle (airy.hpp) and needs 1 < Re m < p.
void amplitudes(const Theory& t, Complex m, double x, std::span<const double> theta_rad,
                std::span<Complex> s1, std::span<Complex> s2, int threads = 0);

// A Gauss-Legendre quadrature in ln r over the radii of a gamma or log-normal distribution that
// holds its r^2- to r^4-weighted mass (intensities grow like r^2 to r^4) to 1e-6: gamma from 1e-3
// of the mean (drops that small scatter ~ (1e-3)^6 as much; for relative width 1 they are 1e-3 of
// the number) to beta (alpha + 4 + 10 sqrt(alpha + 4)), log-normal from exp(mu - 8 s) to
// exp(mu + 4 s^2 + 8 s).
// Monodisperse gives its one radius. (Marshall-Palmer rain is usually cut to physical radii: use
// SizeDistribution::quadrature(nodes, r_min, r_max).)
RadiusQuadrature intensity_quadrature(const SizeDistribution& d, int nodes);
// The range of radii intensity_quadrature integrates over, in metres (gamma, log-normal; monodisperse:
// its one radius twice; Marshall-Palmer: Error, as there).
std::pair<double, double> intensity_range(const SizeDistribution& d);

// Intensities i1 = |S1|^2 and i2 = |S2|^2 averaged over the drops of a size distribution: the
// number-weighted mean over the quadrature's radii, each drop solved at its own size parameter
// (B&H normalisation, so i / k^2 is the intensity per drop per unit incident irradiance at unit
// distance). Oscillating theories (Mie, Debye) need nodes that resolve the ripple in r, about
// lambda / 10 apart; `progress` is called after each radius. s2_s1conj is the same mean of the
// product S2 S1*, whose real and imaginary parts are the Mueller elements S33 and S34 (mueller.hpp).
struct Intensities {
  std::vector<double> i1, i2;
  std::vector<Complex> s2_s1conj;
};
Intensities average_intensities(const Theory& t, const RadiusQuadrature& q, double wavelength_nm,
                                const optics::Medium& drop, const optics::Medium& surrounding,
                                std::optional<double> temperature_c, std::span<const double> theta_rad,
                                int threads = 0, const ProgressFn& progress = {});

// The same average to a tolerance, choosing its own radii: the trapezoid rule on radii evenly spaced
// over [r_min, r_max] (n(r) vanishes at both ends of a distribution's intensity_range, so the rule
// converges fast once the spacing resolves what the intensities do between radii), the spacing
// halved (each grid keeps the last one's radii), at least twice, until two grids agree to tolerance / 2
// at every angle, relative to S11 = (i1 + i2) / 2 there, in i1, i2 and S2 S1* alike. A wave theory (Mie,
// Debye) starts at radii kRefineStartStepX apart in x, which resolves the interference of rays
// between radii (its ripple is ~0.8 in x) so that two grids cannot agree by aliasing it alike; its
// morphology-dependent resonances, far narrower, are what the halvings then average. For Mie a shifted
// grid checks the halvings once they agree (kRefineCheckShift). At most kMaxRefinedRadii radii:
// converged is false where the last change is still above tolerance / 2, or the shifted grid's
// difference above the tolerance.
// Measured on cloud droplets (gamma 2-20 um, relative width 0.05-0.5, 550 nm) against 2^20 radii:
// within the tolerance at every angle (docs/mie.md, "Size averages").
inline constexpr double kRefineStartStepX = 0.25;
inline constexpr std::size_t kMinRefinedRadii = 65;
inline constexpr std::size_t kMaxRefinedRadii = (std::size_t(1) << 18) + 1;
// The angles a Mie refinement checks besides those asked: every kRefineProbeStepDeg degrees where no angle
// asked is within half a step (none for the 1-degree default grid; none for the other theories, whose
// single orders leave most angles dark). A resonance shows at some angles only:
// checked on ten angles, averages stopped at a quarter of the radii with 4 times the error.
inline constexpr double kRefineProbeStepDeg = 5;
// Where two halvings agree, one more grid checks them: the last spacing's radii each moved by
// kRefineCheckShift of the spacing (the golden section: no grid of the halvings holds any of them), at the
// check's angles (per kRefineProbeStepDeg probe, the angle asked nearest it or the probe itself). The
// nested grids share their nodes, so a component of the intensities' ripple that repeats with the last
// spacing (or any whole fraction of it) is summed alike on every grid, and no halving's change shows it;
// at wide drizzle's resonances that hid 4.5e-3 of S12 (docs/mie.md). The shifted grid sums it at another
// phase. Its difference from the last grid over sqrt(2) counts as the error at least (two grids of one
// spacing whose errors are alike and independent differ by sqrt(2) times either's), and the average
// halves again while that difference is above the tolerance; once it has been, the shifted grid
// alone decides (the halving's change then measures the grid found off) and is the error. It costs
// a grid of the last spacing at about 37 angles: 30-60% more time at 181 angles (BENCHMARKS.md).
inline constexpr double kRefineCheckShift = 0.6180339887498949;
// The error estimate's largest ratio of one halving's change to the one before (RefinedIntensities::error:
// the changes to come summed as a geometric series, r / (1 - r) times the last, at most 4 times).
inline constexpr double kErrorRatioCap = 0.8;
// The largest error at any angle in each size-averaged Mueller element, relative to S11 there.
struct MuellerErrors {
  double s11 = 0, s12 = 0, s33 = 0, s34 = 0;
  double largest() const { return std::max({s11, s12, s33, s34}); }
};
struct RefinedIntensities {
  Intensities averaged;
  RadiusQuadrature quadrature;  // the last grid: its radii and their trapezoid weights n(r) h
  // The last halving's largest change in i1, i2 or S2 S1*, relative to S11 at its angle: what the
  // refinement stops on.
  double last_change = 0;
  // The estimated error per element at its worst angle asked, relative to S11 there: each element's last
  // change times r / (1 - r), r the ratio of the last two halvings' changes (root mean square over the
  // angles checked) capped at kErrorRatioCap; where the shifted grid was computed, at least its
  // difference from the last grid over sqrt(2) (at the check's angles asked), and after a failed check
  // that alone. Measured at the default tolerance against other rules on cloud droplets (2-20 um) and
  // drizzle (50 um): the largest of the four 1.27 to 2.33 times the largest error, and in wide drizzle
  // each within 0.55 to 0.83 of its own (docs/mie.md, "Size averages").
  MuellerErrors error;
  // The shifted grid's largest difference from the last grid in i1, i2 or S2 S1* at the check's angles,
  // relative to S11 there (kRefineCheckShift); unset where the halvings never agreed.
  std::optional<double> shifted_change;
  bool converged = false;
};
RefinedIntensities refine_average_intensities(const Theory& t, const SizeDistribution& d, double r_min, double r_max,
                                              double wavelength_nm, const optics::Medium& drop,
                                              const optics::Medium& surrounding, std::optional<double> temperature_c,
                                              std::span<const double> theta_rad, double tolerance, int threads = 0,
                                              const ProgressFn& progress = {});

// A distribution's bulk optics (mie_bulk_optics) at several wavelengths (relative index m[i] and
// wavenumber k[i] each) to a tolerance, on one grid of radii: the trapezoid rule over radii evenly spaced
// on [r_min, r_max], from kMinRefinedRadii, halved at least twice and until two spacings agree to
// tolerance / 2 at every wavelength in the extinction, in the scattering and absorption (relative to the
// extinction) and in g. The cross sections ripple far less than the intensities at one angle, so no start
// in x is needed. n(r) times `scale` is drops per m^3 per m of radius. The errors estimated as
// RefinedIntensities::error: each quantity's last change times r / (1 - r), r the ratio of the last two
// halvings' changes (root mean square over the wavelengths and quantities), capped at kErrorRatioCap.
struct RefinedBulkOptics {
  std::vector<MieBulkOptics> optics;         // per wavelength
  double error_extinction = 0, error_g = 0;  // estimated, relative to the extinction and to g; the largest
  double last_change = 0;
  std::size_t radii = 0;
  bool converged = false;
};
RefinedBulkOptics refine_bulk_optics(std::span<const Complex> m, std::span<const double> wavenumber_per_m,
                                     const SizeDistribution& d, double r_min, double r_max, double scale,
                                     double tolerance, int threads = 0);

}  // namespace hydrolux::scatter
