#include "hydrolux/drop/render.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <mutex>

#include "hydrolux/core/error.hpp"
#include "hydrolux/core/math.hpp"
#include "hydrolux/drop/model.hpp"
#include "hydrolux/drop/params.hpp"
#include "hydrolux/drop/trace.hpp"

namespace hydrolux::drop {

namespace {
constexpr const char* kContext = "the drop camera";

double pixel_m(const DropCamera& c) { return c.frame_m / c.width; }

// Deterministic per-pixel jitter: a hash of the pixel and sample index to [0, 1).
double hash01(std::uint64_t a, std::uint64_t b) {
  std::uint64_t h = a * 0x9E3779B97F4A7C15ull ^ (b + 0x632BE59BD9B4E019ull + (a << 6) + (a >> 2));
  h ^= h >> 33;
  h *= 0xFF51AFD7ED558CCDull;
  h ^= h >> 33;
  h *= 0xC4CEB9FE1A85EC53ull;
  h ^= h >> 33;
  return double(h >> 11) * 0x1.0p-53;
}

// Orthonormal basis around a unit vector.
void basis(const Vec3& w, Vec3& u, Vec3& v) {
  const Vec3 a = std::abs(w.x) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
  u = glm::normalize(glm::cross(a, w));
  v = glm::cross(w, u);
}
}  // namespace

void validate(const DropCamera& c) {
  require_in_range("radius_m", c.radius_m, 1e-6, 1.0, kContext);
  require_in_range("distance_m", c.distance_m, 1.01 * c.radius_m, 1e4, kContext);
  require_in_range("frame_m", c.frame_m, 1e-12, 1e3, kContext);
  require_in_range("width", c.width, 1, 16384, kContext);
  require_in_range("height", c.height, 1, 16384, kContext);
}

// The image plane is the plane z = distance_m through the drop's centre, with pixels frame_m /
// width wide on it; a pixel's ray runs from the pinhole through its point on that plane.
double defocus_blur_radius_rad(double focal_m, double f_number, double focus_distance_m) {
  require_in_range("focal_m", focal_m, 1e-6, 10.0, "a thin lens");
  require_in_range("f_number", f_number, 0.1, 1e3, "a thin lens");
  require_in_range("focus_distance_m", focus_distance_m, focal_m * (1 + 1e-9), 1e9, "a thin lens");
  // Image of the focus plane at v = f D / (D - f); a point at infinity focuses at f, so its blur
  // circle on the sensor has diameter A (v - f) / f = A f / (D - f), which subtends A f / ((D - f) v)
  // = A / D from the lens: radius A / (2 D).
  return 0.5 * (focal_m / f_number) / focus_distance_m;
}

Ray DropCamera::ray(double px, double py) const {
  const double s = pixel_m(*this);
  const Vec3 p{(px - 0.5 * width) * s, (0.5 * height - py) * s, distance_m};
  return {Vec3{0, 0, 0}, glm::normalize(p)};
}

std::array<double, 2> DropCamera::project(const Vec3& p) const {
  const double s = pixel_m(*this);
  const double k = distance_m / p.z;
  return {0.5 * width + p.x * k / s, 0.5 * height - p.y * k / s};
}

std::array<double, 2> DropCamera::drop_center_px() const { return {0.5 * width, 0.5 * height}; }

// The sphere's silhouette is the cone of half-angle asin(a / d) around the axis; on the image plane
// at distance d its radius is d tan(asin(a / d)) = a / sqrt(1 - (a / d)^2).
double DropCamera::drop_radius_px() const {
  const double r = radius_m / std::sqrt(1 - sqr(radius_m / distance_m));
  return r / pixel_m(*this);
}

Image render(const DropCamera& camera, const scene::Environment& env, const RenderOptions& options,
             const RayShader& shade) {
  validate(camera);
  static const Param& samples = drop_render_param("samples");  // the declared range (drop/params.hpp)
  require_in_range("samples_per_axis", options.samples_per_axis, samples.lo, samples.hi, "drop rendering");
  require_in_range("background_blur_rad", options.background_blur_rad, 0.0, kPi<> / 2, "drop rendering");
  const int n = options.samples_per_axis;
  // A blurred background is an average over the defocus disk; it gets at least 8 x 8 samples, on the
  // same stratified pattern in every pixel, so it is smooth rather than noisy.
  const int blur_n = options.background_blur_rad > 0 ? std::max(n, 8) : 1;
  Image img(camera.width, camera.height, 4);
  std::atomic<int> rows_done{0};
  std::mutex progress_mutex;
  int reported = 0;  // rows reported to options.progress, under progress_mutex

  const auto background = [&](const Ray& ray, std::uint64_t seed) -> scene::Rgb {
    Vec3 u, v;
    basis(ray.direction, u, v);
    scene::Rgb sum{0, 0, 0};
    const double rot = 2 * kPi<> * hash01(seed, 7);  // a per-pixel rotation of the pattern
    for (int j = 0; j < blur_n; ++j)
      for (int i = 0; i < blur_n; ++i) {
        // Uniform disk: radius sqrt(stratum) in area, angle by stratum.
        const double r = options.background_blur_rad * std::sqrt((j + 0.5) / blur_n);
        const double phi = rot + 2 * kPi<> * (i + 0.5 * (j % 2)) / blur_n;
        const Vec3 d = glm::normalize(ray.direction + std::tan(r) * (std::cos(phi) * u + std::sin(phi) * v));
        sum += env.radiance(d);
      }
    return sum / double(blur_n * blur_n);
  };

  tbb::parallel_for(tbb::blocked_range<int>(0, camera.height), [&](const tbb::blocked_range<int>& rows) {
    for (int y = rows.begin(); y < rows.end(); ++y) {
      for (int x = 0; x < camera.width; ++x) {
        const std::uint64_t pix = std::uint64_t(y) * std::uint64_t(camera.width) + std::uint64_t(x);
        scene::Rgb sum{0, 0, 0};
        int hits = 0, misses = 0;
        // Stratified, jittered supersamples: the drop's rim is anti-aliased by the hit fraction.
        for (int j = 0; j < n; ++j)
          for (int i = 0; i < n; ++i) {
            const int k = j * n + i;
            const double px = x + (i + hash01(pix, 2 * k)) / n, py = y + (j + hash01(pix, 2 * k + 1)) / n;
            const Ray ray = camera.ray(px, py);
            if (const auto l = shade(ray)) {
              sum += *l;
              ++hits;
            } else if (options.background && options.background_blur_rad <= 0) {
              sum += env.radiance(ray.direction);
            } else {
              ++misses;
            }
          }
        // The blurred background varies over many pixels: it is computed once per pixel, at its
        // centre, and weighted by the fraction of samples that missed the drop.
        if (options.background && misses > 0) sum += double(misses) * background(camera.ray(x + 0.5, y + 0.5), pix);
        const double inv = 1.0 / (n * n);
        for (int c = 0; c < 3; ++c) img.at(x, y, c) = float(sum[c] * inv);
        img.at(x, y, 3) = options.background ? 1.f : float(hits * inv);
      }
      const int done = ++rows_done;
      if (options.progress && (done % 16 == 0 || done == camera.height)) {
        // Rows finish out of order: report under the lock, and never less than already reported.
        std::lock_guard lock(progress_mutex);
        const int now = rows_done.load();
        if (now > reported) {
          reported = now;
          options.progress(double(now) / camera.height, "rendering");
        }
      }
    }
  });
  return img;
}

ZoneDifference compare_by_zone(const Image& image, const Image& reference, const DropCamera& camera) {
  const auto c = camera.drop_center_px();
  const double r = camera.drop_radius_px();
  double sq[2] = {}, sum[2] = {};
  int n[2] = {};
  for (int y = 0; y < camera.height; ++y)
    for (int x = 0; x < camera.width; ++x) {
      const double rho = std::hypot(x + 0.5 - c[0], y + 0.5 - c[1]) / r;
      if (rho > 1 - 1.5 / r) continue;
      const int zone = rho <= 0.9 ? 0 : 1;
      for (int ch = 0; ch < 3; ++ch) {
        sq[zone] += sqr(double(image.at(x, y, ch)) - reference.at(x, y, ch));
        sum[zone] += reference.at(x, y, ch);
        ++n[zone];
      }
    }
  const auto rel = [&](int z) { return n[z] > 0 ? std::sqrt(sq[z] / n[z]) / (sum[z] / n[z]) : 0.0; };
  return {rel(0), rel(1)};
}

Image render_model(const DropCamera& camera, const scene::Environment& env, const ChannelIndex& mu,
                   const RenderOptions& options) {
  validate(camera);
  for (double m : mu) require_in_range("mu", m, 1.0 + 1e-9, 10.0, "the Garg & Nayar drop model");
  const SphereSurface sphere({0, 0, camera.distance_m}, camera.radius_m);
  const bool dispersive = !(mu[0] == mu[1] && mu[1] == mu[2]);
  const RayShader shade = [&](const Ray& ray) -> std::optional<scene::Rgb> {
    const auto hit = sphere.intersect(ray, 0.0);
    if (!hit) return std::nullopt;
    // Rounding can leave a grazing hit's normal turned a hair away from the camera (a millimetre
    // drop kilometres away): make it perpendicular to the view instead.
    Vec3 normal = hit->normal;
    if (const double facing = glm::dot(normal, ray.direction); facing > 0)
      normal = glm::normalize(normal - facing * ray.direction);
    scene::Rgb out{0, 0, 0};
    // Eq. 19: L = R Le(r) + S Le(s) + sum_N P_N Le(p_N), each channel with its own index when the
    // drop is dispersive (the paths of the three channels then part: colour fringes).
    for (int c = 0; c < (dispersive ? 3 : 1); ++c) {
      const auto p = drop_rays(ray.direction, normal, mu[std::size_t(c)], options.n_internal);
      scene::Rgb l = p.R * env.radiance(p.refraction) + p.S * env.radiance(p.reflection);
      for (std::size_t k = 0; k < p.internal.size(); ++k) l += p.P[k] * env.radiance(p.internal[k]);
      if (!dispersive) return l;
      out[c] = l[c];
    }
    return out;
  };
  return render(camera, env, options, shade);
}

}  // namespace hydrolux::drop
