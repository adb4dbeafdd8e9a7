#pragma once
// The rain's composite of one row over a 3-channel frame without fog, in SIMD (composite.cpp): the
// renderer's scalar composite (render.cpp) lane by lane, for the pixels [0, n) of a row, n a whole
// number of accumulator blocks (kStreakAccumLanes).
#include <cstddef>
#include <cstdint>

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

}  // namespace hydrolux::rain::detail
