#pragma once
// Rain over a photograph or a video frame: physically based streaks from a field of drops
// (Garg & Nayar 2004, seed 000: drop size, fall speed, the drop's ~165 degree view of its
// surroundings, streaks as the drop's motion blur). docs/rain.md states the model.
//
// Frames. The camera sits at the origin of its own frame: x to the right, y up, z forward (the
// optical axis), the principal point at the image centre, pixel (x, y) centred at x + 1/2, y + 1/2,
// row 0 at the top. The world frame has the same origin and x axis, y up against gravity; the
// camera is pitched up by pitch_deg about x, and stands height_m above a flat ground.
//
// The rain field. Drops are drawn per radius class from Marshall & Palmer's distribution (the real
// count: 8000 m^-3 mm^-1 per diameter, 1.6e7 m^-4 per radius) inside a box around the part of the
// frustum where a drop of that class can be resolved, and fall at Gunn & Kinzer's terminal velocity
// carried by the wind. Each drop's start position, radius and phase come from a counter-based hash
// of (seed, class, index), and its position at time t is the start moved by velocity x t and wrapped
// periodically into its box: the same drops move on from frame to frame, any frame can be made
// without the ones before it, and the number of drops in the box never changes.
//
// A streak. During the exposure [t, t + exposure] a drop moves along a straight segment, which
// projects to a segment of the image (p0 to p1, length L = |p1 - p0| px). The drop covers a point of
// the image for the fraction of the exposure its disk (radius r = f a / z px) spends over it; the
// disk is widened by the lens's defocus (radius b) to R = sqrt(r^2 + b^2), keeping its area-time
// integral (pi r^2): alpha = (r / R)^2 |[s - c, s + c] n [0, L]| / L with c = sqrt(R^2 - p^2), s and p
// the point's coordinates along and across the segment. Below one pixel (R < 1) the disk becomes a
// one-pixel tent across and along the segment with the same integral, so a thin streak is neither
// lost between pixel centres nor aliased. A pixel takes the product of (1 - alpha) over the drops
// nearer than its scene depth, and their alpha-weighted mean colour.
//
// The drop's light. Each drop shows the composite of Garg & Nayar's eq. 19 (refraction, reflection
// and two internal reflections, Fresnel-weighted) averaged over its disk, looking at an environment
// made from the frame itself: directions inside the camera's field of view see the (blurred) frame,
// directions outside it the sky (the mean of the frame's top rows) above the horizon and the ground
// (the mean of its bottom rows) below. A drop sees ~165 degrees, mostly sky and ground beyond the
// frame, so drops are brighter than a background darker than the sky, as the paper observes.
//
// Unresolved rain. Drops of a class beyond the depth where their streak's peak alpha falls below
// min_alpha, and drops smaller than min_radius_mm, are not drawn: they block the line of sight with
// their geometric cross-section, beta = pi integral a^2 N(a) da over them, and show the same drop
// light (airlight), so the rain's total extinction is the same whether a drop is drawn or not. The
// line of sight ends at the scene's depth: from the depth map (extent_m where it has none, the sky),
// or without one the ground plane closed by a backdrop at backdrop_m.
#include <algorithm>
#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "hydrolux/core/error.hpp"
#include "hydrolux/core/image.hpp"
#include "hydrolux/core/random.hpp"
#include "hydrolux/core/vec.hpp"

namespace hydrolux::rain {

struct RainCamera {
  int width = 1920, height = 1080;  // pixels
  double focal_mm = 35;
  double sensor_width_mm = 36;      // the pixel pitch is sensor_width_mm / width
  double f_number = 0;              // 0: a pinhole, every depth sharp
  double focus_m = 10;              // the focused distance (with f_number > 0)
  double exposure_s = 0.008;
  double fps = 25;                  // frame k is exposed from t = k / fps
  double height_m = 1.7;            // above the ground plane
  double pitch_deg = 0;             // optical axis above the horizon

  double focal_px() const { return focal_mm / sensor_width_mm * width; }
  double pixel_pitch_m() const { return sensor_width_mm * 1e-3 / width; }
  // The image position (pixels) of a point in the camera frame with z > 0.
  std::array<double, 2> project(const Vec3& p) const;
  // The unit ray through image position (px, py), in the camera frame.
  Vec3 ray(double px, double py) const;
  // Camera frame from world frame and back (the pitch).
  Vec3 to_camera(const Vec3& world) const;
  Vec3 to_world(const Vec3& camera) const;
  // The radius (pixels) of the defocus disk of a point at depth z (m); 0 for a pinhole.
  double defocus_radius_px(double z_m) const;
};

// A frame's sides, pixels; an aperture's smallest f-number other than 0 (a pinhole).
inline constexpr int kMinFrameSide = 16, kMaxFrameSide = 16384;
inline constexpr double kMinFNumber = 0.7;

// The focal length that gives a horizontal field of view `fov_deg` on a sensor `sensor_width_mm` wide.
double focal_mm_from_fov(double fov_deg, double sensor_width_mm);

// DomainError naming the quantity ("focal_mm", "exposure_s", ...) for a value outside its range: the
// declared ranges (rain/params.cpp), the frame's sides in [kMinFrameSide, kMaxFrameSide], an f-number
// of 0 (a pinhole) or from kMinFNumber, the focus beyond the focal length, the exposure within one
// frame (1 / fps).
void validate(const RainCamera& camera);

// The rain a user asks for. The valid ranges (and each member's help) are declared once with the
// parameters in rain/params.cpp; validate() checks them and the ranges that follow from other
// members (far_m beyond near_m, max_radius_mm beyond min_radius_mm).
struct RainSettings {
  double rain_rate_mmh = 25;     // rain rate, mm/h (0: no rain)
  double wind_mps = 0;           // horizontal wind speed, m/s; drops move with it
  double wind_dir_deg = 90;      // where it blows to: 0 away from the camera, 90 to its right
  double near_m = 0.5;           // drops nearer than this are left out
  double far_m = 100;            // no drop is drawn beyond this
  double min_radius_mm = 0.1;    // smaller drops count only as unresolved rain
  double max_radius_mm = 2.9;    // larger ones break up (Gunn & Kinzer's table ends there)
  double min_alpha = 0.01;       // a class is drawn out to where its peak alpha falls below this
  double extent_m = 1000;        // the rain's depth where a depth map has none (sky)
  double backdrop_m = 100;       // without a depth map: the ground plane up to a backdrop this far
  double oscillation = 0;        // relative amplitude of the drop's apparent radius oscillation
  double refractive_index = 1.333;  // water, [1.01, 3]
  std::uint64_t seed = 1;
  bool unresolved = true;        // the unresolved rain's extinction and airlight
  int radius_classes = 24;       // log-spaced radius classes
};

// The largest seed every door accepts (core/random.hpp).
using hydrolux::kMaxSeed;

// DomainError naming the setting ("rain_rate_mmh", "near_m", ...) for a value outside its range.
void validate(const RainSettings& settings);

// Marshall & Palmer's drop count per metre of radius per m^3 at radius a (m) for rate h (mm/h).
double marshall_palmer_per_m4(double radius_m, double rain_rate_mmh);

// One radius class of the field.
struct RadiusClass {
  double radius_lo_m = 0, radius_hi_m = 0;
  double number_per_m3 = 0;       // drops per m^3 in the class
  double beta_per_m = 0;          // their geometric extinction, pi integral a^2 N da
  double resolved_to_m = 0;       // depth to which the class is drawn (its largest drop's peak alpha
                                  // reaches min_alpha there), <= far_m; near_m if never
  Vec3 box_lo, box_size;          // the periodic box, world frame, metres
  Vec3 box_inv_size;              // 1 / box_size, per axis
  std::uint64_t count = 0;        // drops in the box
  std::uint64_t first_index = 0;  // of its first drop among all drops
  // The inverse CDF of the class's truncated exponential: a = lo - log1p(u cdf_span) inv_lambda.
  double cdf_span = 0, inv_lambda = 0;
};

// One drop during one exposure, as seen by the camera.
struct Streak {
  float x0, y0, x1, y1;   // image positions at the start and end of the exposure, pixels
  float r;                // the drop's image radius (pixels) at mid-exposure
  float R;                // the footprint radius with defocus, sqrt(r^2 + b^2)
  float z;                // depth (camera z, metres) at mid-exposure
  float rgb[3];           // the drop's radiance (linear)
  float osc_amp, osc_phase, osc_cycles;  // oscillation: amplitude, phase at the start, cycles per exposure
  std::uint32_t drop;     // the drop's index among all drops (low 32 bits)
};

// A field that would hold more than RainField::kMaxDrops drops: the text names the settings to change
// between braces (ParamError), each door spelling them its way.
class TooManyDrops : public ParamError {
 public:
  TooManyDrops(double drops, std::string text) : ParamError(std::move(text)), drops_(drops) {}
  double drops() const noexcept { return drops_; }

 private:
  double drops_;
};

// The drops of one rain, for one camera. Deterministic in (settings, camera, ground_plane).
class RainField {
 public:
  // `ground_plane`: no drop below the ground is kept (used when there is no depth map).
  RainField(const RainSettings& settings, const RainCamera& camera, bool ground_plane = true);

  const RainSettings& settings() const { return s_; }
  const RainCamera& camera() const { return c_; }
  const std::vector<RadiusClass>& classes() const { return classes_; }
  std::uint64_t drop_count() const { return total_; }

  // Drop `index`'s radius (m), its position at time t (world frame, m) and its velocity (m/s).
  double radius_m(std::uint64_t index) const;
  Vec3 position(std::uint64_t index, double t_s) const;
  Vec3 velocity(std::uint64_t index) const;

  // The optical depth of unresolved rain along the ray through image position (px, py) up to the
  // scene depth depth_m (camera z; infinite for none: then extent_m along the ray).
  double unresolved_optical_depth(double depth_m, double cos_off_axis) const;
  // The total geometric extinction of the rain (all radii), m^-1.
  double beta_total_per_m() const { return beta_total_; }

  // The most drops a field may hold (TooManyDrops beyond).
  static constexpr std::uint64_t kMaxDrops = 200'000'000;

 private:
  friend class RainRenderer;
  struct Drop {
    Vec3 start;        // in its class's box at t = 0
    double radius = 0;
    double phase = 0;  // of its oscillation, in [0, 1)
    std::size_t cls = 0;
  };
  Drop drop(std::uint64_t index) const;
  Drop drop(std::uint64_t index, std::size_t cls) const;
  // The same from the drop's key, detail::hash(seed, index) (the renderer has it already).
  Drop drop_with_key(std::uint64_t key, std::size_t cls) const;
  std::size_t class_of(std::uint64_t index) const;
  // The velocity of a drop of this radius: the wind across, the terminal speed down (tabulated).
  Vec3 velocity_of(double radius_m) const {
    const double x = std::clamp((radius_m - lut_lo_) / lut_step_, 0.0, double(velocity_lut_.size() - 1));
    const std::size_t i = std::min(std::size_t(x), velocity_lut_.size() - 2);
    const double v = velocity_lut_[i] + (x - double(i)) * (velocity_lut_[i + 1] - velocity_lut_[i]);
    return Vec3(wind_.x, -v, wind_.z);
  }

  RainSettings s_;
  RainCamera c_;
  bool ground_plane_;
  std::vector<RadiusClass> classes_;
  std::uint64_t total_ = 0;
  double beta_total_ = 0, beta_small_ = 0;
  Vec3 wind_;
  std::vector<float> velocity_lut_;  // terminal velocity over radius
  double lut_lo_ = 0, lut_step_ = 1;
};

// The drops' radiance over the image: Garg & Nayar's composite averaged over a drop's disk, on a
// coarse grid of viewing directions, for an environment made from the frame (see the top).
class DropLight {
 public:
  DropLight(const RainCamera& camera, double refractive_index, int grid_x = 32, int grid_y = 18);
  // Takes the environment from `frame` (linear RGB, the camera's size, >= 3 channels).
  void update(const Image& frame);
  // The drop radiance seen at image position (px, py): bilinear between grid nodes.
  Vec3 at(double px, double py) const;
  // at(x + 1/2, py) for every pixel x of a row, into `out` (width RGB triples, as floats).
  void row(double py, std::vector<float>& out) const;
  Vec3 sky() const { return sky_; }
  Vec3 ground() const { return ground_; }

 private:
  struct Tap {
    std::uint32_t node;
    float u, v, w;  // position in the small frame (pixels), weight
  };
  RainCamera c_;
  int gx_, gy_, small_w_ = 0, small_h_ = 0;
  std::vector<Tap> taps_;                        // for directions inside the frame
  std::vector<float> sky_w_, ground_w_;          // per node, for directions outside it
  std::vector<float> small_;                     // the frame reduced, RGB
  std::vector<Vec3> node_;                       // per node radiance
  std::vector<double> col_ax_;                   // per image column: its position in its grid cell, [0, 1]
  std::vector<int> cell_col_begin_;              // per grid cell (gx_ entries): its first image column
  std::vector<int> small_col_begin_;             // per small column (small_w_ + 1): its first image column
  Vec3 sky_, ground_;
};

// Statistics of one frame, for the log users keep of what they made.
struct RainStats {
  std::uint64_t drops_total = 0;     // drops in the field
  std::uint64_t drops_in_view = 0;   // whose streak touches the frame
  std::uint64_t drops_visible = 0;   // ... on at least one pixel not hidden by the scene
  double streak_length_px_mean = 0, streak_length_px_p50 = 0, streak_length_px_p95 = 0, streak_length_px_max = 0;
  double streak_width_px_mean = 0, streak_width_px_max = 0;  // 2 R
  double drop_luminance_mean = 0;        // of the drops in view (linear, Rec. 709 Y)
  // Over the pixels with streak alpha >= 0.01: the background the streaks cover (the frame behind the
  // unresolved rain's veil) and how much the streaks change it, mean(rainy - background).
  double background_luminance_mean = 0;
  double streak_luminance_gain = 0;
  double alpha_mean = 0;                 // of the whole rain layer over the image
  double streak_pixel_fraction = 0;      // of pixels with streak alpha >= 0.01
  double unresolved_transmittance_mean = 0;
  // Negative input values (a colour transform's undershoot in an EXR) read as 0; how many there were.
  std::uint64_t negative_values_clamped = 0;
  // With fog (RainRenderer::set_fog): its extinction, mean transmittance, airlight colour and glow.
  double fog_beta_per_m = 0, fog_visibility_m = 0, fog_transmittance_mean = 1, fog_glow_mean = 0;
  Vec3 fog_sky{0.0};
};

// What the renderer does with the frame's values: a non-finite one (NaN, +-inf) in any channel is
// refused with NonFinitePixel, naming the first one in row order, since one infinite pixel would
// spread through the drops' light to thousands of outputs; a negative one in RGB is light that cannot
// be and is read as 0, counted in RainStats::negative_values_clamped (channels beyond RGB are copied
// as they are). So every output value is finite.
class NonFinitePixel : public Error {
 public:
  NonFinitePixel(int x, int y, int channel, float value);
  int x() const noexcept { return x_; }
  int y() const noexcept { return y_; }

 private:
  int x_, y_;
};

struct RainFrame {
  Image image;   // the rainy frame, linear RGB (the frame's channels beyond 3 are copied)
  Image alpha;   // 1 channel: the rain's coverage, image = clear (1 - alpha) + layer
  Image layer;   // 4 channels, premultiplied: RGB the rain's light, A = alpha (if requested)
  RainStats stats;
};

// What the streaks over the pixels add up to while a frame is rasterised (RainRenderer's scratch),
// in blocks of kStreakAccumLanes pixels: the block's T (product of 1 - alpha), W (sum of alpha) and
// C (sum of alpha * rgb, three channels), each kStreakAccumLanes floats side by side, so that the
// raster touches one block a streak pixel and the composite loads each quantity as a vector. Rows
// are padded to a whole number of blocks.
inline constexpr int kStreakAccumLanes = 8;
inline constexpr int kStreakAccumFloats = 5 * kStreakAccumLanes;

// The memory, in bytes, that rendering one frame of the camera's size takes beyond the drops
// themselves: the frame as decoded (`input_channels` floats a pixel), the renderer's per-pixel
// buffers, the rainy frame, its alpha, the layer if asked for, and the encoded output on its way to
// a file. Measured (the peak resident size of `hydrolux rain` at two sizes, rain.cpp), so that a
// door can refuse a size that cannot fit before any work instead of failing a minute in.
// `extra_bytes_per_pixel`: what a door holds besides (the folder run's frames in flight).
std::uint64_t estimated_render_bytes(const RainCamera& camera, int input_channels, bool with_layer,
                                     double extra_bytes_per_pixel = 0);
// Throws Error "<what>: rain over WxH needs about X of memory and Y is available; about W'xH' would
// fit" when the estimate exceeds the memory available now (core/memory.hpp).
void check_render_memory(const RainCamera& camera, int input_channels, bool with_layer, const std::string& what,
                         double extra_bytes_per_pixel = 0);
// The same for the other frame jobs: fog over a frame of `channels` channels (with or without the
// glow), and drops on the lens blurred by a disk of `blur_diameter_px`. Upper bounds of the peak
// resident size of `hydrolux fog` / `hydrolux lens-drops` measured at 2048^2 and 4096^2 (budget.cpp),
// checked by tests/cli/test_memory_estimates.cpp.
std::uint64_t estimated_fog_bytes(int width, int height, int channels, bool glow, double extra_bytes_per_pixel = 0);
std::uint64_t estimated_lens_drops_bytes(int width, int height, int channels, double blur_diameter_px);
// Throws Error "<what>: <job> over WxH needs about X of memory and Y is available; about W'xH' would
// fit" when `need` (bytes, of which `fixed` do not grow with the pixels) exceeds the memory available
// now.
void check_frame_memory(const std::string& what, const std::string& job, int width, int height, std::uint64_t need,
                        std::uint64_t fixed);
// check_frame_memory with fog's estimate: every door's check of a fog frame (the CLI's job from the
// header, Python's fog() and the batch on the array).
void check_fog_memory(const std::string& what, int width, int height, int channels, bool glow);

struct FogSettings;
struct FogOptics;

class RainRenderer {
 public:
  explicit RainRenderer(RainField field, int light_grid_x = 32, int light_grid_y = 18);
  const RainField& field() const { return field_; }

  // Fog with the rain, as one medium along each ray (docs/fog.md, "With rain"): the fog's extinction
  // (rain/fog.hpp) and the unresolved rain's add, their airlights mix in proportion to their optical
  // depths, and each streak is seen through the fog in front of it. The ground plane's backdrop is
  // the rain's. The airlight colour is `sky`, or the first frame's (estimate_sky), kept for the
  // sequence. Throws as rain::validate(FogSettings) for bad settings.
  void set_fog(const FogSettings& settings, std::optional<Vec3> sky = std::nullopt);
  bool has_fog() const { return fog_optics_ != nullptr; }

  // The streaks of frame `index` (exposure from index / fps), in drop order: those whose footprint
  // touches the image. Colours from light() as last updated.
  void streaks(std::int64_t frame_index, std::vector<Streak>& out) const;

  // Rain over `frame` (linear RGB, camera.width x camera.height, >= 3 channels). `depth`: null, or
  // 1 channel of the same size holding camera z in metres (non-finite or <= 0: no geometry); without
  // it the ground plane is the scene. Deterministic: the same inputs give the same floats whatever
  // the number of threads.
  RainFrame render(const Image& frame, const Image* depth, std::int64_t frame_index, bool with_layer = false);
  // The same into `out`, reusing its images' memory (a sequence's frames go through one RainFrame).
  void render_into(const Image& frame, const Image* depth, std::int64_t frame_index, bool with_layer, RainFrame& out);

  const DropLight& light() const { return light_; }

 private:
  // The streaks in blocks of drops (each block's in drop order).
  void collect_streaks(std::int64_t frame_index, std::vector<std::vector<Streak>>& per_block) const;

  RainField field_;
  DropLight light_;
  std::vector<float> depth_;  // the scene depth per pixel
  bool ground_plane_ = false; // depth_ (and transmittance_) hold the ground plane's
  std::vector<float> transmittance_;  // of the unresolved rain, per pixel
  // Kept between frames so that a sequence allocates once.
  std::vector<std::vector<Streak>> per_block_;
  std::vector<float> acc_;  // the streaks' accumulators, blocks of kStreakAccumLanes pixels
  std::vector<Streak> banded_;
  std::vector<std::uint32_t> band_offset_;
  // Fog (set_fog): its settings and optics, the airlight colour and, while a frame renders, its
  // extinction for the streaks.
  std::shared_ptr<const FogSettings> fog_settings_;
  std::shared_ptr<const FogOptics> fog_optics_;
  std::optional<Vec3> fog_sky_;
  double fog_beta_ = 0;
};

// The builtin scene (scene::BuiltinSky without its sun disk: a sky, a road, grass and landmarks) as the
// camera sees it, linear RGB, one sample per pixel centre: a frame to try the rain on without a
// photograph, for the gallery and the tests.
Image builtin_scene(const RainCamera& camera);

// The alpha one streak alone puts on a width x height image (1 channel), as the renderer rasterises it.
// simd = false: thin streaks through the scalar reference raster instead of the SIMD one (the same
// floats; tests/rain/test_rain.cpp compares them).
Image streak_alpha(const Streak& streak, int width, int height, bool simd = true);

// The scene depth (camera z, m) assumed without a depth map: the ground plane, and a backdrop at
// backdrop_m (camera z) wherever the ground is farther or absent (above the horizon), so the scene's
// depth, and the rain veil with it, is continuous across the horizon.
std::vector<float> ground_plane_depth(const RainCamera& camera, double backdrop_m);

}  // namespace hydrolux::rain
