#include "hydrolux/drop/undistort.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>

#include "hydrolux/core/error.hpp"
#include "hydrolux/core/math.hpp"
#include "hydrolux/optics/fresnel.hpp"

namespace hydrolux::drop {

namespace {
constexpr const char* kContext = "undistorting a drop's image (Garg & Nayar Figure 9)";

void check_mu(double mu) { require_in_range("mu", mu, 1.0 + 1e-9, 10.0, kContext); }

// Bilinear sample of channel c at continuous image position (px, py), pixel centres at
// half-integers; taps beyond the border repeat the edge pixel.
float bilinear(const Image& img, double px, double py, int c) {
  const double u = px - 0.5, v = py - 0.5;
  const double fu = std::floor(u), fv = std::floor(v);
  const double tu = u - fu, tv = v - fv;
  const auto clamp_x = [&](double x) { return std::clamp(int(x), 0, img.width - 1); };
  const auto clamp_y = [&](double y) { return std::clamp(int(y), 0, img.height - 1); };
  const int x0 = clamp_x(fu), x1 = clamp_x(fu + 1), y0 = clamp_y(fv), y1 = clamp_y(fv + 1);
  const double top = (1 - tu) * img.at(x0, y0, c) + tu * img.at(x1, y0, c);
  const double bottom = (1 - tu) * img.at(x0, y1, c) + tu * img.at(x1, y1, c);
  return float((1 - tv) * top + tv * bottom);
}
}  // namespace

double max_refraction_deflection(double mu) {
  check_mu(mu);
  // At the rim i = pi/2 and q is the critical angle asin(1/mu): theta_r = 2 (pi/2 - asin(1/mu)).
  return kPi<> - 2 * std::asin(1 / mu);
}

double incidence_for_deflection(double theta_r, double mu) {
  require_in_range("theta_r", theta_r, 0.0, max_refraction_deflection(mu), kContext);
  // eq. 8 inverted in closed form: with h = theta_r / 2 = i - q, Snell's law sin(i) = mu sin(q)
  // reads sin(q + h) = mu sin(q), i.e. cos(q) sin(h) = sin(q) (mu - cos(h)), so
  // tan(q) = sin(h) / (mu - cos(h)) (mu - cos h > 0 for mu > 1) and i = q + h. The root is unique:
  // theta_r(i) is monotonic (see undistort.hpp).
  const double h = theta_r / 2;
  const double q = std::atan2(std::sin(h), mu - std::cos(h));
  return std::min(q + h, kPi<> / 2);  // the rim may round a hair past pi/2
}

std::optional<DropImagePoint> drop_image_point(const Vec3& dir, double mu) {
  const double theta_max = max_refraction_deflection(mu);
  // Polar angle from +z by atan2, accurate near the axis where acos(z) loses digits.
  const double s = std::hypot(dir.x, dir.y);
  const double theta_r = std::atan2(s, dir.z);
  if (!(theta_r <= theta_max)) return std::nullopt;  // outside the field of view (or NaN)
  DropImagePoint p;
  p.incidence = incidence_for_deflection(theta_r, mu);
  const double rho = std::sin(p.incidence);
  // eq. 11: phi_r = phi_n + pi, so the surface point lies opposite d's azimuth. World +x is image
  // +x, world +y is image -y: the offset rho (cos phi_n, sin phi_n) in world axes becomes
  // rho (-cos phi_d, +sin phi_d) in image axes.
  if (s > 0) {
    p.x = -rho * dir.x / s;
    p.y = rho * dir.y / s;
  }
  p.transmission = sqr(1 - optics::fr_dielectric(std::cos(p.incidence), mu));  // eq. 12
  return p;
}

Vec3 UndistortView::direction(double px, double py) const {
  // Pinhole at the drop: focal length in pixels from the horizontal field of view.
  const double f = 0.5 * width / std::tan(deg_to_rad(fov_deg) / 2);
  const Vec3 c{(px - 0.5 * width) / f, (0.5 * height - py) / f, 1.0};  // camera frame, +y up
  // Pitch about the camera's x axis (forward tilts towards +y), then yaw about +y (forward turns
  // towards +x).
  const double cp = std::cos(deg_to_rad(pitch_deg)), sp = std::sin(deg_to_rad(pitch_deg));
  const double cy = std::cos(deg_to_rad(yaw_deg)), sy = std::sin(deg_to_rad(yaw_deg));
  const Vec3 p{c.x, c.y * cp + c.z * sp, -c.y * sp + c.z * cp};
  return glm::normalize(Vec3{p.x * cy + p.z * sy, p.y, -p.x * sy + p.z * cy});
}

void validate(const UndistortView& view) {
  require_in_range("yaw_deg", view.yaw_deg, -360.0, 360.0, kContext);
  require_in_range("pitch_deg", view.pitch_deg, -90.0, 90.0, kContext);
  // (0, 179]: a pinhole's field of view must stay below 180 degrees.
  if (!(view.fov_deg > 0 && view.fov_deg <= 179)) throw DomainError("fov_deg", view.fov_deg, 0, 179, kContext);
  require_in_range("width", view.width, 1, 16384, kContext);
  require_in_range("height", view.height, 1, 16384, kContext);
}

Image undistort(const Image& drop_image, double cx, double cy, double radius_px, double mu,
                const UndistortView& view, bool transmission_correction) {
  check_mu(mu);
  validate(view);
  if (!(radius_px > 0 && radius_px <= 1e6)) throw DomainError("radius_px", radius_px, 0, 1e6, kContext);
  if (!std::isfinite(cx)) throw DomainError("center_x_px", cx, -1e9, 1e9, kContext);
  if (!std::isfinite(cy)) throw DomainError("center_y_px", cy, -1e9, 1e9, kContext);
  require_in_range("image_width", drop_image.width, 1, 1 << 20, kContext);
  require_in_range("image_height", drop_image.height, 1, 1 << 20, kContext);
  require_in_range("image_channels", drop_image.channels, 1, 64, kContext);
  if (drop_image.pixels.size() != std::size_t(drop_image.width) * drop_image.height * drop_image.channels)
    throw Error("undistort: the drop image's pixel buffer does not match its dimensions");

  // Colour channels read from the drop image: RGB, or grey repeated.
  const std::array<int, 3> source =
      drop_image.channels >= 3 ? std::array<int, 3>{0, 1, 2} : std::array<int, 3>{0, 0, 0};
  Image out(view.width, view.height, 4);
  tbb::parallel_for(tbb::blocked_range<int>(0, view.height), [&](const tbb::blocked_range<int>& rows) {
    for (int y = rows.begin(); y != rows.end(); ++y) {
      for (int x = 0; x < view.width; ++x) {
        const auto p = drop_image_point(view.direction(x + 0.5, y + 0.5), mu);
        if (!p) continue;  // beyond the drop's field of view: transparent black
        const double px = cx + p->x * radius_px, py = cy + p->y * radius_px;
        if (!(px >= 0 && px <= drop_image.width && py >= 0 && py <= drop_image.height)) continue;
        // Near the rim (1 - k)^2 -> 0 and the division amplifies whatever else the drop shows
        // there (reflections); at the rim itself it is 0 and the pixel is left uncorrected.
        const double scale = transmission_correction && p->transmission > 0 ? 1 / p->transmission : 1.0;
        for (int c = 0; c < 3; ++c) out.at(x, y, c) = float(scale * bilinear(drop_image, px, py, source[std::size_t(c)]));
        out.at(x, y, 3) = 1.f;
      }
    }
  });
  return out;
}

double resolved_fraction(const Image& undistorted) {
  if (undistorted.channels < 4 || undistorted.width <= 0 || undistorted.height <= 0) return 0;
  std::size_t seen = 0;
  for (int y = 0; y < undistorted.height; ++y)
    for (int x = 0; x < undistorted.width; ++x) seen += undistorted.at(x, y, 3) > 0 ? 1 : 0;
  return double(seen) / (double(undistorted.width) * double(undistorted.height));
}

}  // namespace hydrolux::drop
