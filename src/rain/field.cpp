// The rain field: camera, radius classes, drops from a counter-based hash (rain.hpp).
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "field_detail.hpp"
#include "hydrolux/core/error.hpp"
#include "hydrolux/core/math.hpp"
#include "hydrolux/drop/physics.hpp"
#include "hydrolux/rain/params.hpp"
#include "hydrolux/rain/rain.hpp"
#include "hydrolux/scatter/size_distribution.hpp"

namespace hydrolux::rain {

// ---- camera ---------------------------------------------------------------------------------

std::array<double, 2> RainCamera::project(const Vec3& p) const {
  const double f = focal_px();
  return {0.5 * width + f * p.x / p.z, 0.5 * height - f * p.y / p.z};
}

Vec3 RainCamera::ray(double px, double py) const {
  const double f = focal_px();
  return glm::normalize(Vec3(px - 0.5 * width, 0.5 * height - py, f));
}

Vec3 RainCamera::to_camera(const Vec3& w) const {
  const double t = deg_to_rad(pitch_deg), c = std::cos(t), s = std::sin(t);
  return {w.x, w.y * c - w.z * s, w.y * s + w.z * c};
}

Vec3 RainCamera::to_world(const Vec3& v) const {
  const double t = deg_to_rad(pitch_deg), c = std::cos(t), s = std::sin(t);
  return {v.x, v.y * c + v.z * s, -v.y * s + v.z * c};
}

double RainCamera::defocus_radius_px(double z_m) const {
  if (f_number <= 0) return 0;
  // Thin lens: the blur disk on the sensor has diameter A f |z - D| / (z (D - f)), A = f / N.
  const double f = focal_mm * 1e-3, aperture = f / f_number;
  const double diameter_m = aperture * f * std::abs(z_m - focus_m) / (z_m * (focus_m - f));
  return 0.5 * diameter_m / pixel_pitch_m();
}

double focal_mm_from_fov(double fov_deg, double sensor_width_mm) {
  const Param& focal = rain_param("focal_mm");
  const double kMinFocalMm = focal.lo, kMaxFocalMm = focal.hi;
  const Param& fov = rain_param("fov_deg");
  // The field of view is refused in its own terms where the focal length it gives would be: the
  // fields of view of focal lengths 1-2000 mm on this sensor, within [1, 170] degrees.
  const auto fov_of = [&](double focal_mm) { return 2 * rad_to_deg(std::atan(0.5 * sensor_width_mm / focal_mm)); };
  require_in_range("fov_deg", fov_deg, std::max(fov.lo, fov_of(kMaxFocalMm)), std::min(fov.hi, fov_of(kMinFocalMm)),
                   fmt::format("a {:g} mm wide sensor (focal lengths {:g}-{:g} mm)", sensor_width_mm, kMinFocalMm,
                               kMaxFocalMm));
  // At the ends of that range the focal length is the bound itself, whatever the rounding.
  return std::clamp(0.5 * sensor_width_mm / std::tan(deg_to_rad(0.5 * fov_deg)), kMinFocalMm, kMaxFocalMm);
}

// The ranges are the declared parameters' (params.cpp); the checks here add those that follow from
// other values (far beyond near, exposure within a frame, focus beyond the focal length).
void validate(const RainCamera& c) {
  require_in_range("width", c.width, kMinFrameSide, kMaxFrameSide);
  require_in_range("height", c.height, kMinFrameSide, kMaxFrameSide);
  rain_param("focal_mm").check(c.focal_mm);
  rain_param("sensor_width_mm").check(c.sensor_width_mm);
  if (c.f_number != 0) require_in_range("f_number", c.f_number, kMinFNumber, rain_param("f_number").hi, "0 for a pinhole");
  if (c.f_number != 0) require_in_range("focus_m", c.focus_m, c.focal_mm * 1e-3 * 1.01, rain_param("focus_m").hi);
  rain_param("fps").check(c.fps);
  require_in_range("exposure_s", c.exposure_s, rain_param("exposure_s").lo, 1.0 / c.fps,
                   "at most one frame interval, 1 / {fps}");
  rain_param("camera_height_m").check(c.height_m);
  rain_param("pitch_deg").check(c.pitch_deg);
}

void validate(const RainSettings& s) {
  // The declared ranges of the settings' own rows (params.cpp; the camera's and the fog's are checked
  // with them), then those that follow from other values.
  RainOptions declared;
  declared.settings = s;
  check_fields(rain_params(), declared);
  require_in_range("far_m", s.far_m, s.near_m * 1.001, rain_param("far_m").hi, "beyond {near_m}");
  require_in_range("max_radius_mm", s.max_radius_mm, s.min_radius_mm * 1.001, rain_param("max_radius_mm").hi,
                   "beyond {min_radius_mm}");
  require_in_range("refractive_index", s.refractive_index, 1.01, 3);
}

// ---- Marshall-Palmer ------------------------------------------------------------------------

namespace {
// Marshall & Palmer (1948): N(D) = 8000 exp(-4.1 h^-0.21 D) m^-3 mm^-1 over diameter D in mm; per
// metre of radius a = D / 2: N0 = 1.6e7 m^-4 and Lambda = 8200 h^-0.21 m^-1 (the library's law).
constexpr double kMpN0PerM4 = scatter::kMarshallPalmerN0PerRadius;
double mp_lambda(double rain_rate_mmh) { return scatter::SizeDistribution::marshall_palmer(rain_rate_mmh, kMpN0PerM4).lambda(); }
// Integral of a^k N0 exp(-L a) from a to infinity, k = 0 or 2.
double mp_tail(int k, double a, double lambda) {
  const double e = kMpN0PerM4 * std::exp(-lambda * a) / lambda;
  if (k == 0) return e;
  return e * (a * a + 2 * a / lambda + 2 / (lambda * lambda));
}
}  // namespace

double marshall_palmer_per_m4(double radius_m, double rain_rate_mmh) {
  if (rain_rate_mmh <= 0) return 0;
  return kMpN0PerM4 * std::exp(-mp_lambda(rain_rate_mmh) * radius_m);
}

// ---- peak alpha -----------------------------------------------------------------------------

double detail::peak_alpha(double r, double R, double L) {
  if (R < 1) {
    // The tent footprint (render.cpp): pi r^2 tent(0) G(L / 2), G the box of length L smoothed by
    // the tent, at most 1 / L (L >= 2) and 1 - L / 4 below.
    const double g = L >= 2 ? 1 / L : 1 - L / 4;
    return kPi<double> * r * r * g;
  }
  const double k = (r / R) * (r / R);
  return L <= 2 * R ? k : k * 2 * R / L;
}

// ---- the field ------------------------------------------------------------------------------

namespace {
// A field of `drops` drops, over the limit: the settings that bound it named for each door to spell.
TooManyDrops too_many_drops(double drops, double min_alpha) {
  return TooManyDrops(drops, fmt::format("{{min_alpha}} {:g}: the rain field would hold {:.3g} drops, more than the "
                                         "limit of {:.3g}; raise {{min_alpha}}, {{near_m}} or {{min_radius_mm}}, or "
                                         "lower {{far_m}} or {{rain_rate_mmh}}",
                                         min_alpha, drops, double(RainField::kMaxDrops)));
}
}  // namespace

RainField::RainField(const RainSettings& settings, const RainCamera& camera, bool ground_plane)
    : s_(settings), c_(camera), ground_plane_(ground_plane) {
  validate(s_);
  validate(c_);
  const double wind_dir = deg_to_rad(s_.wind_dir_deg);
  wind_ = Vec3(std::sin(wind_dir), 0, std::cos(wind_dir)) * s_.wind_mps;

  // Terminal velocity over radius, tabulated from Gunn & Kinzer (linear in radius, 2 um steps).
  const auto gk = drop::gunn_kinzer_radius_range_m();
  lut_lo_ = gk[0];
  const int n = 1 + int(std::ceil((gk[1] - gk[0]) / 2e-6));
  lut_step_ = (gk[1] - gk[0]) / (n - 1);
  velocity_lut_.resize(std::size_t(n));
  for (int i = 0; i < n; ++i)
    velocity_lut_[std::size_t(i)] = float(drop::terminal_velocity_gunn_kinzer_mps(std::min(gk[1], gk[0] + i * lut_step_)));

  if (s_.rain_rate_mmh <= 0) return;
  const double lambda = mp_lambda(s_.rain_rate_mmh);
  const double a_min = s_.min_radius_mm * 1e-3, a_max = s_.max_radius_mm * 1e-3;
  beta_small_ = kPi<double> * (mp_tail(2, 0, lambda) - mp_tail(2, a_min, lambda));
  beta_total_ = kPi<double> * (mp_tail(2, 0, lambda) - mp_tail(2, a_max, lambda));

  const double f = c_.focal_px();
  const double tan_x = 0.5 * c_.width / f, tan_y = 0.5 * c_.height / f;
  const int k = s_.radius_classes;
  classes_.resize(std::size_t(k));
  for (int i = 0; i < k; ++i) {
    auto& rc = classes_[std::size_t(i)];
    rc.radius_lo_m = a_min * std::pow(a_max / a_min, double(i) / k);
    rc.radius_hi_m = a_min * std::pow(a_max / a_min, double(i + 1) / k);
    rc.number_per_m3 = mp_tail(0, rc.radius_lo_m, lambda) - mp_tail(0, rc.radius_hi_m, lambda);
    rc.beta_per_m = kPi<double> * (mp_tail(2, rc.radius_lo_m, lambda) - mp_tail(2, rc.radius_hi_m, lambda));
    rc.cdf_span = std::expm1(-lambda * (rc.radius_hi_m - rc.radius_lo_m));
    rc.inv_lambda = 1 / lambda;

    // How far the class's largest drop stays resolved: its streak's peak alpha (seen at the image
    // centre, moving across the view at its full speed) against min_alpha, scanned from far_m in.
    const double a = rc.radius_hi_m;
    const Vec3 vel = velocity_of(a);
    const double speed = std::hypot(vel.x, vel.y);
    rc.resolved_to_m = s_.near_m;
    const int steps = 400;
    for (int j = 0; j <= steps; ++j) {
      const double z = s_.far_m * std::pow(s_.near_m / s_.far_m, double(j) / steps);
      const double r = f * a / z, b = c_.defocus_radius_px(z);
      const double L = f * speed * c_.exposure_s / z;
      if (detail::peak_alpha(r, std::sqrt(r * r + b * b), L) >= s_.min_alpha) {
        rc.resolved_to_m = z;
        break;
      }
    }
    if (rc.resolved_to_m <= s_.near_m) continue;  // never drawn: all unresolved

    // The box: the frustum between near_m and resolved_to_m widened by the largest footprint (near,
    // defocused) so a drop just outside the view whose disk reaches into it is kept, in the world
    // frame, then stretched against the velocity by one exposure so that every drop whose streak
    // crosses the frustum during an exposure starts inside it.
    const double z0 = s_.near_m, z1 = rc.resolved_to_m;
    const double r_near = f * a / z0, b_near = c_.defocus_radius_px(z0);
    const double margin = (std::sqrt(r_near * r_near + b_near * b_near) + 2) / f;
    Vec3 lo(std::numeric_limits<double>::max()), hi(std::numeric_limits<double>::lowest());
    for (const double z : {z0, z1})
      for (const double sx : {-1.0, 1.0})
        for (const double sy : {-1.0, 1.0}) {
          const Vec3 w = c_.to_world(Vec3(sx * (tan_x + margin) * z, sy * (tan_y + margin) * z, z));
          lo = glm::min(lo, w);
          hi = glm::max(hi, w);
        }
    const Vec3 travel = vel * c_.exposure_s;
    lo = lo - glm::max(travel, Vec3(0));
    hi = hi - glm::min(travel, Vec3(0));
    if (ground_plane_) lo.y = std::max(lo.y, -c_.height_m);
    if (hi.y <= lo.y) {  // the view holds no air above the ground
      rc.resolved_to_m = s_.near_m;
      continue;
    }
    rc.box_lo = lo;
    rc.box_size = hi - lo;
    rc.box_inv_size = 1.0 / rc.box_size;
    const double mean = rc.number_per_m3 * rc.box_size.x * rc.box_size.y * rc.box_size.z;
    if (mean > double(kMaxDrops)) throw too_many_drops(mean, s_.min_alpha);
    // An unbiased whole count from the hash: floor(mean + u).
    rc.count = std::uint64_t(std::floor(mean + detail::unit(detail::hash(s_.seed, 0xC1A55ULL + std::uint64_t(i)))));
  }
  for (auto& rc : classes_) {
    rc.first_index = total_;
    total_ += rc.count;
  }
  if (double(total_) > double(kMaxDrops)) throw too_many_drops(double(total_), s_.min_alpha);
}

std::size_t RainField::class_of(std::uint64_t index) const {
  const auto it = std::upper_bound(classes_.begin(), classes_.end(), index,
                                   [](std::uint64_t i, const RadiusClass& c) { return i < c.first_index; });
  return std::size_t(it - classes_.begin()) - 1;
}

RainField::Drop RainField::drop(std::uint64_t index) const { return drop(index, class_of(index)); }

RainField::Drop RainField::drop(std::uint64_t index, std::size_t cls) const {
  return drop_with_key(detail::hash(s_.seed, index), cls);
}

RainField::Drop RainField::drop_with_key(std::uint64_t key, std::size_t cls) const {
  Drop d;
  d.cls = cls;
  const auto& rc = classes_[d.cls];
  const double u0 = detail::variate(key, 0), u1 = detail::variate(key, 1), u2 = detail::variate(key, 2);
  const double u3 = detail::variate(key, 3), u4 = detail::variate(key, 4);
  d.start = rc.box_lo + Vec3(u0, u1, u2) * rc.box_size;
  // The radius from N(a) within the class: an exponential truncated to [lo, hi], inverted.
  d.radius = rc.radius_lo_m - std::log1p(u3 * rc.cdf_span) * rc.inv_lambda;
  d.radius = std::clamp(d.radius, rc.radius_lo_m, rc.radius_hi_m);
  d.phase = u4;
  return d;
}

double RainField::radius_m(std::uint64_t index) const { return drop(index).radius; }

Vec3 RainField::velocity(std::uint64_t index) const { return velocity_of(drop(index).radius); }

Vec3 RainField::position(std::uint64_t index, double t_s) const {
  const Drop d = drop(index);
  const auto& rc = classes_[d.cls];
  return detail::wrap(d.start + velocity_of(d.radius) * t_s, rc.box_lo, rc.box_size);
}

double RainField::unresolved_optical_depth(double depth_m, double cos_off_axis) const {
  if (!s_.unresolved || s_.rain_rate_mmh <= 0) return 0;
  // Along the ray: the path between depths z1 < z2 is (z2 - z1) / cos.
  const double z = std::isfinite(depth_m) && depth_m > 0 ? depth_m : s_.extent_m * cos_off_axis;
  double tau = beta_small_ * std::max(0.0, z - s_.near_m);
  for (const auto& rc : classes_) tau += rc.beta_per_m * std::max(0.0, z - rc.resolved_to_m);
  return tau / cos_off_axis;
}

}  // namespace hydrolux::rain
