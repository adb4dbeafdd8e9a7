#pragma once
// Fog, haze and mist over a photograph (docs/fog.md): a homogeneous layer of water droplets between
// the camera and the scene, from first principles.
//
// Extinction. Either from a meteorological visibility V by Koschmieder's law, beta = -ln(0.02) / V
// = 3.912 / V (the distance at which a black object's contrast against the horizon sky falls to the
// 2% threshold; Koschmieder 1924, as WMO defines the meteorological optical range with 5% instead:
// 2.996 / V, which we do not use), or from Lorenz-Mie over a droplet size distribution for a liquid
// water content: beta = integral Q_ext(k r) pi r^2 n(r) dr (scatter/mie.hpp, mie_bulk_optics).
//
// The droplets. Shettle & Fenn's (1979, AFGL-TR-79-0214) fog models: the modified gamma
// n(r) = a r^alpha exp(-b r^gamma) with gamma = 1, whose mode radius is alpha / b: alpha = 3 and
// r_mode = 10 um is their heavy advection fog (20 cm^-3, 0.37 g/m^3, V ~ 130 m), alpha = 6 and
// r_mode = 2 um their moderate radiation fog. It is the library's gamma distribution
// (scatter/size_distribution.hpp) with shape alpha + 1; the number density follows from the liquid
// water content, LWC = rho_w (4/3) pi <r^3> N. Water's index 1.333 + 0i at 550 nm: fog droplets
// (x = 2 pi r / lambda ~ 10 - 300) extinguish all visible wavelengths alike (Q_ext ~ 2), so the fog
// is grey, and the single-scattering albedo is 1 (water absorbs ~1e-8 per droplet pass).
//
// The phase function. p(theta), normalised to (1 / 4 pi) integral p dOmega = 1, from the Mie
// amplitudes averaged over the distribution, p = 2 pi sum w (|S1|^2 + |S2|^2) / (k^2 sum w C_sca),
// tabulated in u = sin(theta / 2) (so dOmega = 8 pi u du, and the forward diffraction peak is
// resolved). The visibility route takes its phase function from the same distribution (the
// extinction alone comes from V).
//
// The picture. A pinhole camera (rain::RainCamera: the principal point at the centre, x right, y
// up, z forward). Each pixel's line of sight has a range d = z / cos(off-axis) from its camera depth
// z: the depth map's (camera z in metres, the rain job's convention; non-finite or <= 0 is sky, at
// infinite range), or without one the ground plane below a level camera at camera_height_m (pitched
// by pitch_deg), closed by a backdrop at backdrop_m (rain::ground_plane_depth). Then
//   t = exp(-beta d),  fogged = I t + A (1 - t) + G,
// with A the airlight: the sky's colour (estimate_sky). The mask is the fog's coverage 1 - t.
//
// The glow around lights (G). Light of a source brighter than the sky (its excess E = max(0, I - A)
// per channel) loses E (1 - t) to scattering on its way; A (1 - t) stands for the ambient part. Of
// the excess, the fraction scattered exactly once (and not again) over a path of optical depth
// tau = beta d is tau e^-tau = tau t (single scattering: each length dx scatters beta dx, and the
// light must survive the whole path); it reappears around the source, spread by the phase function.
// The rest, 1 - t - tau t, is scattered more than once and becomes part of the diffuse veil, which
// the airlight stands for: so a source at an optical depth of 5 or more shows no glow of its own, as
// in thick fog, and one at tau = 1 the most (0.37 of its excess). A scatterer at distance x from the
// camera, on the way to a source at D, shows light scattered by theta at an apparent angle
// ~ theta (1 - x / D) from the source (small angles); with the scatterers spread evenly along the
// path (weighting by the attenuation left out) the apparent phase function is
// p_app(u) = (1 / u) integral_u^1 p(v) dv, which again integrates to 1. Per source pixel s and
// target pixel t (solid angles Omega), with S = E tau t the once-scattered excess:
//   G_t = sum_s S_s Omega_s p_app(u_st) / (4 pi),
// and a pixel's own light S F_app(u_c) within the cap of its own solid angle. So the glow over the
// whole sphere carries exactly the once-scattered excess of the sources, and within the frame the
// apparent phase function's fraction of it. The sum runs over cells (the frame's pixels averaged in
// blocks): the finest blocks for which the sum over (source cell, cell) pairs stays within a budget
// (fog_glow), down to kGlowCells cells along the longer side; the cells' glow is interpolated
// bilinearly to the pixels.
#include <cmath>
#include <optional>
#include <span>
#include <string_view>
#include <string>
#include <vector>

#include "hydrolux/core/image.hpp"
#include "hydrolux/core/params.hpp"
#include "hydrolux/core/progress.hpp"
#include "hydrolux/rain/rain.hpp"
#include "hydrolux/scatter/size_distribution.hpp"

namespace hydrolux::rain {

// Koschmieder's contrast threshold and -ln of it: beta = kKoschmieder / V.
inline constexpr double kKoschmiederContrast = 0.02;
inline const double kKoschmieder = -std::log(kKoschmiederContrast);  // 3.912
double koschmieder_beta_per_m(double visibility_m);
double koschmieder_visibility_m(double beta_per_m);

// The fog a user asks for (ranges declared with the parameters, fog_params()).
struct FogSettings {
  std::optional<double> visibility_m;  // Koschmieder's route; or
  std::optional<double> lwc_g_m3;      // Mie's: liquid water content, g/m^3
  double mode_radius_um = 10;          // the droplets' mode radius (Shettle & Fenn advection fog)
  double size_alpha = 3;               // modified-gamma shape alpha (3 advection, 6 radiation fog)
  double wavelength_nm = 550;          // of the Mie optics (fog is grey)
  double backdrop_m = 1000;            // without a depth map: the backdrop's camera depth
  bool glow = true;                    // the forward-scattered glow around lights
};
// DomainError naming the setting for a value outside its range; Error when neither or both of
// visibility_m and lwc_g_m3 is given.
void validate(const FogSettings& s);

// The droplets' distribution: the library's gamma with shape alpha + 1 and mode radius r_mode,
// number density from lwc_g_m3 (1 m^-3 without it).
scatter::SizeDistribution fog_distribution(const FogSettings& s);

// A phase function tabulated on u = sin(theta / 2), u_i = i / (n - 1).
struct PhaseTable {
  std::vector<double> p;    // p(u_i), (1 / 4 pi) integral p dOmega = 1
  std::vector<double> cum;  // F(u_i): the fraction scattered within the cap of half-angle theta_i
  // The table of any p(theta) (radians), normalised on the table (trapezoid in u with weight 2 u).
  template <class F>
  static PhaseTable from_function(F&& p_of_theta, int n = 2049) {
    std::vector<double> v(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) v[std::size_t(i)] = p_of_theta(2 * std::asin(double(i) / (n - 1)));
    return from_values(std::move(v));
  }
  static PhaseTable from_values(std::vector<double> p_u);
  // Linear interpolation in u in [0, 1].
  double at(double u) const;
  double cumulative(double u) const;
  // The apparent phase function of scatterers spread evenly along the path (see above):
  // p_app(u) = (1 / u) integral_u^1 p dv (stored as P(u) = integral_u^1 p dv; at() divides by u).
  PhaseTable apparent() const;
  bool divided_by_u = false;  // at() returns p(u) / u (the apparent table)
  double total() const { return cum.empty() ? 0 : cum.back(); }
};

// The fog's optics: extinction and phase function.
struct FogOptics {
  double beta_per_m = 0;
  double visibility_m = 0;      // Koschmieder's V for beta
  double lwc_g_m3 = 0;          // NaN on the visibility route
  double number_per_cm3 = 0;    // NaN on the visibility route
  double effective_radius_um = 0, g = 0;  // of the distribution (Hansen & Travis r_eff; Mie's g)
  PhaseTable phase, apparent;
};
// `phase_nodes` radii and `angles` values of u for the phase table.
FogOptics fog_optics(const FogSettings& s, int angles = 1025, int phase_nodes = 64);
// The Mie extinction (1/m) of the distribution fog_distribution(s) (lwc_g_m3 required).
double mie_fog_beta_per_m(const FogSettings& s, int nodes = 512);

// The sky's colour from the frame: the mean RGB of the brightest tenth (by Rec. 709 luminance) of
// the pixels in the top tenth of the rows (at least one row).
Vec3 estimate_sky(const Image& frame);

struct FogStats {
  double beta_per_m = 0, visibility_m = 0;
  double transmittance_mean = 0, transmittance_min = 0, transmittance_max = 0;
  double range_m_median = 0;  // over pixels at finite range
  double sky_fraction = 0;    // pixels at infinite range (t = 0)
  Vec3 sky{0.0};
  double glow_mean = 0;       // mean luminance the glow adds
  double glow_source_fraction = 0;  // pixels brighter than the sky
  std::uint64_t negative_values_clamped = 0;
};

struct FogFrame {
  Image image;  // the fogged frame, linear RGB (channels beyond 3 copied)
  Image alpha;  // 1 channel: 1 - t
  FogStats stats;
};

// The fog along each pixel's ray, for a renderer that composites it with other media (rain's one
// veil, RainRenderer): transmittance t = exp(-tau) per pixel (0 and tau = inf where the ray meets no
// geometry: the sky), the airlight colour and the glow (empty without it). Checks as render_fog.
struct FogVeil {
  std::vector<double> t;
  std::vector<float> tau;
  Vec3 sky{0.0};
  Image glow;  // 3 channels, or empty
  FogStats stats;
};
// `progress`: called once a row of each pass and once a source cell of the glow; a callback that
// throws (a caller's Ctrl-C) stops the work, the exception passed on. It never changes the result.
FogVeil fog_veil(const Image& frame, const Image* depth, const RainCamera& camera, const FogSettings& s,
                 const FogOptics& optics, std::optional<Vec3> sky = std::nullopt, const ProgressFn& progress = {});

// The frame seen through the veil: clear t + sky (1 - t) + glow per RGB value (negatives read as 0),
// the channels beyond 3 copied. Rows in parallel; the same floats whatever the threads.
Image apply_fog_veil(const Image& frame, const FogVeil& veil);

// Fog over `frame` (linear RGB, >= 3 channels, the camera's size). `depth`: null (the ground plane)
// or 1 channel of camera z, m. `sky`: the airlight colour, or estimate_sky(frame). Error naming the
// pixel and channel for a non-finite input value (NaN, +-inf); negative values read as 0. Deterministic, single-threaded.
// `progress` as fog_veil's (a throwing callback stops the work).
FogFrame render_fog(const Image& frame, const Image* depth, const RainCamera& camera, const FogSettings& s,
                    const FogOptics& optics, std::optional<Vec3> sky = std::nullopt, const ProgressFn& progress = {});

// The glow alone (3 channels) of a source radiance S (3 channels: the excess times tau t),
// through the apparent phase table, for the camera (see above). Cells of at most `cells` pixels
// along the longer side.
// The blocks are the smallest (1x1, 2x2, ...) for which (source cells) x (cells) <= pair_budget, and
// never coarser than `cells` along the longer side. Source values below 1e-6 of the brightest are
// left out.
inline constexpr int kGlowCells = 96;
inline constexpr double kGlowPairBudget = 3e7;
Image fog_glow(const Image& source, const RainCamera& camera, const PhaseTable& apparent, int cells = kGlowCells,
               double pair_budget = kGlowPairBudget, const ProgressFn& progress = {});

// ---- declared parameters (hydrolux fog, hydrolux.fog) ----
struct FogOptions {
  FogSettings settings;
  RainCamera camera;
  std::optional<double> fov_deg;
};
struct FogFileOptions {
  int png_compression = 1;
  double depth_scale_m = 0.001;
};
std::span<const Field<FogOptions>> fog_params();
std::span<const Field<FogFileOptions>> fog_file_params();
// The fog's own parameters (visibility_m, lwc_g_m3, mode_radius_um, size_alpha, wavelength_nm, glow),
// which hydrolux rain's fog rows take too.
const Param& fog_medium_param(std::string_view name);
RainCamera fog_camera_for(const FogOptions& o, int width, int height);

}  // namespace hydrolux::rain
