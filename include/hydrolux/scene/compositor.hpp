#pragma once
// The CPU reference compositor: a rainbow, secondary bow, fogbow or corona put into a daylight
// scene from the Lee tables (atmos/lee.hpp), per pixel, in absolute units; and seed 002's two
// real-time shortcuts (a baked cube map, a tessellated half dome), emulated exactly so their error
// against the per-pixel answer can be measured. docs/sky.md states the model; the GLSL and HLSL
// that `hydrolux export` writes (data/shaders/) implement the same equations, and the web test
// compares the browser's frame with this one.
#include <cmath>
#include <memory>
#include <optional>
#include <vector>

#include "hydrolux/atmos/lee.hpp"
#include "hydrolux/core/image.hpp"
#include "hydrolux/core/params.hpp"
#include "hydrolux/core/vec.hpp"
#include "hydrolux/scene/environment.hpp"
#include "hydrolux/scene/sky_model.hpp"

namespace hydrolux::scene {

// ---- Lee tables as the compositor reads them ----------------------------------------------

// A Lee table's linear RGB (sr^-1, gamut-mapped as in its EXR), rows uniform on their axis.
struct BowTable {
  atmos::LeeTableKind kind = atmos::LeeTableKind::rainbow;
  atmos::AngleAxis axis = atmos::AngleAxis::angle;
  std::vector<double> radius_um;      // per column, increasing
  double row_first = 0, row_last = 0; // row 0's and the last row's axis value (degrees or cosine)
  int rows = 0;
  std::vector<float> rgb;             // rows x columns x 3, row-major
  // The Stokes Q of a table computed with stokes on (atmos::LeeSpec::stokes), in the same layout:
  // Q's XYZ through the table's XYZ -> RGB matrix (signed; > 0 polarised normal to the scattering
  // plane, tangential to the bow), limited per channel to |Q| <= the gamut-mapped I (where the
  // mapping lifted a channel of I, Q's unmapped value could exceed it). Empty for an intensity-only
  // table.
  std::vector<float> q;
  bool has_q() const { return !q.empty(); }
  int columns() const { return int(radius_um.size()); }
  // The scattering angles the rows span, degrees, increasing.
  std::array<double, 2> angle_range_deg() const;
};

// From a computed table (its gamut-mapped RGB, and its Q when it has one).
BowTable bow_table(const atmos::LeeTable& t);
// From a table's parts (a read EXR and its sidecar), none of which is trusted: checks the sizes
// agree; the radii are finite, strictly increasing and within [atmos::kMinRadiusUm, kMaxRadiusUm],
// and, when `radius_scale` is given, uniform on it (in ln r for log, in r for linear; to 1e-6 of
// the span); the rows are finite, within the axis's range ([0, 180] degrees or [-1, 1]), strictly
// increasing (row 0 the smallest angle or cosine, as hydrolux writes them) and uniform (to 1e-6 of
// the span); the values are finite and non-negative (the tables' RGB is gamut-mapped, so a negative
// value is a damaged or forged file). `q`, when not empty, is the table's Stokes Q in the same
// layout: of the same size and finite (the caller checks it against the intensity's XYZ), then
// limited to |Q| <= RGB per channel as above. Throws Error naming what is wrong.
BowTable bow_table(atmos::LeeTableKind kind, atmos::AngleAxis axis, std::vector<double> radius_um,
                   const std::vector<double>& row_values, std::vector<float> rgb,
                   std::optional<atmos::RadiusScale> radius_scale = std::nullopt, std::vector<float> q = {});

// One radius's column of a table, interpolated linearly in ln(radius) (the radius clamped to the
// table's range; `empty` when `outside_is_empty` and the radius lies outside it).
struct BowSlice {
  atmos::LeeTableKind kind = atmos::LeeTableKind::rainbow;
  bool cosine_axis = false;
  float first = 0, last = 0;  // axis values of the first and last row
  int rows = 0;
  std::vector<float> rgb;     // rows x 3
  std::vector<float> q;       // rows x 3, the Stokes Q (BowTable::q); empty without
  // The profile's estimated error (atmos::LeeTable::error's luminance_rms) where it was computed here
  // (compute_bow_slice); unset for a slice of a table read from a file and for one wavelength.
  std::optional<double> error;
  // Where it was computed here: the sampling multiplier its table was computed at (after automatic
  // sampling's second pass, atmos::compute_lee_table), and, where a second pass was made, the first
  // pass's estimate. 0 and unset for a slice read from a file.
  double sampling = 0;
  std::optional<double> first_error;
  bool empty() const { return rows == 0; }
  bool has_q() const { return !q.empty(); }
  // Linear between row centres on the axis; 0 outside [first, last]. `cos_theta` and `theta_deg`
  // are the same angle (the caller has both).
  void lookup(float cos_theta, float theta_deg, float out[3]) const { lookup_in(cos_theta, theta_deg, out, nullptr); }
  // The same of Q (0 when the slice has none).
  void lookup_q(float cos_theta, float theta_deg, float out[3]) const {
    float unused[3];
    lookup_in(cos_theta, theta_deg, unused, out);
  }
  // I into `out` and, when `q_out` is given, Q into it (0 when the slice has none), one search.
  void lookup_in(float cos_theta, float theta_deg, float out[3], float* q_out) const {
    out[0] = out[1] = out[2] = 0;
    if (q_out) q_out[0] = q_out[1] = q_out[2] = 0;
    if (rows == 0) return;
    const float a = cosine_axis ? cos_theta : theta_deg;
    const float lo = first < last ? first : last, hi = first < last ? last : first;
    if (!(a >= lo && a <= hi)) return;
    const bool with_q = q_out && !q.empty();
    if (rows == 1) {
      out[0] = rgb[0], out[1] = rgb[1], out[2] = rgb[2];
      if (with_q) q_out[0] = q[0], q_out[1] = q[1], q_out[2] = q[2];
      return;
    }
    float p = (a - first) / (last - first) * float(rows - 1);
    p = p < 0 ? 0 : (p > float(rows - 1) ? float(rows - 1) : p);
    int i = int(p);
    if (i > rows - 2) i = rows - 2;
    const float f = p - float(i);
    const float* v = &rgb[std::size_t(i) * 3];
    out[0] = v[0] + f * (v[3] - v[0]);
    out[1] = v[1] + f * (v[4] - v[1]);
    out[2] = v[2] + f * (v[5] - v[2]);
    if (with_q) {
      const float* w = &q[std::size_t(i) * 3];
      q_out[0] = w[0] + f * (w[3] - w[0]);
      q_out[1] = w[1] + f * (w[4] - w[1]);
      q_out[2] = w[2] + f * (w[5] - w[2]);
    }
  }
};
BowSlice slice_at_radius(const BowTable& t, double radius_um, bool outside_is_empty = false);

// The rainbow side of a scene: one slice, the same all round the bow (spherical drops), or slices
// at position angles spread evenly over [0, 180] degrees (slice k at 180 k / (n - 1); n >= 2), the
// bow of non-spherical drops, whose radius and width change along the arc. The position angle
// (docs/sky.md, "Drop shapes") runs around the antisolar point from the zenith side (0, the top of
// the bow) to the nadir side (180, the bottom), the same on the left and the right.
struct RainbowSlices {
  std::vector<BowSlice> by_position;  // empty: no rainbow; one: spherical drops
  RainbowSlices() = default;
  RainbowSlices(BowSlice one) { by_position.push_back(std::move(one)); }  // NOLINT: a slice is the round bow
  explicit RainbowSlices(std::vector<BowSlice> slices) : by_position(std::move(slices)) {}
};

// ---- the scene ----------------------------------------------------------------------------

struct Camera {
  double fov_deg = 90;  // horizontal, (0, 180)
  double azimuth_deg = 0, elevation_deg = 10;
  int width = 1280, height = 720;
};

enum class Blend { physical, whitepaper };
enum class BowMode { per_pixel, cube_map, half_dome };
std::string_view blend_name(Blend b);
std::string_view bow_mode_name(BowMode m);

struct SkySettings {
  Camera camera;
  double sun_azimuth_deg = 180, sun_elevation_deg = 25;
  double turbidity = 2.5;
  double radius_um = 500;
  double rain_rate_mmh = 5;
  double curtain_near_m = 1000, curtain_far_m = 3000;
  Vec3 light_color{1.0};
  bool secondary = true, corona = false;
  Blend blend = Blend::physical;
  BowMode mode = BowMode::per_pixel;
  int cube_face_size = 512;          // texels per cube face side
  int dome_rings = 90, dome_segments = 180;
  // A linear polariser in front of the camera (docs/sky.md, "Polarisation"): its transmission axis
  // in the image plane, degrees from the image's horizontal towards its up; none by default (the
  // frame is then bit for bit the one without). Each pixel gets I' = (I + Q cos 2A + U sin 2A) / 2
  // in the pixel's image basis; the bow's and corona's Q come from Stokes tables, the sky's from
  // sky_dolp; the sun's disk, the ground and an environment map are unpolarised.
  std::optional<double> polarizer_deg;
  double sky_max_dolp = kSkyMaxDolpDefault;  // P90 of the sky's polarisation (sky_dolp)
  // The Stokes images instead of one filter: render() gives 9 channels, I (R, G, B), Q and U (each
  // R, G, B) in each pixel's image basis, from which any filter's frame follows as (I + Q cos 2A +
  // U sin 2A) / 2. The physical blend only (the whitepaper's is not linear in the light), and not
  // with a polariser (Error).
  bool stokes = false;
};
// Throws DomainError naming the setting ("fov_deg", "rain_rate_mmh", ...).
void validate(const SkySettings& s);

// The one check of a polarised request, which every door makes (the compositor itself, hydrolux
// sky's job, hydrolux.sky): the Stokes images and a polariser not both; the Stokes images with the
// physical blend only; and with either, the tables' Stokes Q: `rainbow_q` whether every rainbow slice
// carries it, `corona_q` whether the corona, when drawn, does (true for tables still to be computed
// with it). Throws Error in the compositor's words, naming the parameter as the door spells it:
// `door` is Door::cli for the CLI ("--stokes", "--polarizer-deg 10"), Door::python (or library) for the
// library and Python ("stokes", "polarizer_deg 10").
void check_polarization(const SkySettings& s, bool rainbow_q = true, bool corona_q = true,
                        Door door = Door::library);

// The peak memory, in bytes, of rendering `s` into a frame and writing it out (hydrolux sky), so
// that a frame too large for the machine is refused before the work. Measured, not guessed: the
// peak resident set (/usr/bin/time -v) of `hydrolux sky --radius-um 5 --sampling 0.25` grew by
// 27.1 bytes a pixel for a PNG (the frame, its tone-mapped copy, the encoder's 8-bit rows) and
// 33.0 for an EXR (the frame and the encoder's buffers) between 2048x2048 (242 / 279 MB) and
// 4096x4096 (574 / 683 MB); the cube map 72.0 bytes a texel of a face side squared (6 faces x RGB
// float; 204 / 426 MB at faces of 1024 / 2048); a fixed 131-138 MB besides (the libraries, the
// tables). The estimate takes the larger per-pixel cost and 160 MB: 16384x16384 is 9.3 GB (its
// measured peak was 7.2 GB, the PNG path), 1280x720 0.19 GB.
inline constexpr double kSkyBytesPerPixel = 34, kSkyBytesPerCubeTexel = 72, kSkyFixedBytes = 160e6;
double estimated_bytes(const SkySettings& s);

// Secondary-bow window (docs/sky.md): 1 with the secondary on; else smoothstep(132, 136, theta).
float secondary_weight(bool secondary_on, float theta_deg);

// The rain's projected-area coefficient beta_geo = pi M2 (m^-1) of Marshall-Palmer rain.
double rain_beta_geo_per_m(double rain_rate_mmh);

// A cube map of the bow colour for one sun direction and radius (OpenGL face order +X -X +Y -Y +Z
// -Z and orientation), bilinear within a face.
struct CubeMap {
  int size = 0;
  std::vector<float> rgb;  // 6 x size x size x 3
  void lookup(const Vec3T<float>& dir, float out[3]) const;
};

class SkyCompositor {
 public:
  // `rainbow` covers the bow side (90-180 degrees): one slice (spherical drops), or slices by
  // position angle, between which each direction interpolates linearly by its own position angle
  // (in every mode: the cube map bakes it, the half dome takes it from the view ray); `corona` the
  // forward side, empty when absent. All slices of the rainbow must share their kind, axis and
  // rows (Error otherwise). `environment`, when given, replaces the analytic sky and ground (its
  // radiance x environment_scale, taken as cd/m^2). Bakes the cube map or builds the dome when
  // `mode` asks.
  //
  // With a polariser (SkySettings::polarizer_deg) or the Stokes images (stokes) every rainbow slice,
  // and the corona when drawn, must carry the Stokes Q (BowSlice::q; Error otherwise, saying so).
  SkyCompositor(const SkySettings& settings, RainbowSlices rainbow, BowSlice corona,
                std::shared_ptr<const Environment> environment = nullptr, double environment_scale = 1);

  // The composited frame (RGB, cd/m^2; with SkySettings::stokes, the 9 Stokes channels named R, G,
  // B, Q.R, Q.G, Q.B, U.R, U.G, U.B). `moisture` (optional, channel 0 in [0, 1], any size:
  // sampled bilinearly at pixel centres) scales the rain's optical depth. Uses every core.
  Image render(const Image* moisture = nullptr) const;
  // The same into `out`, whose storage is reused when it already has the frame's size (a frame
  // loop allocates nothing).
  void render_into(Image& out, const Image* moisture = nullptr) const;
  // The bow colour T(theta) w(theta) at each pixel (RGB, sr^-1) as the current mode computes it:
  // what the optimisations approximate.
  Image bow_colour() const;

  // The position angle of direction `d` around the antisolar point, degrees in [0, 180] (0 towards
  // the zenith, 180 towards the nadir; 0 at the antisolar point itself and for a sun at the zenith,
  // where it is undefined).
  float position_angle_deg(const Vec3T<float>& d) const;
  // How many position-angle slices the rainbow has (1: the bow is the same all round).
  int rainbow_positions() const { return by_position_.empty() ? 1 : int(by_position_.size()); }

  const SkySettings& settings() const { return s_; }
  const SunSky& sun_sky() const { return sky_; }
  Vec3 sun_direction() const { return sun_; }
  double beta_geo_per_m() const { return beta_geo_; }
  double bake_seconds() const { return bake_seconds_; }

 private:
  // `q_out`, when given: the Stokes Q too (the same interpolation and windows).
  void rainbow_term(const Vec3T<float>& d, float c, float theta_deg, float out[3], float* q_out = nullptr) const;
  void add_corona_term(float c, float theta_deg, float out[3], float* q_out = nullptr) const;
  void bow_pixel(const Vec3T<float>& d, float c, float theta_deg, float out[3], float* q_out = nullptr) const;
  float dome_theta(const Vec3T<float>& d, bool& covered) const;

  SkySettings s_;
  BowSlice rainbow_, corona_;           // rainbow_: the one slice of spherical drops
  std::vector<BowSlice> by_position_;    // non-spherical drops: >= 2 slices over [0, 180] degrees
  // The position angle's frame: its 0 direction (the zenith projected normal to the antisolar
  // direction) and its 90 direction (normal to both); zero for a sun at the zenith.
  Vec3T<float> position_up_{0}, position_side_{0};
  std::shared_ptr<const Environment> env_;
  double env_scale_ = 1;
  SunSky sky_;
  Vec3 sun_{0}, fwd_{0}, right_{0}, up_{0};
  double beta_geo_ = 0;
  CubeMap cube_, cube_q_;  // cube_q_: the bow's Q, baked with a polariser only
  std::vector<Vec3T<float>> dome_;  // (rings + 1) x segments vertices
  Vec3T<float> dome_e1_{0}, dome_e2_{0}, dome_axis_{0};
  double bake_seconds_ = 0;
  // The sky's two Perez factors tabulated per frame (Y, x, y interleaved): over cos t in [0, 1]
  // and over gamma in [0, pi], linear between entries (relative error < 1e-5).
  std::vector<float> sky_zenith_factor_, sky_sun_factor_;
};

// acos for float, Abramowitz and Stegun 4.4.46 (|error| <= 2e-8 rad), branch-light.
inline float fast_acos(float x) {
  const float ax = x < 0 ? -x : x;
  float p = -0.0012624911f;
  p = p * ax + 0.0066700901f;
  p = p * ax - 0.0170881256f;
  p = p * ax + 0.0308918810f;
  p = p * ax - 0.0501743046f;
  p = p * ax + 0.0889789874f;
  p = p * ax - 0.2145988016f;
  p = p * ax + 1.5707963050f;
  const float r = std::sqrt(1.0f - (ax > 1 ? 1.0f : ax)) * p;
  return x < 0 ? 3.14159265358979f - r : r;
}

// Tone mapping of docs/sky.md: x = 0.6 L / l_ref per channel, extended Reinhard with white 6,
// clamped to [0, 1] (linear display values; the PNG encoder applies the sRGB curve).
Image tone_map(const Image& radiance, double l_ref);

// Errors of an approximate bow colour against the reference, relative to the reference's peak
// luminance: the largest channel difference and the RMS over pixels and channels.
struct BowError {
  double max_rel = 0, rms_rel = 0;
};
BowError bow_error(const Image& approx, const Image& reference);
// PSNR (dB) of two images of [0, 1] values, over every channel: 10 log10(1 / MSE).
double psnr(const Image& a, const Image& b);

}  // namespace hydrolux::scene
