#include "hydrolux/scene/environment.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "hydrolux/core/error.hpp"
#include "hydrolux/core/math.hpp"

namespace hydrolux::scene {

Uv equirect_uv(const Vec3& dir) {
  const double lon = std::atan2(dir.x, dir.z);
  const double lat = std::asin(std::clamp(dir.y, -1.0, 1.0));
  return {0.5 + lon / (2 * kPi<>), 0.5 - lat / kPi<>};
}

Vec3 equirect_direction(double u, double v) {
  const double lon = 2 * kPi<> * (u - 0.5);
  const double lat = (0.5 - v) * kPi<>;
  return {std::cos(lat) * std::sin(lon), std::sin(lat), std::cos(lat) * std::cos(lon)};
}

EquirectEnvironment::EquirectEnvironment(Image image) : image_(std::move(image)) {
  if (image_.width < 2 || image_.height < 1 || image_.channels < 3)
    throw IoError(fmt::format("environment map: need an RGB image of at least 2x1 pixels, got {}x{} with {} channels",
                              image_.width, image_.height, image_.channels));
  if (std::abs(image_.width - 2 * image_.height) > 1)
    throw IoError(fmt::format("environment map: an equirectangular map is twice as wide as it is high, got {}x{}",
                              image_.width, image_.height));
}

Rgb EquirectEnvironment::radiance(const Vec3& dir) const {
  const auto [u, v] = equirect_uv(dir);
  const int w = image_.width, h = image_.height;
  // Pixel centres at (x + 1/2) / w; wrap in longitude, clamp in latitude.
  const double x = u * w - 0.5, y = std::clamp(v * h - 0.5, 0.0, double(h - 1));
  const double fx = std::floor(x), fy = std::floor(y);
  const double tx = x - fx, ty = y - fy;
  const int x0 = ((int(fx) % w) + w) % w, x1 = (x0 + 1) % w;
  const int y0 = int(fy), y1 = std::min(y0 + 1, h - 1);
  Rgb out{0, 0, 0};
  for (int c = 0; c < 3; ++c) {
    const double top = (1 - tx) * image_.at(x0, y0, c) + tx * image_.at(x1, y0, c);
    const double bottom = (1 - tx) * image_.at(x0, y1, c) + tx * image_.at(x1, y1, c);
    out[c] = (1 - ty) * top + ty * bottom;
  }
  return out;
}

// --- the builtin environment ---------------------------------------------------------------------
//
// A viewer 1.6 m above flat ground under a clear sky. Everything is a closed-form function of the
// direction, so it can be sampled at any resolution without a texture. Radiances are relative: the
// sun disk is 2000, the zenith sky about 0.25, the horizon sky about 0.9, sunlit grass about 0.1.
// The layout, by longitude (0 straight ahead along +z, positive to the right):
//   - the sun 35 degrees up at -40 degrees (front left), a soft glow around it;
//   - a grey road with a dashed white centre line running straight ahead (+z) and behind (-z);
//   - grass in 4 m checks of two greens on either side of it, fading into haze with distance;
//   - landmarks on the horizon: a red barn (+20), a yellow water tower (-15), a blue house (+60),
//     a white church spire (-70), dark trees scattered between them, and behind the viewer an
//     orange wall (+160 .. -160) that the drop's reflected image shows.
namespace {

struct Landmark {
  double lon0_deg, lon1_deg;  // angular extent in longitude
  double top_deg;             // elevation of the top edge
  double peak_deg;            // extra height of a triangular roof/crown at the centre (0: flat)
  Rgb colour;
};

constexpr double kViewerHeightM = 1.6;
constexpr double kSunElevationDeg = 35, kSunLongitudeDeg = -40;
constexpr double kSunAngularRadius = 0.5 * 0.53 * kPi<> / 180;
constexpr double kSunRadiance = 2000;

const Landmark kLandmarks[] = {
    {14, 26, 3.0, 1.5, {0.45, 0.05, 0.04}},    // red barn with a gable roof
    {-17, -13, 6.0, 0.0, {0.70, 0.55, 0.08}},  // yellow water tower
    {55, 66, 2.2, 1.2, {0.08, 0.15, 0.45}},    // blue house
    {-71, -69, 9.0, 3.0, {0.85, 0.85, 0.82}},  // white spire
    {-74, -66, 3.0, 0.0, {0.80, 0.80, 0.76}},  // the church under it
    {-40, -30, 2.0, 3.5, {0.03, 0.10, 0.03}},  // trees
    {32, 40, 1.5, 3.0, {0.03, 0.09, 0.03}},
    {-100, -85, 1.8, 2.5, {0.04, 0.11, 0.04}},
    {95, 120, 1.5, 2.0, {0.03, 0.10, 0.04}},
    {160, 200, 8.0, 0.0, {0.60, 0.25, 0.05}},  // orange wall behind the viewer (wraps at 180)
};

constexpr double kMaxLandmarkDeg = 12;  // no landmark reaches higher (9 + 3 for the spire)

Vec3 sun_direction() {
  const double e = deg_to_rad(kSunElevationDeg), l = deg_to_rad(kSunLongitudeDeg);
  return {std::cos(e) * std::sin(l), std::sin(e), std::cos(e) * std::cos(l)};
}

Rgb sky(const Vec3& d, const Vec3& sun, bool sun_disk) {
  const double y = std::max(d.y, 0.0);
  const Rgb zenith{0.10, 0.22, 0.55}, horizon{0.75, 0.85, 0.95};
  const double t = sqr(sqr(1 - y));  // (1 - y)^4
  Rgb c = (1 - t) * zenith + t * horizon;
  const double cos_sun = glm::dot(d, sun);
  // Aureole: a forward-scattering glow around the sun, 0.6 cos^64 + 0.15 cos^8 (by squaring).
  const double c8 = sqr(sqr(sqr(std::max(cos_sun, 0.0))));
  c += Rgb{1.0, 0.9, 0.7} * (0.6 * sqr(sqr(sqr(c8))) + 0.15 * c8);
  if (sun_disk && cos_sun > std::cos(kSunAngularRadius)) c += Rgb{1.0, 0.95, 0.88} * kSunRadiance;
  return c;
}

// Longitude difference wrapped into (-180, 180].
double wrap_deg(double a) {
  a = std::fmod(a + 180.0, 360.0);
  if (a < 0) a += 360.0;
  return a - 180.0;
}

const Landmark* landmark_at(double lon_deg, double elev_deg) {
  for (const auto& m : kLandmarks) {
    const double centre = 0.5 * (m.lon0_deg + m.lon1_deg), half = 0.5 * (m.lon1_deg - m.lon0_deg);
    const double off = std::abs(wrap_deg(lon_deg - centre));
    if (off > half) continue;
    const double top = m.top_deg + m.peak_deg * (1 - off / half);
    if (elev_deg <= top) return &m;
  }
  return nullptr;
}

Rgb ground(const Vec3& d, const Vec3& sun) {
  // The ground point seen, in metres from the viewer's feet.
  const double s = kViewerHeightM / -d.y;
  const double x = d.x * s, z = d.z * s, dist = std::sqrt(x * x + z * z);
  Rgb albedo;
  if (std::abs(x) < 3.0) {
    albedo = {0.16, 0.16, 0.17};  // asphalt
    const bool dash = std::abs(x) < 0.08 && std::fmod(std::abs(z), 6.0) < 3.0;
    const bool edge = std::abs(x) > 2.8;
    if (dash || edge) albedo = {0.75, 0.75, 0.72};
  } else {
    const bool check = (int(std::floor(x / 4.0)) + int(std::floor(z / 4.0))) % 2 == 0;
    albedo = check ? Rgb{0.10, 0.22, 0.06} : Rgb{0.16, 0.30, 0.08};
  }
  // Lambertian under the sun and sky: E / pi with the sun's irradiance and a sky ambient term.
  const double sun_e = kSunRadiance * kPi<> * sqr(kSunAngularRadius) * sun.y;
  const double sky_e = 1.2;
  Rgb c = albedo * ((sun_e + sky_e) / kPi<>);
  // Aerial perspective: distant ground fades to the horizon haze (and is not aliased there).
  const double haze = 1 - std::exp(-dist / 400.0);
  return (1 - haze) * c + haze * Rgb{0.70, 0.78, 0.88};
}

}  // namespace

Rgb BuiltinSky::radiance(const Vec3& dir_in) const {
  const Vec3 d = glm::normalize(dir_in);
  static const Vec3 sun = sun_direction();
  const double lon_deg = rad_to_deg(std::atan2(d.x, d.z));
  const double elev_deg = rad_to_deg(std::asin(std::clamp(d.y, -1.0, 1.0)));
  if (elev_deg >= 0) {
    if (const Landmark* m = elev_deg < kMaxLandmarkDeg ? landmark_at(lon_deg, elev_deg) : nullptr) {
      // Sunlit from the front left: faces turned towards the sun's longitude are brighter.
      const double facing = 0.6 + 0.4 * std::cos(deg_to_rad(lon_deg - kSunLongitudeDeg));
      return m->colour * facing;
    }
    return sky(d, sun, sun_disk_);
  }
  return ground(d, sun);
}

Image bake_equirect(const Environment& env, int width, int samples_per_axis) {
  require_in_range("width", width, 2, 65536, "an equirectangular map");
  require_in_range("samples_per_axis", samples_per_axis, 1, 64, "an equirectangular map");
  const int height = std::max(1, width / 2);
  Image img(width, height, 3);
  const int n = samples_per_axis;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      Rgb sum{0, 0, 0};
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
          const double u = (x + (i + 0.5) / n) / width, v = (y + (j + 0.5) / n) / height;
          sum += env.radiance(equirect_direction(u, v));
        }
      for (int c = 0; c < 3; ++c) img.at(x, y, c) = float(sum[c] / (n * n));
    }
  return img;
}

}  // namespace hydrolux::scene
