#pragma once
// The rain's composite of one row over a 3-channel frame without fog, in SIMD (composite.cpp): the
// renderer's scalar composite (render.cpp) lane by lane, for the pixels [0, n) of a row, n a whole
// number of accumulator blocks (kStreakAccumLanes). And the raster of thin streaks (composite.cpp):
// the renderer's scalar raster (render.cpp) lane by lane, the same floats.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>

namespace hydrolux::rain::detail {

// The row's sums for the frame's statistics (per pixel: the unresolved transmittance, the alpha; over
// pixels with streak alpha >= 0.01: their count, the luminance the streaks add and the background's).
struct RowSums {
  double tu = 0, alpha = 0, gain = 0, bg = 0;
  std::uint32_t streak_px = 0;
};

struct CompositeRow {
  const float* in;   // the frame's row, RGB
  const float* tu;   // the unresolved rain's transmittance, per pixel
  const float* acc;  // the row's first accumulator block (rain.hpp, kStreakAccumLanes)
  const float* air;  // the drop light along the row, RGB
  float* out;        // the rainy row, RGB
  float* alpha;      // 1 - T_u T_s
  float* layer;      // RGBA, or null
  std::size_t n;
  RowSums* sums;
};

void composite_rgb_row(const CompositeRow& row);

// The integral of the unit tent max(0, 1 - |x|) from -infinity to u.
// With c = u clamped to [-1, 1]: (1 + c)^2 / 2 for c <= 0 and 1 - (1 - c)^2 / 2 above, both
// 1/2 + c - c |c| / 2 (no branches in the raster's inner loop).
inline float tent_cdf(float u) {
  const float c = std::clamp(u, -1.f, 1.f);
  return 0.5f + c - 0.5f * c * std::abs(c);
}

// The interval of x where a x + b lies in [lo, hi], intersected into [x0, x1]; inv_a = 1 / a.
inline void clip_linear(float a, float inv_a, float b, float lo, float hi, float& x0, float& x1) {
  if (std::abs(a) < 1e-7f) {
    if (b < lo || b > hi) x1 = x0 - 1;  // empty
    return;
  }
  float u = (lo - b) * inv_a, v = (hi - b) * inv_a;
  if (u > v) std::swap(u, v);
  x0 = std::max(x0, u);
  x1 = std::min(x1, v);
}

// A thin streak (its blur radius under a pixel, no oscillation) as render.cpp's raster() sets it
// up, and where it draws: rows [row0, row1) of accumulators whose first row is acc_r0.
struct ThinStreak {
  float x0, y0, ux, uy, L, inv_L, inv_ux, inv_uy, w, z;
  float rgb[3];
  int row0, row1, width;
  const float* depth;  // the scene's depth, width per row
  float* acc;          // accumulator blocks (rain.hpp, kStreakAccumLanes)
  int acc_r0;
  std::size_t stride;  // accumulator pixels a row, a whole number of blocks
  // The row range's band (thin_row_range), once a streak: whether |uy| >= 1/4, ux / uy and 1 / |uy|.
  bool steep = std::abs(uy) >= 0.25f;
  double slope = steep ? double(ux) / double(uy) : 0.0, half_width = steep ? 1.0 / std::abs(double(uy)) : 0.0;
};

// The pixels [ia, ib] of row y to visit for a thin streak; false when there are none. A pixel
// outside the footprint (|p| >= 1 or s outside (-1, L + 1)) gets alpha <= 0, which adds nothing and
// leaves its accumulators exactly as they were, so any range that holds the footprint gives the same
// floats. For streaks within 75 degrees of vertical (|uy| >= 1/4: nearly all) the range is the band
// |p| < 1 around the streak's axis on the row, widened by 0.01 pixel against rounding (p's error is
// ~1e-4 pixel); the others are clipped to |p| <= 1 and s in [-1, L + 1] exactly.
inline bool thin_row_range(const ThinStreak& t, int y, int& ia, int& ib) {
  const float qy = float(y) + 0.5f;
  if (t.steep) {
    const double xc = double(t.x0) + (double(qy) - double(t.y0)) * t.slope;
    ia = std::max(0, int(std::ceil(xc - t.half_width - 0.51)));
    ib = std::min(t.width - 1, int(std::floor(xc + t.half_width - 0.49)));
    return ia <= ib;
  }
  float xa = -std::numeric_limits<float>::max(), xb = std::numeric_limits<float>::max();
  clip_linear(t.uy, t.inv_uy, -t.x0 * t.uy - (qy - t.y0) * t.ux, -1.f, 1.f, xa, xb);
  clip_linear(t.ux, t.inv_ux, -t.x0 * t.ux + (qy - t.y0) * t.uy, -1.f, t.L + 1.f, xa, xb);
  if (xb < xa) return false;
  ia = std::max(0, int(std::ceil(xa - 0.5f)));
  ib = std::min(t.width - 1, int(std::floor(xb - 0.5f)));
  return ia <= ib;
}

// Rasterises the streak; returns whether it touched a pixel.
bool thin_streak_rows(const ThinStreak& t);

}  // namespace hydrolux::rain::detail
