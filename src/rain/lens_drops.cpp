// Drops on the lens or windshield (lens_drops.hpp; docs/lens-drops.md).
//
// References: the cap geometry (R = a / sin theta_c, h = R (1 - cos theta_c)) is the spherical cap of
// a sessile drop small against the capillary length (de Gennes, Brochard-Wyart & Quere, "Capillarity
// and Wetting Phenomena", 2004, ch. 1); refraction is optics/snell.hpp and the transmittances
// Fresnel's (as optics/fresnel.hpp, in real arithmetic); the circle of confusion is the thin-lens formula (Potmesil & Chakravarty,
// "A lens and aperture camera model for synthetic image generation", SIGGRAPH 1981, eq. 1; Hecht,
// Optics, 5th ed., sec. 5.2); the compositing of a defocused occluder as a blurred coverage over the
// sharp background follows rain.hpp's "rainy = clear (1 - alpha) + layer" (Porter & Duff 1984).
#include "hydrolux/rain/lens_drops.hpp"

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include "hydrolux/core/error.hpp"
#include "hydrolux/core/random.hpp"
#include "hydrolux/optics/snell.hpp"
#include "hydrolux/rain/params.hpp"
#include "hydrolux/rain/rain.hpp"

namespace hydrolux::rain {

namespace {

using K = ParamKind;

constexpr double kPi = std::numbers::pi;
constexpr int kPlacementTries = 50;
// A trail's drops: footprint radius this fraction of the drop's (give or take 30 %), spaced about this
// many of their radii apart. A drop running down partly wetting glass leaves such a chain of
// droplets; these numbers are a visual choice, not a measurement (docs/lens-drops.md).
constexpr double kTrailRadius = 0.3, kTrailSpacing = 3.0;
constexpr std::size_t kMaxPlacedDrops = 1000000;

void validate(const LensDropSettings& s) {
  for (const auto& f : lens_drops_params()) {
    const double v = f.get(s);
    if (!std::isnan(v) || f.param.name != "coverage") f.param.check(v);
  }
  if (s.min_radius_mm > s.max_radius_mm)
    throw DomainError("max_radius_mm", s.max_radius_mm, s.min_radius_mm, 10, "at least {min_radius_mm}");
  if (s.f_number > 0 && s.focus_m * 1e3 <= s.focal_mm)
    throw DomainError("focus_m", s.focus_m, s.focal_mm * 1e-3, 1e4, "beyond the focal length");
  // The glass' circle of confusion at most the sensor's width: beyond it every drop would be spread
  // over more than the frame (a uniform veil), and the blur's work (rows x columns x its diameter)
  // and the glass region the drops are placed over (widened by the blur) would grow without bound.
  // c is inversely proportional to N, so the smallest f-number that keeps it is N c / sensor width.
  const double c = circle_of_confusion_mm(s.focal_mm, s.f_number, s.focus_m, s.glass_distance_m);
  if (c > s.sensor_width_mm)
    throw DomainError("f_number", s.f_number, s.f_number * c / s.sensor_width_mm, 64,
                      fmt::format("at least where the glass' circle of confusion, {:.3g} mm with {{focus_m}} = {:g} and "
                                  "{{glass_distance_m}} = {:g}, is no wider than the sensor ({:g} mm); or 0, a pinhole",
                                  c, s.focus_m, s.glass_distance_m, s.sensor_width_mm));
}

int light_channels(int channels) { return channels >= 3 ? 3 : 1; }

double focal_px_for(const LensDropSettings& s, int width) { return s.focal_mm / s.sensor_width_mm * width; }

double blur_diameter_px(const LensDropSettings& s, int width) {
  return circle_of_confusion_mm(s.focal_mm, s.f_number, s.focus_m, s.glass_distance_m) / s.sensor_width_mm * width;
}

// 2 * integral of sqrt(r^2 - y^2) from 0 to y, for |y| <= r.
double chord_integral(double y, double r) {
  const double yy = std::clamp(y, -r, r);
  return yy * std::sqrt(std::max(0.0, r * r - yy * yy)) + r * r * std::asin(yy / r);
}

// One channel `c` of `src` (channels `ch`) blurred by the disk into `dst` (one channel, or channel c
// of dst with dst_ch channels). Where `only` is given, output pixels with only[i] == 0 are set to 0.
void blur_channel(const Image& src, int c, double r, std::vector<float>& dst, const std::vector<float>* only) {
  const int W = src.width, H = src.height, ch = src.channels;
  const int rows = int(std::ceil(r + 0.5));
  // Each row offset's strip of the disk: its exact area, spread as a chord of half-width area / 2.
  std::vector<double> half(2 * rows + 1);
  double total = 0;
  int max_w = 0;
  for (int dy = -rows; dy <= rows; ++dy) {
    const double lo = std::max(-r, dy - 0.5), hi = std::min(r, dy + 0.5);
    const double area = hi > lo ? chord_integral(hi, r) - chord_integral(lo, r) : 0.0;
    half[dy + rows] = area / 2;
    total += area;
    max_w = std::max(max_w, int(std::ceil(area / 2)));
  }
  const int pad = max_w + 2;
  const int PW = W + 2 * pad;
  // Prefix sums of each row, its ends repeated: P[y][k] = sum of the padded row's first k values.
  std::vector<double> P(std::size_t(H) * (PW + 1));
  std::vector<char> zero_row(std::size_t(H), 1);  // rows of zeros add nothing: skipped
  tbb::parallel_for(0, H, [&](int y) {
    double* p = &P[std::size_t(y) * (PW + 1)];
    p[0] = 0;
    bool zero = true;
    for (int k = 0; k < PW; ++k) {
      const int x = std::clamp(k - pad, 0, W - 1);
      const float v = src.pixels[(std::size_t(y) * W + x) * ch + c];
      zero = zero && v == 0;
      p[k + 1] = p[k] + double(v);
    }
    zero_row[std::size_t(y)] = zero ? 1 : 0;
  });
  // Each row offset's chord [centre - w, centre + w] in padded coordinates, centre = x + 0.5 + pad:
  // its ends fall at x + k + f with k and f the same for every x, so the continuous cumulative of the
  // row, C(t) = P[floor t] + frac(t) v[floor t], is read at fixed offsets along the row.
  struct Chord {
    int dy, k_hi, k_lo;
    double f_hi, f_lo;
  };
  std::vector<Chord> chords;
  for (int dy = -rows; dy <= rows; ++dy) {
    const double w = half[dy + rows];
    if (w <= 0) continue;
    const double hi = 0.5 + pad + w, lo = 0.5 + pad - w;
    const int k_hi = int(std::floor(hi)), k_lo = int(std::floor(lo));
    chords.push_back({dy, k_hi, k_lo, hi - k_hi, lo - k_lo});
  }
  dst.assign(std::size_t(W) * H, 0.f);
  tbb::parallel_for(0, H, [&](int y) {
    std::vector<double> sum(std::size_t(W), 0.0);
    for (const Chord& ch_ : chords) {
      const int yy = std::clamp(y + ch_.dy, 0, H - 1);
      const double* p = &P[std::size_t(yy) * (PW + 1)];
      if (zero_row[std::size_t(yy)]) continue;
      const double* a = p + ch_.k_hi;
      const double* b = p + ch_.k_lo;
      const double fa = ch_.f_hi, fb = ch_.f_lo;
      for (int x = 0; x < W; ++x) sum[x] += (a[x] + fa * (a[x + 1] - a[x])) - (b[x] + fb * (b[x + 1] - b[x]));
    }
    for (int x = 0; x < W; ++x) {
      const std::size_t i = std::size_t(y) * W + x;
      if (only && (*only)[i] == 0) continue;
      dst[i] = float(sum[std::size_t(x)] / total);
    }
  });
}

// The s and p power transmittances of a dielectric interface from n_i into n_t at cos_i, where no
// total reflection occurs: T = 1 - r^2 with Fresnel's real amplitudes (the same numbers as
// optics::fresnel_dielectric, without its complex arithmetic: this runs for every sample). cos_t out.
struct Transmit {
  double s, p, cos_t;
};
Transmit transmit(double cos_i, double n_i, double n_t) {
  const double eta = n_i / n_t;
  const double cos_t = std::sqrt(std::max(0.0, 1 - eta * eta * (1 - cos_i * cos_i)));
  const double rs = (n_i * cos_i - n_t * cos_t) / (n_i * cos_i + n_t * cos_t);
  const double rp = (n_t * cos_i - n_i * cos_t) / (n_t * cos_i + n_i * cos_t);
  return {1 - rs * rs, 1 - rp * rp, cos_t};
}

// Bilinear sample of `img` at continuous pixel coordinates (pixel centres at k + 0.5), clamped.
void sample_bilinear(const Image& img, double fx, double fy, float* out) {
  const double x = std::clamp(fx - 0.5, 0.0, double(img.width - 1));
  const double y = std::clamp(fy - 0.5, 0.0, double(img.height - 1));
  const int x0 = std::min(int(x), img.width - 1), y0 = std::min(int(y), img.height - 1);
  const int x1 = std::min(x0 + 1, img.width - 1), y1 = std::min(y0 + 1, img.height - 1);
  const double tx = x - x0, ty = y - y0;
  for (int c = 0; c < img.channels; ++c) {
    const double a = img.at(x0, y0, c) * (1 - tx) + img.at(x1, y0, c) * tx;
    const double b = img.at(x0, y1, c) * (1 - tx) + img.at(x1, y1, c) * tx;
    out[c] = float(a * (1 - ty) + b * ty);
  }
}

}  // namespace

// The camera's focal length and sensor and the PNG level are hydrolux rain's (rain/params.cpp): the
// same quantities, declared there once and copied here (made on first use, after rain's tables).
std::span<const Field<LensDropSettings>> lens_drops_params() {
  static const Field<LensDropSettings> table[] = {
    {{"drops", "--drops", "drops", K::integer, "", 0, 100000, "Drops on the part of the glass the camera sees"},
     HYDROLUX_PARAM_MEMBER(drops)},
    {{"coverage", "--coverage", "drops", K::real, "", 0, 0.5,
      "Fraction of the glass in view that the footprints cover (instead of --drops)", "drops"},
     HYDROLUX_PARAM_OPTIONAL(coverage)},
    {{"min_radius_mm", "--min-radius-mm", "drops", K::real, "mm", 0.05, 10,
      "Smallest footprint (contact) radius, mm; radii are log-uniform"},
     HYDROLUX_PARAM_MEMBER(min_radius_mm)},
    {{"max_radius_mm", "--max-radius-mm", "drops", K::real, "mm", 0.05, 10, "Largest footprint (contact) radius, mm"},
     HYDROLUX_PARAM_MEMBER(max_radius_mm)},
    {{"trail_fraction", "--trail-fraction", "drops", K::real, "", 0, 1,
      "Fraction of drops that ran down the glass, each leaving a trail of small drops above it (0: none)"},
     HYDROLUX_PARAM_MEMBER(trail_fraction)},
    {{"trail_length_mm", "--trail-length-mm", "drops", K::real, "mm", 0, 500, "Length of those trails, mm"},
     HYDROLUX_PARAM_MEMBER(trail_length_mm)},
    {{"contact_angle_deg", "--contact-angle-deg", "drops", K::real, "deg", 5, 90,
      "Contact angle of the caps, degrees (smaller on clean glass, larger on a water-repellent coating)"},
     HYDROLUX_PARAM_MEMBER(contact_angle_deg)},
    {{"glass_distance_m", "--glass-distance-m", "camera", K::real, "m", 0.005, 10,
      "Distance of the glass in front of the camera, m (a lens cover ~0.01, a windshield ~0.1-0.5)"},
     HYDROLUX_PARAM_MEMBER(glass_distance_m)},
    {rain::rain_param("focal_mm"), HYDROLUX_PARAM_MEMBER(focal_mm)},
    {rain::rain_param("sensor_width_mm"), HYDROLUX_PARAM_MEMBER(sensor_width_mm)},
    {{"f_number", "--f-number", "camera", K::real, "", 0, 64, "Aperture f-number; 0 = pinhole (drops sharp)"},
     HYDROLUX_PARAM_MEMBER(f_number)},
    {{"focus_m", "--focus-m", "camera", K::real, "m", 0.01, 1e4, "Focus distance, m (the scene is sharp)"},
     HYDROLUX_PARAM_MEMBER(focus_m)},
    {{"water_ior", "--water-ior", "optics", K::real, "", 1.2, 1.6, "Refractive index of the drops"},
     HYDROLUX_PARAM_MEMBER(water_ior)},
    {{"glass_ior", "--glass-ior", "optics", K::real, "", 1.3, 2, "Refractive index of the glass (its Fresnel losses)"},
     HYDROLUX_PARAM_MEMBER(glass_ior)},
    {{"samples", "--samples", "render", K::integer, "", 1, 8, "Sub-pixel samples per axis of the sharp drop layer"},
     HYDROLUX_PARAM_MEMBER(samples)},
    {{"seed", "--seed", "drops", K::integer, "", 0, double(kMaxSeed),
      "Random seed: the same seed gives the same drops, bytes for bytes"},
     HYDROLUX_PARAM_MEMBER(seed)},
  };
  return table;
}

std::span<const Field<LensDropsFileOptions>> lens_drops_file_params() {
  static const Field<LensDropsFileOptions> table[] = {
    {rain::rain_param("png_compression"), HYDROLUX_PARAM_MEMBER(png_compression)},
  };
  return table;
}


double LensCap::sphere_radius() const { return radius / std::sin(contact_angle); }
double LensCap::height() const { return sphere_radius() * (1 - std::cos(contact_angle)); }

CapRay trace_cap(const LensCap& cap, double glass_z, const Vec3& dir, double water_ior, double glass_ior) {
  CapRay out;
  if (!(dir.z > 0)) return out;
  const Vec3 P = dir * (glass_z / dir.z);
  const double ex = P.x - cap.x, ey = P.y - cap.y;
  if (ex * ex + ey * ey >= cap.radius * cap.radius) return out;
  const Vec3 u = glm::normalize(dir);
  out.through = true;
  out.entry = P;
  // The two parallel faces of the glass: air -> glass -> water, one plane of incidence.
  const Transmit f1 = transmit(u.z, 1.0, glass_ior);
  const Transmit f2 = transmit(f1.cos_t, glass_ior, water_ior);
  double Is = 0.5 * f1.s * f2.s, Ip = 0.5 * f1.p * f2.p;
  // The direction in the water (Snell's invariant across parallel faces: only air and water matter).
  const auto into = optics::refract(-u, Vec3(0, 0, -1), water_ior);
  const Vec3 w = into->wt;  // no total reflection entering a denser medium
  // The far intersection with the cap's sphere (the ray starts inside it): c < 0, no cancellation.
  const double R = cap.sphere_radius();
  const Vec3 C(cap.x, cap.y, glass_z - R * std::cos(cap.contact_angle));
  const Vec3 oc = P - C;
  const double b = glm::dot(oc, w);
  const double cc = (glm::length(oc) - R) * (glm::length(oc) + R);
  const double s = -b + std::sqrt(std::max(0.0, b * b - cc));
  const Vec3 Q = P + s * w;
  const Vec3 N = glm::normalize(Q - C);
  out.exit = Q;
  // Turn the s/p intensities into the plane of incidence at the sphere (the light after the plane
  // carries no s-p correlation, so intensities rotate as cos^2 and sin^2 of the frames' angle).
  const Vec3 s1 = glm::cross(u, Vec3(0, 0, 1)), s2 = glm::cross(w, N);
  const double l1 = glm::length(s1), l2 = glm::length(s2);
  if (l1 > 1e-12 && l2 > 1e-12) {
    const double c = glm::dot(s1, s2) / (l1 * l2), c2 = c * c;
    const double rs = Is * c2 + Ip * (1 - c2), rp = Is * (1 - c2) + Ip * c2;
    Is = rs;
    Ip = rp;
  }
  const double cos_i = std::clamp(glm::dot(N, w), 0.0, 1.0);
  const auto exit = optics::refract(-w, N, water_ior);
  if (!exit || water_ior * water_ior * (1 - cos_i * cos_i) >= 1) {
    out.tir = true;
    out.direction = optics::reflect(-w, N);
    return out;
  }
  const Transmit f3 = transmit(cos_i, water_ior, 1.0);
  out.direction = glm::normalize(exit->wt);
  out.transmittance = Is * f3.s + Ip * f3.p;
  return out;
}

double circle_of_confusion_mm(double focal_mm, double f_number, double focus_m, double distance_m) {
  if (f_number <= 0) return 0;
  const double f = focal_mm * 1e-3, s = focus_m, d = distance_m;
  const double aperture = f / f_number;
  return 1e3 * aperture * f / (s - f) * std::abs(s - d) / d;
}

Image disk_blur(const Image& image, double radius_px) {
  if (!(radius_px >= 0.5) || image.width == 0 || image.height == 0) return image;
  Image out(image.width, image.height, image.channels);
  out.channel_names = image.channel_names;
  std::vector<float> plane;
  for (int c = 0; c < image.channels; ++c) {
    blur_channel(image, c, radius_px, plane, nullptr);
    for (std::size_t i = 0; i < plane.size(); ++i) out.pixels[i * image.channels + c] = plane[i];
  }
  return out;
}

std::vector<LensCap> place_lens_drops(const LensDropSettings& s, int width, int height) {
  validate(s);
  if (width < 1 || height < 1) throw Error("place_lens_drops: an empty frame");
  const double d = s.glass_distance_m, fpx = focal_px_for(s, width);
  const double a0 = s.min_radius_mm * 1e-3, a1 = s.max_radius_mm * 1e-3;
  const double blur_m = blur_diameter_px(s, width) / 2 * d / fpx;
  const double X = width / 2.0 * d / fpx, Y = height / 2.0 * d / fpx;
  const double margin = a1 + blur_m;
  const double view_area = 4 * X * Y, region_area = 4 * (X + margin) * (Y + margin);
  const double mean_a2 = a1 > a0 ? (a1 * a1 - a0 * a0) / (2 * std::log(a1 / a0)) : a0 * a0;
  const double in_view = s.coverage ? *s.coverage * view_area / (kPi * mean_a2) : double(s.drops);
  const double wanted = std::round(in_view * region_area / view_area);
  if (wanted > double(kMaxPlacedDrops))
    throw DomainError(s.coverage ? "coverage" : "drops", s.coverage ? *s.coverage : double(s.drops), 0,
                      s.coverage ? *s.coverage * kMaxPlacedDrops / wanted : in_view * kMaxPlacedDrops / wanted,
                      "at most a million footprints on the glass in view and its margin; raise {min_radius_mm}");
  const auto n = std::size_t(wanted);
  const double contact = s.contact_angle_deg * kPi / 180;
  Rng rng(s.seed);
  // A grid of cells at least 2 a1 wide: a footprint can only overlap those of its own and neighbouring
  // cells. Cells are widened to about one drop each where the region is large against the drops (a
  // wide blur margin), so that the grid's memory follows the drops' count, not the region's area:
  // which cells hold a drop changes, which drops overlap does not.
  const double cell = std::max(2 * a1, std::sqrt(region_area / double(std::max<std::size_t>(n, 1))));
  const int gx = std::max(1, int(std::ceil(2 * (X + margin) / cell))), gy = std::max(1, int(std::ceil(2 * (Y + margin) / cell)));
  std::vector<std::vector<std::uint32_t>> grid(std::size_t(gx) * gy);
  std::vector<LensCap> caps;
  caps.reserve(n);
  // A footprint at (x, y) of radius r, kept unless it overlaps one already there or lies beyond the
  // region.
  const auto place = [&](double x, double y, double r) {
    if (std::abs(x) > X + margin || std::abs(y) > Y + margin) return false;
    const int cx = std::clamp(int((x + X + margin) / cell), 0, gx - 1), cy = std::clamp(int((y + Y + margin) / cell), 0, gy - 1);
    for (int j = std::max(0, cy - 1); j <= std::min(gy - 1, cy + 1); ++j)
      for (int i = std::max(0, cx - 1); i <= std::min(gx - 1, cx + 1); ++i)
        for (const auto o : grid[std::size_t(j) * gx + i]) {
          const LensCap& c = caps[o];
          const double dx = c.x - x, dy = c.y - y, rr = c.radius + r;
          if (dx * dx + dy * dy < rr * rr) return false;
        }
    grid[std::size_t(cy) * gx + cx].push_back(std::uint32_t(caps.size()));
    caps.push_back({x, y, r, contact});
    return true;
  };
  const double trail_length = s.trail_length_mm * 1e-3;
  for (std::size_t k = 0; k < n; ++k) {
    const double a = a1 > a0 ? a0 * std::exp(rng.uniform() * std::log(a1 / a0)) : a0;
    for (int t = 0; t < kPlacementTries; ++t) {
      const double x = -(X + margin) + rng.uniform() * 2 * (X + margin);
      const double y = -(Y + margin) + rng.uniform() * 2 * (Y + margin);
      if (!place(x, y, a)) continue;
      // A drop that ran down the glass: the small drops it left behind it, above it (up the glass is
      // -y). The random numbers are drawn only with trails, so without them the drops stay the same.
      if (s.trail_fraction > 0 && rng.uniform() < s.trail_fraction) {
        const double r = std::max(kTrailRadius * a, 0.5 * a0), step = kTrailSpacing * r;
        double ty = y - a - step;
        for (; ty > y - a - trail_length; ty -= step * (0.8 + 0.4 * rng.uniform()))
          (void)place(x + (rng.uniform() - 0.5) * r, ty, r * (0.7 + 0.6 * rng.uniform()));
      }
      break;
    }
  }
  return caps;
}

LensDropsResult render_lens_drops(const Image& clean, const LensDropSettings& s, const ProgressFn& progress) {
  const auto caps = place_lens_drops(s, clean.width, clean.height);
  return render_lens_drops(clean, s, caps, progress);
}

LensDropsResult render_lens_drops(const Image& clean, const LensDropSettings& s, std::span<const LensCap> caps,
                                  const ProgressFn& progress) {
  validate(s);
  const int W = clean.width, H = clean.height, C = clean.channels;
  if (W < 1 || H < 1 || C < 1) throw Error("render_lens_drops: an empty image");
  // The light: the first three channels (one of a grey image, or of grey and alpha); any others
  // (alpha, depth, masks) are not light and pass through unchanged, as rain and fog leave them.
  const int L = light_channels(C);
  LensDropsResult out;
  for (std::size_t i = 0; i < clean.pixels.size(); ++i) {
    if (!std::isfinite(clean.pixels[i])) {
      const std::size_t p = i / std::size_t(C);
      throw Error("pixel (" + std::to_string(p % std::size_t(W)) + ", " + std::to_string(p / std::size_t(W)) +
                  ") is not finite; give an image of finite values");
    }
    if (clean.pixels[i] < 0 && int(i % std::size_t(C)) < L) ++out.negative_values_clamped;
  }
  const double d = s.glass_distance_m, fpx = focal_px_for(s, W);
  const double cx = W / 2.0, cy = H / 2.0;
  out.focal_px = fpx;
  out.blur_diameter_px = blur_diameter_px(s, W);
  out.drops = caps.size();
  // The sharp layer: premultiplied light through the drops, and their coverage.
  Image layer(W, H, L), cover(W, H, 1);
  const int S = s.samples;
  const double inv = 1.0 / (double(S) * S);
  // Each drop's pixel box; rows in parallel, the drops of a row in their order (the same sums
  // whatever the threads).
  struct Box {
    int x0, x1, y0, y1;
  };
  std::vector<Box> boxes;
  boxes.reserve(caps.size());
  for (const LensCap& cap : caps) {
    const double px = cx + fpx * cap.x / d, py = cy + fpx * cap.y / d, pr = fpx * cap.radius / d;
    const auto lo = [](double v, int hi) { return int(std::clamp(std::floor(v) - 1, -1.0, double(hi))); };
    const auto up = [](double v, int hi) { return int(std::clamp(std::ceil(v) + 1, -1.0, double(hi))); };
    boxes.push_back({std::max(0, lo(px - pr, W)), std::min(W - 1, up(px + pr, W)), std::max(0, lo(py - pr, H)),
                     std::min(H - 1, up(py + pr, H))});
  }
  std::atomic<int> rows_done{0};
  tbb::parallel_for(0, H, [&](int y) {
    // Once a row: the caller may stop the work here (its callback throws; the loop unwinds).
    if (progress) progress(0.9 * rows_done.fetch_add(1, std::memory_order_relaxed) / H, "drops");
    std::vector<float> value(std::size_t(C), 0.f);
    for (std::size_t n = 0; n < caps.size(); ++n) {
      const Box& b = boxes[n];
      if (y < b.y0 || y > b.y1) continue;
      const LensCap& cap = caps[n];
      for (int x = b.x0; x <= b.x1; ++x)
        for (int j = 0; j < S; ++j)
          for (int i = 0; i < S; ++i) {
            const double sx = x + (i + 0.5) / S, sy = y + (j + 0.5) / S;
            const CapRay r = trace_cap(cap, d, Vec3((sx - cx) / fpx, (sy - cy) / fpx, 1), s.water_ior, s.glass_ior);
            if (!r.through) continue;
            cover.at(x, y, 0) += float(inv);
            if (r.tir) continue;
            // The scene at infinity, through the same pinhole; behind the camera's plane: the borders.
            const Vec3& v = r.direction;
            const double vz = std::max(v.z, 1e-9);
            const double fx = std::clamp(cx + fpx * v.x / vz, -1.0, W + 1.0);
            const double fy = std::clamp(cy + fpx * v.y / vz, -1.0, H + 1.0);
            sample_bilinear(clean, fx, fy, value.data());
            for (int c = 0; c < L; ++c)
              layer.at(x, y, c) += float(inv * r.transmittance * std::max(0.f, value[std::size_t(c)]));
          }
    }
  });
  double sharp = 0;
  for (float v : cover.pixels) sharp += v;
  out.coverage = sharp / (double(W) * H);
  // Defocus: the layer and its coverage blurred by the circle of confusion, then composited.
  const double r = out.blur_diameter_px / 2;
  out.mask = Image(W, H, 1);
  Image blurred(W, H, L);
  if (r >= 0.5) {
    std::vector<float> plane;
    blur_channel(cover, 0, r, plane, nullptr);
    for (std::size_t i = 0; i < plane.size(); ++i) out.mask.pixels[i] = std::clamp(plane[i], 0.f, 1.f);
    for (int c = 0; c < L; ++c) {
      if (progress) progress(0.9 + 0.1 * c / L, "blur");
      blur_channel(layer, c, r, plane, &out.mask.pixels);
      for (std::size_t i = 0; i < plane.size(); ++i) blurred.pixels[i * L + c] = std::max(0.f, plane[i]);
    }
  } else {
    out.mask.pixels = cover.pixels;
    for (auto& v : out.mask.pixels) v = std::clamp(v, 0.f, 1.f);
    blurred = layer;
  }
  out.image = Image(W, H, C);
  out.image.channel_names = clean.channel_names;
  for (std::size_t p = 0; p < std::size_t(W) * H; ++p) {
    const float a = out.mask.pixels[p];
    for (int c = 0; c < C; ++c) {
      const std::size_t i = p * C + c;
      if (c >= L) {
        out.image.pixels[i] = clean.pixels[i];
        continue;
      }
      // Negative light reads as 0 (counted in negative_values_clamped), as rain and fog read it.
      const float v = std::max(0.f, clean.pixels[i]);
      out.image.pixels[i] = a > 0 ? v * (1 - a) + blurred.pixels[p * L + c] : v;
    }
  }
  return out;
}

}  // namespace hydrolux::rain
