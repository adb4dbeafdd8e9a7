#pragma once
// Drops on the lens or windshield: adherent water drops on a glass plane a stated distance in front
// of a thin-lens camera, each a spherical cap that refracts the scene behind it, the drop layer
// defocused by the aperture, with its coverage (docs/lens-drops.md).
//
// Conventions: the camera's pinhole (the thin lens' centre) is the origin, +z looks into the scene,
// +x is to the right of the image and +y down it (pixel (px, py) looks along
// ((px - cx) / f_px, (py - cy) / f_px, 1)). The glass is the plane z = glass_distance_m, infinitely
// thin (its two faces change no direction: the refraction into the water depends only on the indices
// of air and water, Snell's invariant n sin(theta) across parallel faces; its Fresnel losses are
// kept). The drops sit on the glass' far side (z > d). The scene is at infinity: a direction is
// looked up in the image by the same pinhole (docs/lens-drops.md, limits).
//
// A cap of footprint (contact) radius a and contact angle theta_c is the part z >= d of a sphere of
// radius R = a / sin(theta_c) whose centre lies R cos(theta_c) before the glass (z = d - R cos
// theta_c); its height is h = R (1 - cos theta_c). theta_c = 90 degrees is a hemisphere.
//
// Units: SI inside (metres, radians); the declared parameters name theirs (mm, deg, m).
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "hydrolux/core/image.hpp"
#include "hydrolux/core/params.hpp"
#include "hydrolux/core/progress.hpp"
#include "hydrolux/core/vec.hpp"

namespace hydrolux::rain {

// What a user sets (declared in lens_drops_params(); the defaults are these initializers).
struct LensDropSettings {
  int drops = 150;                 // drops on the part of the glass the camera sees
  std::optional<double> coverage;  // instead of drops: the fraction of that glass the footprints cover
  double min_radius_mm = 0.4;      // footprint radii, log-uniform between these
  double max_radius_mm = 2.0;
  double trail_fraction = 0;     // drops that ran down, leaving a trail of small drops above them
  double trail_length_mm = 30;
  double contact_angle_deg = 60;
  double glass_distance_m = 0.1;
  double focal_mm = 6;
  double sensor_width_mm = 6.17;
  double f_number = 2;  // 0: a pinhole, no defocus
  double focus_m = 10;
  double water_ior = 1.333;
  double glass_ior = 1.52;
  int samples = 3;  // sub-pixel samples per axis of the sharp drop layer
  std::uint64_t seed = 0;
};

// How a run over files encodes its outputs (hydrolux lens-drops; the Python function returns arrays).
struct LensDropsFileOptions {
  int png_compression = 1;  // the deflate level of PNG outputs: io::kDefaultPngCompression
};

std::span<const Field<LensDropSettings>> lens_drops_params();
std::span<const Field<LensDropsFileOptions>> lens_drops_file_params();

// One drop on the glass.
struct LensCap {
  double x = 0, y = 0;      // footprint centre on the glass, m
  double radius = 0;        // footprint (contact) radius a, m
  double contact_angle = 0; // theta_c, radians in (0, pi/2]
  double sphere_radius() const;  // R = a / sin(theta_c)
  double height() const;         // h = R (1 - cos(theta_c))
};

// A camera ray through a cap: where it leaves the water and in which direction, with its power
// transmittance (unpolarised: the mean of s and p products over the three interfaces).
struct CapRay {
  bool through = false;   // the ray meets the glass inside the footprint
  bool tir = false;       // totally reflected at the cap's surface (transmittance 0)
  Vec3 entry;             // on the glass
  Vec3 exit;              // on the cap's surface
  Vec3 direction;         // unit, in the air behind the drop
  double transmittance = 0;
};

// Traces the camera ray from the origin along `dir` (any length, dir.z > 0) through `cap` on the
// glass at z = glass_z: air -> glass -> water at the plane (Snell, Fresnel for both faces), water ->
// air at the sphere (vector Snell at the outward normal, Fresnel; optics/snell.hpp, fresnel.hpp).
CapRay trace_cap(const LensCap& cap, double glass_z, const Vec3& dir, double water_ior, double glass_ior);

// The thin-lens camera's circle of confusion for a point at distance `distance_m`, as a diameter on
// the sensor in millimetres: c = (f / N) (f / (s - f)) |s - d| / d (f focal length, N f-number, s
// focus distance); 0 for a pinhole (N = 0).
double circle_of_confusion_mm(double focal_mm, double f_number, double focus_m, double distance_m);

// The image blurred by a disk of `radius_px` (pixels): the kernel is the disk's area in each pixel
// row (exact), spread evenly along the row's chord with fractional ends, and divided by pi r^2, so
// it sums to 1 and the flux away from the borders is kept; beyond the borders the edge pixels
// repeat. radius_px < 0.5: returned unchanged.
Image disk_blur(const Image& image, double radius_px);

// The drops for a frame of width x height: footprint centres uniform over the glass the camera sees
// (widened by the largest drop and the blur radius, the count scaled with the area), radii
// log-uniform, no two footprints overlapping (a drop that would is drawn again, up to 50 times, and
// left out if it still does). With trail_fraction, that fraction of the drops has run down the
// glass and left a trail of small drops (0.3 of its radius, ~3 of theirs apart) above it over
// trail_length_mm. Deterministic for the seed. Throws DomainError for a setting out of
// its declared range.
std::vector<LensCap> place_lens_drops(const LensDropSettings& settings, int width, int height);

struct LensDropsResult {
  Image image;  // clean (1 - mask) + blurred premultiplied drop layer, the input's channels
  Image mask;   // one channel: the defocused coverage in [0, 1]
  std::size_t drops = 0;          // placed
  double coverage = 0;            // sharp footprint coverage of the frame (mean of the sharp mask)
  double blur_diameter_px = 0;    // the circle of confusion at the glass, pixels
  double focal_px = 0;
  std::size_t negative_values_clamped = 0;  // negative values of the light channels, read as 0
};

// Throws Error "<what>: lens drops over WxH needs about X of memory ..." when rendering a frame of
// width x height x channels with these settings would not fit in the memory available now
// (rain.hpp's check_frame_memory with estimated_lens_drops_bytes): every door's check.
// `extra_bytes_per_pixel`: what a door holds besides (a pipeline's frames in flight).
void check_lens_drops_memory(const LensDropSettings& settings, const std::string& what, int width, int height,
                             int channels, double extra_bytes_per_pixel = 0);

// Renders the drops over `clean` (linear, any channel count, not modified; the light is its first three
// channels, or the first of a one- or two-channel image: the others pass through unchanged, and negative
// light reads as 0, counted in negative_values_clamped): each sub-pixel sample
// inside a footprint sees transmittance x the image at the traced direction (bilinear, clamped at
// the borders; 0 under total internal reflection), the layer and its coverage are blurred by
// disk_blur with the circle of confusion, and composited over the image. `progress` is called once
// a row of the drops' layer and once a blurred channel, from the worker threads: a callback that
// throws (a caller's Ctrl-C) stops the work, the exception passed on; it never changes the result.
LensDropsResult render_lens_drops(const Image& clean, const LensDropSettings& settings,
                                  const ProgressFn& progress = {});
LensDropsResult render_lens_drops(const Image& clean, const LensDropSettings& settings,
                                  std::span<const LensCap> caps, const ProgressFn& progress = {});

}  // namespace hydrolux::rain
