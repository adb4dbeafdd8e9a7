// Streaks of a frame, rasterised and composited over the frame (rain.hpp).
#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <bit>
#include <atomic>
#include <cmath>
#include <limits>
#include <numeric>
#include <tuple>
#include <utility>

#include "composite.hpp"
#include "field_detail.hpp"
#include "hydrolux/core/error.hpp"
#include "hydrolux/core/math.hpp"
#include "hydrolux/rain/fog.hpp"
#include "hydrolux/rain/rain.hpp"
#include "hydrolux/scene/environment.hpp"

namespace hydrolux::rain {

namespace {

// Streaks are binned into bands of image rows; each band is rasterised by one task, in drop order,
// so the result does not depend on the number of threads.
constexpr int kBandRows = 16;
// Drops are turned into streaks in blocks of this many, in parallel.
constexpr std::uint64_t kBlockDrops = std::uint64_t(1) << 12;
// Rayleigh (1879): a drop's fundamental (n = 2) oscillation has angular frequency
// sqrt(8 sigma / (rho a^3)); water at 20 C: sigma = 0.0728 N/m, rho = 998 kg/m^3.
constexpr double kSurfaceTension = 0.0728, kWaterDensity = 998.0;
constexpr float kLuma[3] = {0.2126f, 0.7152f, 0.0722f};

using detail::clip_linear;
using detail::tent_cdf;

constexpr std::size_t kLanes = kStreakAccumLanes, kBlock = kStreakAccumFloats;

// Rows [r0, ...) of accumulators, `stride` pixels a row (a whole number of blocks; rain.hpp).
struct Accum {
  float* base;
  int r0;
  std::size_t stride;
  // Pixel (x, y)'s T; its W is kLanes floats on, its C[k] (2 + k) kLanes on.
  float* at(int y, int x) const {
    const std::size_t j = std::size_t(y - r0) * stride + std::size_t(x);
    return base + (j / kLanes) * kBlock + j % kLanes;
  }
};

// Accumulator rows padded to whole blocks.
std::size_t accum_stride(int width) { return (std::size_t(width) + kLanes - 1) / kLanes * kLanes; }

// `blocks` blocks cleared: T = 1, W = C = 0.
void clear_blocks(float* p, std::size_t blocks) {
  for (std::size_t b = 0; b < blocks; ++b, p += kBlock) {
    std::fill(p, p + kLanes, 1.f);
    std::fill(p + kLanes, p + kBlock, 0.f);
  }
}

// Rasterises the rows [row0, row1) of one streak into `acc`. Returns whether it touched a pixel.
// simd: thin streaks without oscillation (nearly all) through the SIMD raster (composite.cpp), whose
// lanes do this loop's operations in its order: the same floats.
bool raster(const Streak& st, int row0, int row1, int width, const float* depth, Accum& acc, bool simd = true) {
  const float dx = st.x1 - st.x0, dy = st.y1 - st.y0;
  float L = std::sqrt(dx * dx + dy * dy);
  float ux = 0, uy = 1;
  if (L > 1e-4f) {
    ux = dx / L;
    uy = dy / L;
  } else {
    L = 0;
  }
  const bool thin = st.R < 1;
  const float ext = thin ? 1.f : st.R + 0.5f;
  const float w = thin ? kPi<float> * st.r * st.r : (st.r / st.R) * (st.r / st.R);
  const float R2 = st.R * st.R;
  // Reciprocals once a streak, not once a row or a pixel.
  const float inv_ux = std::abs(ux) < 1e-7f ? 0.f : 1 / ux, inv_uy = std::abs(uy) < 1e-7f ? 0.f : 1 / uy;
  const float inv_L = L > 0 ? 1 / L : 0.f;
  const detail::ThinStreak ts{st.x0, st.y0, ux, uy, L, inv_L, inv_ux, inv_uy, w, st.z,
                              {st.rgb[0], st.rgb[1], st.rgb[2]}, row0, row1, width, depth, acc.base, acc.r0, acc.stride};
  if (simd && thin && !(st.osc_amp > 0)) return detail::thin_streak_rows(ts);
  bool touched = false;
  for (int y = row0; y < row1; ++y) {
    const float qy = float(y) + 0.5f;
    int ia, ib;
    if (thin) {  // the pixels the SIMD raster visits (composite.hpp)
      if (!detail::thin_row_range(ts, y, ia, ib)) continue;
    } else {  // pixel centres qx with |p| <= ext and s in [-ext, L + ext]
      float xa = -std::numeric_limits<float>::max(), xb = std::numeric_limits<float>::max();
      clip_linear(uy, inv_uy, -st.x0 * uy - (qy - st.y0) * ux, -ext, ext, xa, xb);
      clip_linear(ux, inv_ux, -st.x0 * ux + (qy - st.y0) * uy, -ext, L + ext, xa, xb);
      if (xb < xa) continue;
      ia = std::max(0, int(std::ceil(xa - 0.5f)));
      ib = std::min(width - 1, int(std::floor(xb - 0.5f)));
    }
    const std::size_t row = std::size_t(y) * std::size_t(width);
    // Thin streaks (nearly all of them) without a branch a pixel: a pixel the streak misses, or whose
    // scene is nearer than the drop, adds alpha 0, which leaves its accumulators exactly as they were.
    for (int x = ia; x <= ib; ++x) {
      const std::size_t i = row + std::size_t(x);
      const float qx = float(x) + 0.5f;
      const float s = (qx - st.x0) * ux + (qy - st.y0) * uy;
      const float p = (qx - st.x0) * uy - (qy - st.y0) * ux;
      float a;
      if (thin) {
        const float along = L > 1e-3f ? (tent_cdf(s) - tent_cdf(s - L)) * inv_L : std::max(0.f, 1 - std::abs(s));
        a = w * (1 - std::abs(p)) * along;  // <= 0 off the streak
      } else {
        if (L > 0) {
          const float p2 = p * p;
          if (p2 >= R2) continue;
          const float c = std::sqrt(R2 - p2);
          const float overlap = std::min(s + c, L) - std::max(s - c, 0.f);
          if (overlap <= 0) continue;
          a = w * overlap * inv_L;
        } else {
          // A drop at rest: its disk with a one-pixel soft edge, clamp(R + 1/2 - rho, 0, 1), whose
          // integral pi R^2 + pi / 12 is the disk's to 1 / (12 R^2), where a hard edge sampled at
          // pixel centres would be off by up to ~15% at R = 2.
          a = w * std::clamp(st.R + 0.5f - std::sqrt(s * s + p * p), 0.f, 1.f);
          if (a <= 0) continue;
        }
      }
      if (st.osc_amp > 0) {
        const float tau = L > 0 ? std::clamp(s / L, 0.f, 1.f) : 0.5f;
        const float m = 1 + st.osc_amp * std::sin(2 * kPi<float> * (st.osc_phase + st.osc_cycles * tau));
        a *= m * m;
      }
      const bool keep = a > 1e-7f && !(depth[i] < st.z);
      a = keep ? std::min(a, 1.f) : 0.f;
      float* q = acc.at(y, x);
      q[0] *= 1 - a;
      q[kLanes] += a;
      for (std::size_t k = 0; k < 3; ++k) q[(2 + k) * kLanes] += a * st.rgb[k];
      touched |= keep;
    }
  }
  return touched;
}

// The q-th and p-th quantiles (q < p) of v (reordered): the element of rank floor(q (n - 1)), by
// one selection of the higher rank and one among the elements below it.
std::pair<double, double> percentiles(std::vector<float>& v, double q, double p) {
  if (v.empty()) return {0, 0};
  const auto rank = [&](double f) { return std::size_t(std::clamp(f * double(v.size() - 1), 0.0, double(v.size() - 1))); };
  const std::size_t kq = rank(q), kp = rank(p);
  std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(kp), v.end());
  std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(kq), v.begin() + std::ptrdiff_t(kp));
  return {double(v[kq]), double(v[kp])};
}

// Refuses a non-finite value anywhere in the frame (NonFinitePixel, the first in row order) and
// counts the negative RGB values the composite reads as 0. Rows in parallel; the first bad row wins.
// The negative values among n floats, and whether all are finite: one flat loop the compiler
// vectorises (exponent bits for finiteness), compiled for AVX-512 and AVX2 too on x86-64.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
__attribute__((target_clones("avx512f", "avx2", "default")))
#endif
std::uint64_t count_rgb_values(const float* __restrict p, std::size_t n, bool& finite) {
  std::uint32_t negs = 0, infinite = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t bits = std::bit_cast<std::uint32_t>(p[i]);
    negs += p[i] < 0.f ? 1u : 0u;
    infinite |= (bits & 0x7f800000u) == 0x7f800000u ? 1u : 0u;
  }
  finite = infinite == 0;
  return negs;
}

std::uint64_t check_frame_values(const Image& frame) {
  const int W = frame.width, H = frame.height, ch = frame.channels;
  std::vector<std::uint64_t> negatives(std::size_t(H), 0);
  std::atomic<int> first_bad_row{H};
  tbb::parallel_for(0, H, [&](int y) {
    const float* row = frame.pixels.data() + std::size_t(y) * std::size_t(W) * std::size_t(ch);  // ch >= 3
    std::uint64_t neg = 0;
    bool finite = true;
    if (ch == 3) {
      neg = count_rgb_values(row, std::size_t(W) * 3, finite);
    } else {
      for (int x = 0; x < W; ++x, row += ch) {
        for (int k = 0; k < 3; ++k) neg += row[k] < 0.f ? 1 : 0;
        for (int k = 0; k < ch; ++k) finite &= std::isfinite(row[k]);
      }
    }
    negatives[std::size_t(y)] = neg;
    if (!finite) {
      int cur = first_bad_row.load();
      while (y < cur && !first_bad_row.compare_exchange_weak(cur, y)) {
      }
    }
  });
  if (const int y = first_bad_row.load(); y < H) {
    for (int x = 0; x < W; ++x)
      for (int k = 0; k < ch; ++k)
        if (const float v = frame.at(x, y, k); !std::isfinite(v)) throw NonFinitePixel(x, y, k, v);
  }
  return std::accumulate(negatives.begin(), negatives.end(), std::uint64_t(0));
}

}  // namespace

NonFinitePixel::NonFinitePixel(int x, int y, int channel, float value)
    : Error(fmt::format("pixel ({}, {}) channel {} is {}: rain needs finite linear values (negative ones read as 0)", x,
                        y, channel, std::isnan(value) ? "NaN" : value > 0 ? "+inf" : "-inf")),
      x_(x),
      y_(y) {}

std::uint64_t estimated_render_bytes(const RainCamera& camera, int input_channels, bool with_layer,
                                     double extra_bytes_per_pixel) {
  // Per pixel: the decoded frame and the rainy frame (4 bytes a channel each); the alpha, the
  // renderer's depth, transmittance and streak accumulators (4 + 4 + 4 + 4 + 12 bytes); the encoder's
  // scratch; with the layer, its 16 bytes and its own encoding. An upper bound of the peak resident
  // size of `hydrolux rain` measured at 1024^2 to 8192^2 pixels (2026-11-28, BENCHMARKS.md: 205 MB,
  // 438 MB, 1.45 GB, 3.26 GB, 5.77 GB to a PNG, the marginal cost per pixel rising from 74 to 86
  // bytes with the size; 2.07 GB at 4096^2 to EXR with --layer-out and --mask-out), with a margin of
  // 5-15% above them; tests/cli/test_memory_estimates.cpp checks it against the measured peak.
  constexpr double kEncodeBytesPerPixel = 34, kLayerBytesPerPixel = 16 + 26, kFixedBytes = 128e6;
  const double per_pixel =
      8.0 * std::max(3, input_channels) + 32 + kEncodeBytesPerPixel + (with_layer ? kLayerBytesPerPixel : 0) +
      extra_bytes_per_pixel;
  return std::uint64_t(kFixedBytes + per_pixel * double(camera.width) * double(camera.height));
}

Image builtin_scene(const RainCamera& c) {
  validate(c);
  const scene::BuiltinSky sky(false);
  Image img(c.width, c.height, 3);
  tbb::parallel_for(0, c.height, [&](int y) {
    for (int x = 0; x < c.width; ++x) {
      const Vec3 L = sky.radiance(c.to_world(c.ray(x + 0.5, y + 0.5)));
      for (int k = 0; k < 3; ++k) img.at(x, y, k) = float(L[k]);
    }
  });
  return img;
}

Image streak_alpha(const Streak& streak, int width, int height, bool simd) {
  const std::size_t n = std::size_t(width) * std::size_t(height);
  const std::size_t stride = accum_stride(width), blocks = stride / kLanes * std::size_t(height);
  std::vector<float> px(blocks * kBlock);
  clear_blocks(px.data(), blocks);
  const std::vector<float> depth(n, std::numeric_limits<float>::infinity());
  Accum acc{px.data(), 0, stride};
  raster(streak, 0, height, width, depth.data(), acc, simd);
  Image a(width, height, 1);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) a.pixels[std::size_t(y) * std::size_t(width) + std::size_t(x)] = 1 - *acc.at(y, x);
  return a;
}

std::vector<float> ground_plane_depth(const RainCamera& c, double backdrop_m) {
  std::vector<float> depth(std::size_t(c.width) * std::size_t(c.height), float(backdrop_m));
  for (int y = 0; y < c.height; ++y)
    for (int x = 0; x < c.width; ++x) {
      const Vec3 d = c.ray(x + 0.5, y + 0.5);
      const Vec3 w = c.to_world(d);
      // The ray meets the ground (world y = -height) at distance height / -w.y, at camera z d.z times that.
      if (w.y < -1e-9) depth[std::size_t(y) * c.width + x] = float(std::min(backdrop_m, c.height_m / -w.y * d.z));
    }
  return depth;
}

RainRenderer::RainRenderer(RainField field, int light_grid_x, int light_grid_y)
    : field_(std::move(field)),
      light_(field_.camera(), field_.settings().refractive_index, light_grid_x, light_grid_y) {}

void RainRenderer::set_fog(const FogSettings& settings, std::optional<Vec3> sky) {
  auto s = std::make_shared<FogSettings>(settings);
  s->backdrop_m = field_.settings().backdrop_m;  // one scene: the rain's ground plane and backdrop
  fog_optics_ = std::make_shared<const FogOptics>(fog_optics(*s));
  fog_settings_ = std::move(s);
  fog_sky_ = sky;
}

void RainRenderer::streaks(std::int64_t frame_index, std::vector<Streak>& out) const {
  std::vector<std::vector<Streak>> per_block;
  collect_streaks(frame_index, per_block);
  out.clear();
  for (const auto& l : per_block) out.insert(out.end(), l.begin(), l.end());
}

void RainRenderer::collect_streaks(std::int64_t frame_index, std::vector<std::vector<Streak>>& per_block) const {
  const RainField& f = field_;
  const RainCamera& cam = f.camera();
  const std::uint64_t total = f.drop_count();
  const std::uint64_t blocks = (total + kBlockDrops - 1) / kBlockDrops;
  per_block.resize(blocks);
  if (total == 0) return;
  const double t0 = double(frame_index) / cam.fps, te = cam.exposure_s;
  const double fpx = cam.focal_px(), cx = 0.5 * cam.width, cy = 0.5 * cam.height;
  const double W = cam.width, H = cam.height;
  const double near = f.settings().near_m, amp = f.settings().oscillation;
  const double pitch = deg_to_rad(cam.pitch_deg), pc = std::cos(pitch), ps = std::sin(pitch);

  // With the camera level (no pitch), a drop's depth and horizontal image position do not depend on its
  // radius (the wind is the same for all; only the fall speed is the radius's): the drops outside the
  // view are then culled from their start's x and z alone, before the radius is drawn, with the
  // largest extent the class's radii can give (the exact test below follows for those kept). The
  // same streaks as without: the early test is the exact one's arithmetic with a wider margin.
  const bool level = ps == 0.0;
  const Vec3 wind = f.velocity_of(0.0);  // x and z: the wind
  const std::uint64_t mixed_seed = detail::mix(f.settings().seed);
  // Per class, the early cull's margin: the largest extent any of its drops drawn (depth in [near,
  // resolved_to]) can have, its largest radius at the nearest depth with the largest defocus there or
  // at the farthest (the defocus of a depth is monotonic on each side of the focus).
  std::vector<double> early_ext(f.classes_.size(), 0.0);
  for (std::size_t k = 0; k < f.classes_.size(); ++k) {
    const RadiusClass& rc = f.classes_[k];
    const double z_far = std::max(near, rc.resolved_to_m);
    const double r = fpx * rc.radius_hi_m / near;
    const double b = std::max(cam.defocus_radius_px(near), cam.defocus_radius_px(z_far));
    early_ext[k] = std::max(1.0, std::sqrt(r * r + b * b) + 0.5) * 1.000001 + 1e-6;
  }
  tbb::parallel_for(std::uint64_t(0), blocks, [&](std::uint64_t b) {
    auto& list = per_block[b];
    list.clear();
    const std::uint64_t i0 = b * kBlockDrops, i1 = std::min(total, i0 + kBlockDrops);
    std::size_t cls = f.class_of(i0);
    for (std::uint64_t i = i0; i < i1; ++i) {
      while (cls + 1 < f.classes_.size() && i >= f.classes_[cls + 1].first_index) ++cls;
      const RadiusClass& rc = f.classes_[cls];
      const std::uint64_t key = detail::hash_mixed(mixed_seed, i);
      double level_x = 0, level_z = 0;  // with a level camera: the start's x and z, wrapped (as below)
      if (level) {
        const double x0 = detail::wrap1(rc.box_lo.x + detail::variate(key, 0) * rc.box_size.x + wind.x * t0,
                                        rc.box_lo.x, rc.box_size.x, rc.box_inv_size.x);
        const double wz = detail::wrap1(rc.box_lo.z + detail::variate(key, 2) * rc.box_size.z + wind.z * t0,
                                        rc.box_lo.z, rc.box_size.z, rc.box_inv_size.z);
        const double x1 = x0 + wind.x * te, z0 = wz * pc, z1 = (wz + wind.z * te) * pc, zm = 0.5 * (z0 + z1);
        const bool in_depth = zm >= near && zm <= rc.resolved_to_m && z0 >= 0.5 * near && z1 >= 0.5 * near;
        // Both ends left of the image (cx + fpx x / z + ext < 0) or both right of it (> W + ext),
        // multiplied through by z > 0 (no division; the margin covers the rounding); one branch.
        const double ext = early_ext[cls], lo = -(cx + ext), hi = W - cx + ext;
        const bool left = fpx * x0 < lo * z0 && fpx * x1 < lo * z1, right = fpx * x0 > hi * z0 && fpx * x1 > hi * z1;
        if (!in_depth || left || right) continue;
        level_x = x0;
        level_z = wz;
      }
      const auto d = f.drop_with_key(key, cls);
      const Vec3 vel = f.velocity_of(d.radius);
      // The start wrapped into the box (as RainField::position), then into the camera frame. With a
      // level camera x and z are those found above: the same arithmetic (the wind is every drop's x
      // and z velocity), done once.
      const Vec3 w0 =
          level ? Vec3(level_x, detail::wrap1(d.start.y + vel.y * t0, rc.box_lo.y, rc.box_size.y, rc.box_inv_size.y), level_z)
                : detail::wrap(d.start + vel * t0, rc.box_lo, rc.box_size);
      const Vec3 w1 = w0 + vel * te;
      const double z0 = w0.y * ps + w0.z * pc, z1 = w1.y * ps + w1.z * pc, zm = 0.5 * (z0 + z1);
      // Drawn between near_m and the depth where its class stops being resolved (beyond, the
      // unresolved rain stands for it); both ends in front of the camera.
      if (zm < near || zm > rc.resolved_to_m || z0 < 0.5 * near || z1 < 0.5 * near) continue;
      const double y0 = w0.y * pc - w0.z * ps, y1 = w1.y * pc - w1.z * ps;
      const double px0 = cx + fpx * w0.x / z0, py0 = cy - fpx * y0 / z0;
      const double px1 = cx + fpx * w1.x / z1, py1 = cy - fpx * y1 / z1;
      const double r = fpx * d.radius / zm, b_px = cam.defocus_radius_px(zm);
      const double R = std::sqrt(r * r + b_px * b_px);
      const double ext = R < 1 ? 1 : R + 0.5;
      if (std::max(px0, px1) + ext < 0 || std::min(px0, px1) - ext > W) continue;
      if (std::max(py0, py1) + ext < 0 || std::min(py0, py1) - ext > H) continue;
      Streak s{};
      s.x0 = float(px0);
      s.y0 = float(py0);
      s.x1 = float(px1);
      s.y1 = float(py1);
      s.r = float(r);
      s.R = float(R);
      s.z = float(zm);
      Vec3 rgb = light_.at(0.5 * (px0 + px1), 0.5 * (py0 + py1));
      if (fog_beta_ > 0) {  // seen through the fog in front of the drop, with its airlight
        const double range = zm / cam.ray(0.5 * (px0 + px1), 0.5 * (py0 + py1)).z, t = std::exp(-fog_beta_ * range);
        rgb = rgb * t + *fog_sky_ * (1 - t);
      }
      for (int k = 0; k < 3; ++k) s.rgb[k] = float(rgb[k]);
      if (amp > 0) {
        const double freq = std::sqrt(8 * kSurfaceTension / (kWaterDensity * d.radius * d.radius * d.radius)) /
                            (2 * kPi<double>);
        const double ph = d.phase + freq * t0;
        s.osc_amp = float(amp);
        s.osc_phase = float(ph - std::floor(ph));
        s.osc_cycles = float(freq * te);
      }
      s.drop = std::uint32_t(i);
      list.push_back(s);
    }
  });
}

namespace {

// A frame's steps (RainRenderer::render_into), each on the renderer's buffers.

// The scene depth per pixel (`depth`'s camera z, 0 or non-finite as infinity; else the ground plane)
// and the unresolved rain's transmittance along each pixel's ray.
void scene_depth(const Image* depth, const RainField& field, std::vector<float>& scene,
                 std::vector<float>& transmittance) {
  const RainCamera& cam = field.camera();
  const int W = cam.width, H = cam.height;
  const std::size_t npx = std::size_t(W) * std::size_t(H);
  if (depth) {
    if (depth->width != W || depth->height != H || depth->channels < 1)
      throw Error("rain: the depth map's size must be the frame's");
    scene.resize(npx);
    for (std::size_t i = 0; i < npx; ++i) {
      const float z = depth->pixels[i * std::size_t(depth->channels)];
      scene[i] = std::isfinite(z) && z > 0 ? z : std::numeric_limits<float>::infinity();
    }
  } else {
    scene = ground_plane_depth(cam, field.settings().backdrop_m);
  }
  transmittance.resize(npx);
  tbb::parallel_for(0, H, [&](int y) {
    for (int x = 0; x < W; ++x) {
      const std::size_t i = std::size_t(y) * W + x;
      const double cos_axis = cam.ray(x + 0.5, y + 0.5).z;
      transmittance[i] = float(std::exp(-field.unresolved_optical_depth(scene[i], cos_axis)));
    }
  });
}

// Bins the streaks by band of rows: `offset[k]` is band k's first streak in `banded`, each streak
// with its index in the frame (block b's streak j is first[b] + j).
void bin_streaks(const std::vector<std::vector<Streak>>& per_block, const std::vector<std::uint32_t>& first, int H,
                 std::vector<std::uint32_t>& offset, std::vector<Streak>& banded) {
  // A counting sort that copies each streak into every band it touches, in drop order.
  const int bands = (H + kBandRows - 1) / kBandRows;
  auto band_range = [&](const Streak& s) {
    const float ext = s.R < 1 ? 1.f : s.R + 0.5f;
    const float ya = std::max(0.f, std::min(s.y0, s.y1) - ext), yb = std::max(0.f, std::max(s.y0, s.y1) + ext);
    return std::pair<int, int>(std::min(int(ya) / kBandRows, bands - 1), std::min(int(yb) / kBandRows, bands - 1));
  };
  // Blocks in parallel: each block's count per band, then each block copies its streaks to the
  // places the counts give it (a band's streaks in drop order, whatever the threads).
  const std::size_t nb = per_block.size(), nbands = std::size_t(bands);
  std::vector<std::uint32_t> counts(nb * nbands, 0);  // block b, band k at b * nbands + k
  tbb::parallel_for(std::size_t(0), nb, [&](std::size_t b) {
    for (const auto& s : per_block[b]) {
      const auto [lo, hi] = band_range(s);
      for (int k = lo; k <= hi; ++k) ++counts[b * nbands + std::size_t(k)];
    }
  });
  offset.assign(nbands + 1, 0);
  for (std::size_t k = 0; k < nbands; ++k) {  // counts become each block's first place in band k
    std::uint32_t at = offset[k];
    for (std::size_t b = 0; b < nb; ++b) {
      const std::uint32_t n = counts[b * nbands + k];
      counts[b * nbands + k] = at;
      at += n;
    }
    offset[k + 1] = at;
  }
  if (banded.size() < offset.back()) banded.resize(offset.back());  // grown, never shrunk: no refill
  tbb::parallel_for(std::size_t(0), nb, [&](std::size_t b) {
    std::uint32_t* fill = counts.data() + b * nbands;
    for (std::size_t j = 0; j < per_block[b].size(); ++j) {
      const Streak& s = per_block[b][j];
      const auto [lo, hi] = band_range(s);
      for (int k = lo; k <= hi; ++k) {
        Streak& c = banded[fill[std::size_t(k)]++];
        c = s;
        c.drop = first[b] + std::uint32_t(j);  // the streak's index in the frame, for its visibility
      }
    }
  });
}

// What the bands' compositing reads.
struct BandInputs {
  const Image& frame;
  const std::vector<float>& depth;
  const std::vector<float>& transmittance;
  const DropLight& light;
  const FogVeil* fog;
  const std::optional<Vec3>& fog_sky;
  const std::vector<std::uint32_t>& offset;
  const std::vector<Streak>& banded;
  bool with_layer;
};

// Per band of rows, one task: its streaks rasterised into the band's accumulators, then the band
// composited while they are still in cache: image = (clear T_u + airlight (1 - T_u)) T_s + streak
// colour (1 - T_s). Each row's sums to `row_sums`, each streak that reached a pixel marked `visible`.
void composite_bands(const BandInputs& bi, std::vector<float>& accumulators, RainFrame& out,
                     std::vector<detail::RowSums>& row_sums, std::vector<std::atomic<std::uint8_t>>& visible) {
  const Image& frame = bi.frame;
  const FogVeil* fog = bi.fog;
  const bool with_layer = bi.with_layer;
  const int W = frame.width, H = frame.height, ch = frame.channels;
  const int bands = (H + kBandRows - 1) / kBandRows;
  const std::size_t stride = accum_stride(W), band_blocks = stride / kLanes * std::size_t(kBandRows);
  accumulators.resize(std::size_t(bands) * band_blocks * kBlock);
  // RGB frames without fog: whole blocks of a row in SIMD (composite.cpp), the rest here.
  const bool simd = ch == 3 && !fog;
  tbb::parallel_for(0, bands, [&](int band) {
    const int r0 = band * kBandRows, r1 = std::min(H, r0 + kBandRows);
    float* band_acc = accumulators.data() + std::size_t(band) * band_blocks * kBlock;
    clear_blocks(band_acc, band_blocks);
    Accum acc{band_acc, r0, stride};
    for (std::uint32_t m = bi.offset[std::size_t(band)]; m < bi.offset[std::size_t(band) + 1]; ++m) {
      const Streak& s = bi.banded[m];
      const float ext = s.R < 1 ? 1.f : s.R + 0.5f;
      const int ya = std::max(r0, int(std::floor(std::min(s.y0, s.y1) - ext)));
      const int yb = std::min(r1, int(std::ceil(std::max(s.y0, s.y1) + ext)) + 1);
      if (ya < yb && raster(s, ya, yb, W, bi.depth.data(), acc))
        visible[s.drop].store(1, std::memory_order_relaxed);
    }

    std::vector<float> air_row;  // the airlight along a row, RGB
    for (int y = r0; y < r1; ++y) {
      detail::RowSums& sums = row_sums[std::size_t(y)];
      // The airlight along the row: the drop light at the row's two ends of each grid cell, lerped.
      bi.light.row(y + 0.5, air_row);
      const std::size_t row0 = std::size_t(y) * W;
      const float* in = frame.pixels.data() + row0 * std::size_t(ch);
      float* im = out.image.pixels.data() + row0 * std::size_t(ch);
      float* al = out.alpha.pixels.data() + row0;
      float* ly = with_layer ? out.layer.pixels.data() + row0 * 4 : nullptr;
      const float* tur = bi.transmittance.data() + row0;
      int x = 0;
      if (simd) {
        const std::size_t n = std::size_t(W) / kLanes * kLanes;
        detail::composite_rgb_row({in, tur, acc.at(y, 0), air_row.data(), im, al, ly, n, &sums});
        x = int(n);
        in += n * 3;
        im += n * 3;
      }
      for (; x < W; ++x, in += ch, im += ch) {
        const float tu = tur[x];
        const float* q = acc.at(y, x);
        const float ts = q[0], as = 1 - ts, qw = q[kLanes];
        const float inv_w = qw > 0 ? 1 / qw : 0.f;
        // The veil behind the streaks: the unresolved rain's, or with fog one medium of both optical
        // depths whose airlight mixes the drops' light and the fog's sky in their proportion.
        float T = tu, air[3];
        for (int k = 0; k < 3; ++k) air[k] = air_row[std::size_t(x) * 3 + std::size_t(k)] * (1 - tu);
        if (fog) {
          const std::size_t i = row0 + std::size_t(x);
          const float tau_f = fog->tau[i], tau_u = tu < 1 ? -std::log(tu) : 0.f;
          T = tu * float(fog->t[i]);
          const float wr = std::isinf(tau_f) ? 0.f : tau_u + tau_f > 0 ? tau_u / (tau_u + tau_f) : 1.f;
          for (int k = 0; k < 3; ++k)
            air[k] = (wr * air_row[std::size_t(x) * 3 + std::size_t(k)] + (1 - wr) * float((*bi.fog_sky)[k])) * (1 - T) +
                     (fog->glow.pixels.empty() ? 0.f : fog->glow.pixels[i * 3 + std::size_t(k)]);
        }
        // The streaks' own change is measured against the background they cover (with the veil,
        // which lies behind them). composite.cpp does the same, lane by lane.
        float luma_in = 0, luma_out = 0, layer[3];
        for (std::size_t k = 0; k < 3; ++k) {
          const float clear = std::max(0.f, in[k]);
          layer[k] = air[k] * ts + q[(2 + k) * kLanes] * inv_w * as;
          const float v = clear * T * ts + layer[k];
          im[k] = v;
          luma_in += kLuma[k] * (clear * T + air[k]);
          luma_out += kLuma[k] * v;
        }
        for (int k = 3; k < ch; ++k) im[k] = in[k];
        const float alpha = 1 - T * ts;
        al[x] = alpha;
        if (ly) {
          for (int k = 0; k < 3; ++k) ly[std::size_t(x) * 4 + std::size_t(k)] = layer[k];
          ly[std::size_t(x) * 4 + 3] = alpha;
        }
        sums.tu += tu;
        sums.alpha += alpha;
        if (as >= 0.01f) {
          ++sums.streak_px;
          sums.gain += luma_out - luma_in;
          sums.bg += luma_in;
        }
      }
    }
  });

}

// The frame's streak statistics: per block in parallel (sums per block, added in block order), the
// rows' sums in row order: the same whatever the threads.
void streak_stats(const std::vector<std::vector<Streak>>& per_block, const std::vector<std::uint32_t>& first,
                  const std::vector<std::atomic<std::uint8_t>>& visible, const std::vector<detail::RowSums>& row_sums,
                  std::size_t npx, RainStats& st) {
  const std::uint32_t n_streaks = first.back();
  struct BlockStats {
    double width_sum = 0, luma_sum = 0, length_max = 0, width_max = 0;
    std::uint32_t visible = 0;
  };
  std::vector<BlockStats> block_stats(per_block.size());
  std::vector<float> lengths(n_streaks);
  tbb::parallel_for(std::size_t(0), per_block.size(), [&](std::size_t b) {
    BlockStats& bs = block_stats[b];
    for (std::size_t j = 0; j < per_block[b].size(); ++j) {
      const Streak& s = per_block[b][j];
      const float dx = s.x1 - s.x0, dy = s.y1 - s.y0, len = std::sqrt(dx * dx + dy * dy);
      lengths[first[b] + j] = len;
      bs.length_max = std::max(bs.length_max, double(len));
      bs.width_sum += 2.0 * s.R;
      bs.width_max = std::max(bs.width_max, 2.0 * s.R);
      bs.luma_sum += kLuma[0] * s.rgb[0] + kLuma[1] * s.rgb[1] + kLuma[2] * s.rgb[2];
      bs.visible += visible[first[b] + j].load(std::memory_order_relaxed);
    }
  });
  double width_sum = 0, luma_sum = 0;
  for (const BlockStats& bs : block_stats) {
    width_sum += bs.width_sum;
    luma_sum += bs.luma_sum;
    st.streak_length_px_max = std::max(st.streak_length_px_max, bs.length_max);
    st.streak_width_px_max = std::max(st.streak_width_px_max, bs.width_max);
    st.drops_visible += bs.visible;
  }
  if (n_streaks > 0) {
    st.streak_length_px_mean = std::accumulate(lengths.begin(), lengths.end(), 0.0) / double(n_streaks);
    st.streak_width_px_mean = width_sum / double(n_streaks);
    st.drop_luminance_mean = luma_sum / double(n_streaks);
    std::tie(st.streak_length_px_p50, st.streak_length_px_p95) = percentiles(lengths, 0.5, 0.95);
  }
  detail::RowSums total;  // rows in order: the same sums whatever the threads
  for (const auto& r : row_sums) {
    total.tu += r.tu;
    total.alpha += r.alpha;
    total.gain += r.gain;
    total.bg += r.bg;
    total.streak_px += r.streak_px;
  }
  const double streak_px = double(total.streak_px);
  if (streak_px > 0) {
    st.streak_luminance_gain = total.gain / streak_px;
    st.background_luminance_mean = total.bg / streak_px;
  }
  st.streak_pixel_fraction = streak_px / double(npx);
  st.alpha_mean = total.alpha / double(npx);
  st.unresolved_transmittance_mean = total.tu / double(npx);
}

}  // namespace

RainFrame RainRenderer::render(const Image& frame, const Image* depth, std::int64_t frame_index, bool with_layer) {
  RainFrame out;
  render_into(frame, depth, frame_index, with_layer, out);
  return out;
}

void RainRenderer::render_into(const Image& frame, const Image* depth, std::int64_t frame_index, bool with_layer,
                               RainFrame& out) {
  const RainCamera& cam = field_.camera();
  const int W = cam.width, H = cam.height;
  if (frame.channels < 3)
    throw Error(fmt::format("rain: the frame has {} channel{}; rain needs colour (R, G, B: at least 3 channels)",
                            frame.channels, frame.channels == 1 ? "" : "s"));
  if (frame.width != W || frame.height != H)
    throw Error(fmt::format("rain: the frame is {}x{}, the camera {}x{}: they must be the same size", frame.width,
                            frame.height, W, H));
  const std::size_t npx = std::size_t(W) * std::size_t(H);
  const std::uint64_t negatives = check_frame_values(frame);
  // The scene depth and the unresolved rain's transmittance along each pixel's ray: once for the
  // ground plane, per frame for a depth map.
  if (depth || !ground_plane_ || depth_.size() != npx) {
    scene_depth(depth, field_, depth_, transmittance_);
    ground_plane_ = depth == nullptr;
  }

  // Fog: its transmittance, airlight and glow along every ray, the sky colour kept from the first frame.
  // The drops are lit by the scene as the fog lets them see it: the drop light from the fogged frame.
  std::optional<FogVeil> fog;
  if (fog_optics_) {
    fog = fog_veil(frame, depth, cam, *fog_settings_, *fog_optics_, fog_sky_);
    if (!fog_sky_) fog_sky_ = fog->sky;
    fog_beta_ = fog_optics_->beta_per_m;
    light_.update(apply_fog_veil(frame, *fog));
  } else {
    light_.update(frame);
  }
  collect_streaks(frame_index, per_block_);
  // Streak j of the frame is per_block_[b][j - first[b]]; bands list j.
  std::vector<std::uint32_t> first(per_block_.size() + 1, 0);
  for (std::size_t b = 0; b < per_block_.size(); ++b) first[b + 1] = first[b] + std::uint32_t(per_block_[b].size());
  const std::uint32_t n_streaks = first.back();

  // Bin the streaks by band of rows: a band reads its streaks from contiguous memory.
  bin_streaks(per_block_, first, H, band_offset_, banded_);

  // The outputs' buffers (reused when the size is the same), then the bands rasterised and composited.
  const int ch = frame.channels;
  if (out.image.width != W || out.image.height != H || out.image.channels != ch) out.image = Image(W, H, ch);
  out.image.channel_names = frame.channel_names;
  if (out.alpha.width != W || out.alpha.height != H) out.alpha = Image(W, H, 1);
  if (with_layer && (out.layer.width != W || out.layer.height != H)) out.layer = Image(W, H, 4);
  if (!with_layer) out.layer = Image();
  std::vector<detail::RowSums> row_sums(static_cast<std::size_t>(H));
  std::vector<std::atomic<std::uint8_t>> visible(n_streaks);
  composite_bands({frame, depth_, transmittance_, light_, fog ? &*fog : nullptr, fog_sky_, band_offset_, banded_,
                   with_layer},
                  acc_, out, row_sums, visible);

  RainStats& st = out.stats;
  st = RainStats{};
  st.negative_values_clamped = negatives;
  st.drops_total = field_.drop_count();
  st.drops_in_view = n_streaks;
  streak_stats(per_block_, first, visible, row_sums, npx, st);
  if (fog) {
    st.fog_beta_per_m = fog->stats.beta_per_m;
    st.fog_visibility_m = fog->stats.visibility_m;
    st.fog_transmittance_mean = fog->stats.transmittance_mean;
    st.fog_glow_mean = fog->stats.glow_mean;
    st.fog_sky = *fog_sky_;
  }
}

}  // namespace hydrolux::rain
