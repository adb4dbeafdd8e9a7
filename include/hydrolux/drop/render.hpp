#pragma once
// A rain drop's picture rendered from a distant environment (Garg & Nayar 2004, section 5 and
// Figure 8; seed 000), by the drop model (model.hpp) or by the exact tracer (trace.hpp).
//
// Camera: a pinhole at the origin looking along +z (world frame of scene/environment.hpp: +y up,
// +x to the right in the image), the drop's centre on the optical axis at (0, 0, distance_m). The
// image spans `frame_m` metres across at the drop's distance (width), with square pixels; pixel
// (x, y) has its centre at x + 1/2, y + 1/2, row 0 at the top (+y). Every pixel gets its own ray
// direction, so the off-axis angle alpha of the drop model varies across the image.
#include <array>
#include <functional>
#include <memory>
#include <optional>

#include "hydrolux/core/image.hpp"
#include "hydrolux/core/progress.hpp"
#include "hydrolux/core/vec.hpp"
#include "hydrolux/scene/environment.hpp"

namespace hydrolux::drop {

class DropSurface;   // trace.hpp
struct TraceOptions;  // trace.hpp

struct Ray {
  Vec3 origin;
  Vec3 direction;  // unit
};

struct DropCamera {
  double radius_m = 1e-3;    // the drop's (equivalent-sphere) radius
  double distance_m = 2.0;   // camera to drop centre
  double frame_m = 5e-3;     // width of the field at the drop's distance
  int width = 512, height = 512;

  // Ray through image position (px, py) in pixels (pixel centres at half-integers).
  Ray ray(double px, double py) const;
  // Image position of a world point in front of the camera (inverse of ray()).
  std::array<double, 2> project(const Vec3& p) const;
  // The drop's image centre (pixels) and its apparent radius (pixels) on the image.
  std::array<double, 2> drop_center_px() const;
  double drop_radius_px() const;
};

// Validates the camera: radius_m in [1e-6, 1] m, distance_m > 1.01 radius_m and <= 1e4 m, frame_m
// in (0, 1e3], width and height in [1, 16384]. DomainError names "radius_m", "distance_m",
// "frame_m", "width" or "height".
void validate(const DropCamera& camera);

// Relative refractive index per RGB channel; all three equal without dispersion.
using ChannelIndex = std::array<double, 3>;

// The vacuum wavelengths that stand for the R, G and B channels in a dispersive render: near the
// dominant wavelengths of the sRGB primaries (red 610, green 550, blue 465 nm).
inline constexpr std::array<double, 3> kChannelWavelengthsNm{610.0, 550.0, 465.0};

// The angular radius (radians) of the disk into which a thin lens of focal length f and f-number N,
// focused at distance D, spreads a point at infinity: the aperture A = f / N is seen from the focus
// plane under the angle A / D, and a point at infinity lights that cone of directions (to first order
// in A / D). DomainError for non-positive arguments or D <= f.
double defocus_blur_radius_rad(double focal_m, double f_number, double focus_distance_m);

struct RenderOptions {
  int samples_per_axis = 4;   // stratified supersamples per pixel along each axis (anti-aliasing)
  int n_internal = 2;         // internal reflections the model adds (eq. 19)
  bool background = true;     // pixels that miss the drop show the environment
  double background_blur_rad = 0;  // angular radius of the defocus disk on the background; 0 sharp
  ProgressFn progress;        // called with the fraction of rows done
};

// Renders with a per-ray shader: `shade` returns the radiance along a camera ray if it hits the
// drop, or nullopt if it misses (then the background, possibly blurred, is used). Parallel over
// rows (oneTBB). Linear radiance.
using RayShader = std::function<std::optional<scene::Rgb>(const Ray&)>;
// The image has 4 channels: RGB and the fraction of the pixel's samples that hit the drop (alpha;
// 1 everywhere when the background is on).
Image render(const DropCamera& camera, const scene::Environment& env, const RenderOptions& options,
             const RayShader& shade);

// The drop model (Garg & Nayar eq. 19) for a sphere: refraction, reflection and options.n_internal
// internal reflections, Fresnel-weighted, with the per-channel index `mu`.
Image render_model(const DropCamera& camera, const scene::Environment& env, const ChannelIndex& mu,
                   const RenderOptions& options);

// Two renders of the same drop compared by zone of the drop's image radius rho (0 centre, 1 rim):
// the RMS of (image - reference) over RGB, as a fraction of the reference's mean radiance, for
// rho <= 0.9 (inner) and 0.9 < rho < 1 (rim). Pixels within 1.5 px of the rim are left out: they mix
// in the background. Both images are camera.width x camera.height with >= 3 channels.
struct ZoneDifference {
  double inner = 0, rim = 0;
};
ZoneDifference compare_by_zone(const Image& image, const Image& reference, const DropCamera& camera);

// The exact reference (trace.hpp): every Fresnel-split path through `surface` followed to
// trace.max_depth, per channel with its own index when `mu` differs between channels. The surface
// is placed by its own centre (normally the camera's drop centre, (0, 0, distance_m)).
Image render_exact(const DropCamera& camera, const scene::Environment& env, const ChannelIndex& mu,
                   const DropSurface& surface, const RenderOptions& options, const TraceOptions& trace);

// The drop at the camera's position as the tracer's surface: a sphere, or Beard & Chuang's shape
// for its radius (scatter/drop_shape.hpp; radii 0.5-4.5 mm) falling along -y.
enum class DropShapeKind { sphere, beard_chuang };
std::unique_ptr<DropSurface> make_drop_surface(const DropCamera& camera, DropShapeKind shape);

}  // namespace hydrolux::drop
