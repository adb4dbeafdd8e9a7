#pragma once
// Distant environments: radiance arriving from a direction, with no position (the scene at infinity).
//
// World frame: +y up, +z the default camera's forward (the direction the camera looks through a
// drop), +x to the camera's right as seen in the image. Radiance is linear RGB with Rec. 709 / sRGB
// primaries, scene-referred (1 = a white diffuse surface under the builtin sky's sun and sky).
//
// Equirectangular (latitude-longitude) maps: column u in [0, 1) is the longitude
// lambda = 2 pi (u - 1/2) = atan2(x, z), so the map's centre column looks along +z and u grows
// towards +x; row v in [0, 1] is the latitude (1/2 - v) pi = asin(y), row 0 the zenith.
#include <memory>

#include "hydrolux/core/image.hpp"
#include "hydrolux/core/vec.hpp"

namespace hydrolux::scene {

using Rgb = Vec3;  // linear RGB radiance

class Environment {
 public:
  virtual ~Environment() = default;
  // Radiance arriving from unit direction `dir` (the direction light travels is -dir).
  virtual Rgb radiance(const Vec3& dir) const = 0;
};

// (u, v) in [0, 1] of a unit direction, and back, in the convention above.
struct Uv {
  double u = 0, v = 0;
};
Uv equirect_uv(const Vec3& dir);
Vec3 equirect_direction(double u, double v);

// An equirectangular map (any channel count >= 3; the first three are RGB), looked up bilinearly
// with wrap-around in longitude. IoError if the image is empty or has fewer than 3 channels, or if
// its aspect is not 2:1 within one pixel.
class EquirectEnvironment final : public Environment {
 public:
  explicit EquirectEnvironment(Image image);
  Rgb radiance(const Vec3& dir) const override;
  const Image& image() const { return image_; }

 private:
  Image image_;
};

// The builtin environment: an analytic sky, sun and ground, deterministic and resolution-free, so
// that `hydrolux drop render --env builtin` needs no input file. A clear blue sky that brightens to
// the horizon, a sun disk (0.53 degrees, radiance 2000) 35 degrees up and 40 degrees to the left
// of straight ahead, a road running ahead, grass, and coloured landmarks on the horizon that make
// the drop's inversion and distortion readable; environment.cpp has the layout. Without the sun
// disk (its glow and the light on the ground stay) the scene has no sub-pixel highlight, which
// comparisons of pictures pixel by pixel need.
class BuiltinSky final : public Environment {
 public:
  explicit BuiltinSky(bool sun_disk = true) : sun_disk_(sun_disk) {}
  Rgb radiance(const Vec3& dir) const override;

 private:
  bool sun_disk_;
};

// Samples an environment into an equirectangular image `width` x `width / 2` (RGB), averaging
// `samples_per_axis`^2 stratified samples per pixel.
Image bake_equirect(const Environment& env, int width, int samples_per_axis = 2);

}  // namespace hydrolux::scene
