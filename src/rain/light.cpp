// The drops' light from the frame itself (rain.hpp, "The drop's light").
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "hydrolux/core/error.hpp"
#include "hydrolux/core/math.hpp"
#include "hydrolux/drop/model.hpp"
#include "hydrolux/rain/rain.hpp"

namespace hydrolux::rain {

namespace {

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define HYDROLUX_LIGHT_CLONES __attribute__((target_clones("avx512f", "avx2", "default")))
#else
#define HYDROLUX_LIGHT_CLONES
#endif

// The sums of max(0, value) of n RGB pixels, in double, into part[3]: 12 running sums (4 pixels x
// RGB) the compiler vectorises, each a sequence of additions in pixel order, so every SIMD target
// (compiled for AVX-512 and AVX2 too, chosen at load; the baseline is SSE2) gives the same sums.
HYDROLUX_LIGHT_CLONES
void add_rgb_sums(const float* __restrict p, std::size_t n, double* __restrict part) {
  constexpr std::size_t kRun = 12;
  double run[kRun] = {};
  std::size_t x = 0;
  for (; x + 4 <= n; x += 4, p += kRun)
    for (std::size_t l = 0; l < kRun; ++l) run[l] += double(std::max(0.f, p[l]));
  for (std::size_t l = 0; l < kRun; ++l) part[l % 3] += run[l];
  for (; x < n; ++x, p += 3)
    for (std::size_t k = 0; k < 3; ++k) part[k] += double(std::max(0.f, p[k]));
}

// out[3 x] = a (1 - ax[x]) + b ax[x] for the n columns of one grid cell (light.cpp is compiled
// without FMA contraction: every target rounds as the baseline does).
HYDROLUX_LIGHT_CLONES
void lerp_columns(const double* __restrict ax, std::size_t n, const double* __restrict a, const double* __restrict b,
                  float* __restrict out) {
  for (std::size_t x = 0; x < n; ++x)
    for (std::size_t k = 0; k < 3; ++k) out[x * 3 + k] = float(a[k] * (1 - ax[x]) + b[k] * ax[x]);
}

// The frame is reduced to this width for the drops' environment: a drop maps ~165 degrees onto a disk
// a few pixels wide, so it never shows the frame's detail, and smaller is faster to fill.
constexpr int kSmallWidth = 64;
// Samples over the drop's disk per grid node: equal-area rings x azimuths.
constexpr int kRings = 8, kAzimuths = 16;
// The sky and the ground are the means of this fraction of the frame's top and bottom rows.
constexpr double kEdgeRows = 0.1;
}  // namespace

DropLight::DropLight(const RainCamera& camera, double mu, int grid_x, int grid_y)
    : c_(camera), gx_(grid_x), gy_(grid_y) {
  validate(c_);
  require_in_range("grid_x", grid_x, 2, 1024);
  require_in_range("grid_y", grid_y, 2, 1024);
  small_w_ = std::min(kSmallWidth, c_.width);
  small_h_ = std::max(1, int(std::lround(double(small_w_) * c_.height / c_.width)));
  const std::size_t nodes = std::size_t(gx_) * std::size_t(gy_);
  sky_w_.assign(nodes, 0.f);
  ground_w_.assign(nodes, 0.f);
  node_.assign(nodes, Vec3(0));
  // Per column, once: its grid cell and position in it (row() interpolates there) and its small-frame
  // column (update() sums there).
  std::vector<int> col_cell(std::size_t(c_.width)), col_small(std::size_t(c_.width));
  col_ax_.resize(std::size_t(c_.width));
  for (int x = 0; x < c_.width; ++x) {
    const double fx = std::clamp((x + 0.5) / c_.width * (gx_ - 1), 0.0, double(gx_ - 1));
    const int cell = std::min(int(fx), gx_ - 2);
    col_cell[std::size_t(x)] = cell;
    col_ax_[std::size_t(x)] = fx - cell;
    col_small[std::size_t(x)] = std::min(small_w_ - 1, int(std::int64_t(x) * small_w_ / c_.width));
  }
  // Both maps never decrease along a row: each cell's and each small column's first image column.
  cell_col_begin_.assign(std::size_t(gx_), c_.width);
  small_col_begin_.assign(std::size_t(small_w_) + 1, c_.width);
  for (int x = c_.width - 1; x >= 0; --x) {
    cell_col_begin_[std::size_t(col_cell[std::size_t(x)])] = x;
    small_col_begin_[std::size_t(col_small[std::size_t(x)])] = x;
  }
  for (int i = gx_ - 2; i >= 0; --i)  // a cell without columns (a grid finer than the image) is empty
    cell_col_begin_[std::size_t(i)] = std::min(cell_col_begin_[std::size_t(i)], cell_col_begin_[std::size_t(i) + 1]);
  for (int i = small_w_ - 1; i >= 0; --i)
    small_col_begin_[std::size_t(i)] = std::min(small_col_begin_[std::size_t(i)], small_col_begin_[std::size_t(i) + 1]);
  const double scale_x = double(small_w_) / c_.width, scale_y = double(small_h_) / c_.height;
  const double n_samples = double(kRings) * kAzimuths;

  for (int j = 0; j < gy_; ++j) {
    for (int i = 0; i < gx_; ++i) {
      const auto node = std::uint32_t(j * gx_ + i);
      const double px = double(i) * c_.width / (gx_ - 1), py = double(j) * c_.height / (gy_ - 1);
      const Vec3 view = c_.to_world(c_.ray(px, py));
      // An orthonormal pair across the view.
      const Vec3 helper = std::abs(view.y) < 0.9 ? Vec3(0, 1, 0) : Vec3(1, 0, 0);
      const Vec3 e1 = glm::normalize(glm::cross(helper, view)), e2 = glm::cross(view, e1);
      auto add = [&](const Vec3& dir_world, double w) {
        if (w <= 0) return;
        const Vec3 d = c_.to_camera(dir_world);
        if (d.z > 1e-6) {
          const auto p = c_.project(d);
          if (p[0] >= 0 && p[0] <= c_.width && p[1] >= 0 && p[1] <= c_.height) {
            taps_.push_back({node, float(p[0] * scale_x), float(p[1] * scale_y), float(w / n_samples)});
            return;
          }
        }
        (dir_world.y > 0 ? sky_w_ : ground_w_)[node] += float(w / n_samples);
      };
      for (int ring = 0; ring < kRings; ++ring) {
        // Equal-area rings over the disk: rho = sin(i) uniform in rho^2.
        const double rho = std::sqrt((ring + 0.5) / kRings);
        const double cos_i = std::sqrt(1 - rho * rho);
        for (int k = 0; k < kAzimuths; ++k) {
          const double phi = 2 * kPi<double> * (k + 0.5 * (ring % 2 + 0.5)) / kAzimuths;
          const Vec3 normal = -view * cos_i + (e1 * std::cos(phi) + e2 * std::sin(phi)) * rho;
          const auto rays = drop::drop_rays(view, normal, mu, 2);
          add(rays.refraction, rays.R);
          add(rays.reflection, rays.S);
          for (std::size_t n = 0; n < rays.internal.size(); ++n) add(rays.internal[n], rays.P[n]);
        }
      }
    }
  }
}

void DropLight::update(const Image& frame) {
  if (frame.width != c_.width || frame.height != c_.height || frame.channels < 3)
    throw Error("DropLight::update: the frame must have the camera's size and at least 3 channels");
  // Area average into the small frame, one small row per task (the frame's rows that fall in it).
  // Each small column's pixels are contiguous in a row (small_col_begin_): their values are
  // summed in double into 12 running sums (4 pixels x RGB, a loop the compiler vectorises), folded
  // into the column's three sums a row at a time.
  small_.assign(std::size_t(small_w_) * small_h_ * 3, 0.f);
  const auto ch = std::size_t(frame.channels);
  tbb::parallel_for(0, small_h_, [&](int sy) {
    std::vector<double> sum(std::size_t(small_w_) * 3, 0.0), count(std::size_t(small_w_), 0.0);
    const int y0 = int((std::int64_t(sy) * frame.height + small_h_ - 1) / small_h_);
    const int y1 = int((std::int64_t(sy + 1) * frame.height + small_h_ - 1) / small_h_);
    for (int y = y0; y < std::min(y1, frame.height); ++y) {
      const float* row = frame.pixels.data() + std::size_t(y) * std::size_t(frame.width) * ch;
      for (std::size_t sx = 0; sx < std::size_t(small_w_); ++sx) {
        const std::size_t xa = std::size_t(small_col_begin_[sx]), xb = std::size_t(small_col_begin_[sx + 1]);
        double part[3] = {0, 0, 0};
        if (ch == 3) {
          add_rgb_sums(row + xa * 3, xb - xa, part);
        } else {
          for (std::size_t x = xa; x < xb; ++x)
            for (std::size_t k = 0; k < 3; ++k) part[k] += double(std::max(0.f, row[x * ch + k]));
        }
        for (std::size_t k = 0; k < 3; ++k) sum[sx * 3 + k] += part[k];
        count[sx] += double(xb - xa);
      }
    }
    for (std::size_t sx = 0; sx < std::size_t(small_w_); ++sx)
      for (std::size_t k = 0; k < 3; ++k)
        small_[(std::size_t(sy) * small_w_ + sx) * 3 + k] = float(sum[sx * 3 + k] / std::max(1.0, count[sx]));
  });

  const int edge = std::max(1, int(std::lround(kEdgeRows * small_h_)));
  auto mean_rows = [&](int y0, int y1) {
    Vec3 m(0);
    for (int y = y0; y < y1; ++y)
      for (int x = 0; x < small_w_; ++x)
        for (int k = 0; k < 3; ++k) m[k] += small_[(std::size_t(y) * small_w_ + x) * 3 + k];
    return m / double((y1 - y0) * small_w_);
  };
  sky_ = mean_rows(0, edge);
  ground_ = mean_rows(small_h_ - edge, small_h_);

  for (std::size_t n = 0; n < node_.size(); ++n) node_[n] = sky_ * double(sky_w_[n]) + ground_ * double(ground_w_[n]);
  for (const Tap& t : taps_) {
    // Bilinear between the small frame's pixel centres, clamped at its edges.
    const float fx = std::clamp(t.u - 0.5f, 0.f, float(small_w_ - 1)), fy = std::clamp(t.v - 0.5f, 0.f, float(small_h_ - 1));
    const int x0 = std::min(int(fx), std::max(0, small_w_ - 2)), y0 = std::min(int(fy), std::max(0, small_h_ - 2));
    const int x1 = std::min(x0 + 1, small_w_ - 1), y1 = std::min(y0 + 1, small_h_ - 1);
    const float ax = fx - float(x0), ay = fy - float(y0);
    for (int k = 0; k < 3; ++k) {
      const auto at = [&](int x, int y) { return small_[(std::size_t(y) * small_w_ + x) * 3 + k]; };
      const float v = (at(x0, y0) * (1 - ax) + at(x1, y0) * ax) * (1 - ay) + (at(x0, y1) * (1 - ax) + at(x1, y1) * ax) * ay;
      node_[t.node][k] += double(t.w) * v;
    }
  }
}

Vec3 DropLight::at(double px, double py) const {
  const double fx = std::clamp(px / c_.width * (gx_ - 1), 0.0, double(gx_ - 1));
  const double fy = std::clamp(py / c_.height * (gy_ - 1), 0.0, double(gy_ - 1));
  const int x0 = std::min(int(fx), gx_ - 2), y0 = std::min(int(fy), gy_ - 2);
  const double ax = fx - x0, ay = fy - y0;
  const auto n = [&](int x, int y) { return node_[std::size_t(y) * gx_ + x]; };
  return (n(x0, y0) * (1 - ax) + n(x0 + 1, y0) * ax) * (1 - ay) + (n(x0, y0 + 1) * (1 - ax) + n(x0 + 1, y0 + 1) * ax) * ay;
}

void DropLight::row(double py, std::vector<float>& out) const {
  out.resize(std::size_t(c_.width) * 3);
  const double fy = std::clamp(py / c_.height * (gy_ - 1), 0.0, double(gy_ - 1));
  const int y0 = std::min(int(fy), gy_ - 2);
  const double ay = fy - y0;
  const auto node = [&](int i) { return node_[std::size_t(y0) * gx_ + i] * (1 - ay) + node_[std::size_t(y0 + 1) * gx_ + i] * ay; };
  // Cell by cell (its columns are contiguous): the row's values at the cell's two nodes, lerped
  // across its columns in a loop without branches.
  for (int cell = 0; cell + 1 < gx_; ++cell) {
    const Vec3 va = node(cell), vb = node(cell + 1);
    const double a[3] = {va.x, va.y, va.z}, b[3] = {vb.x, vb.y, vb.z};
    const std::size_t xa = std::size_t(cell_col_begin_[std::size_t(cell)]);
    const std::size_t xb = std::size_t(cell_col_begin_[std::size_t(cell) + 1]);
    lerp_columns(col_ax_.data() + xa, xb - xa, a, b, out.data() + xa * 3);
  }
}

}  // namespace hydrolux::rain
