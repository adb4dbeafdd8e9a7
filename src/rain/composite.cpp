// The rain's composite of one row over an RGB frame and the raster of thin streaks, Highway SIMD
// across pixels (composite.hpp).

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "src/rain/composite.cpp"  // NOLINT
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>

#include "composite.hpp"
#include "hydrolux/rain/rain.hpp"

HWY_BEFORE_NAMESPACE();
namespace hydrolux::rain::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// The same operations, in the same order, as the renderer's scalar composite (render.cpp), lane by
// lane: vectors of at most one accumulator block (kStreakAccumLanes pixels), so that every vector's
// T, W and C are contiguous in the block.
void CompositeRgbRow(const detail::CompositeRow& r) {
  const hn::CappedTag<float, kStreakAccumLanes> d;
  using V = hn::Vec<decltype(d)>;
  const std::size_t N = hn::Lanes(d);
  constexpr std::size_t L = kStreakAccumLanes, LF = kStreakAccumFloats;
  const V one = hn::Set(d, 1.f), zero = hn::Zero(d), streak_min = hn::Set(d, 0.01f);
  const V luma[3] = {hn::Set(d, 0.2126f), hn::Set(d, 0.7152f), hn::Set(d, 0.0722f)};
  V s_tu = zero, s_alpha = zero, s_gain = zero, s_bg = zero, s_px = zero;
  for (std::size_t x = 0; x < r.n; x += N) {
    const float* g = r.acc + (x / L) * LF + x % L;
    const V tu = hn::LoadU(d, r.tu + x);
    const V ts = hn::LoadU(d, g), w = hn::LoadU(d, g + L);
    const V c[3] = {hn::LoadU(d, g + 2 * L), hn::LoadU(d, g + 3 * L), hn::LoadU(d, g + 4 * L)};
    V in[3], air_row[3];
    hn::LoadInterleaved3(d, r.in + 3 * x, in[0], in[1], in[2]);
    hn::LoadInterleaved3(d, r.air + 3 * x, air_row[0], air_row[1], air_row[2]);
    const V as = hn::Sub(one, ts);
    const auto covered = hn::Gt(w, zero);
    const V inv_w = hn::IfThenElseZero(covered, hn::Div(one, hn::IfThenElse(covered, w, one)));
    const V veil = hn::Sub(one, tu);
    V luma_in = zero, luma_out = zero, layer[3], v[3];
    for (int k = 0; k < 3; ++k) {
      const V clear = hn::Max(zero, in[k]);
      const V air = hn::Mul(air_row[k], veil);
      layer[k] = hn::Add(hn::Mul(air, ts), hn::Mul(hn::Mul(c[k], inv_w), as));
      v[k] = hn::Add(hn::Mul(hn::Mul(clear, tu), ts), layer[k]);
      luma_in = hn::Add(luma_in, hn::Mul(luma[k], hn::Add(hn::Mul(clear, tu), air)));
      luma_out = hn::Add(luma_out, hn::Mul(luma[k], v[k]));
    }
    hn::StoreInterleaved3(v[0], v[1], v[2], d, r.out + 3 * x);
    const V alpha = hn::Sub(one, hn::Mul(tu, ts));
    hn::StoreU(alpha, d, r.alpha + x);
    if (r.layer) hn::StoreInterleaved4(layer[0], layer[1], layer[2], alpha, d, r.layer + 4 * x);
    s_tu = hn::Add(s_tu, tu);
    s_alpha = hn::Add(s_alpha, alpha);
    const auto streak = hn::Ge(as, streak_min);
    s_px = hn::Add(s_px, hn::IfThenElseZero(streak, one));
    s_gain = hn::Add(s_gain, hn::IfThenElseZero(streak, hn::Sub(luma_out, luma_in)));
    s_bg = hn::Add(s_bg, hn::IfThenElseZero(streak, luma_in));
  }
  r.sums->tu += double(hn::GetLane(hn::SumOfLanes(d, s_tu)));
  r.sums->alpha += double(hn::GetLane(hn::SumOfLanes(d, s_alpha)));
  r.sums->gain += double(hn::GetLane(hn::SumOfLanes(d, s_gain)));
  r.sums->bg += double(hn::GetLane(hn::SumOfLanes(d, s_bg)));
  r.sums->streak_px += std::uint32_t(hn::GetLane(hn::SumOfLanes(d, s_px)));
}

// render.cpp's raster() of a thin streak, lane by lane, in vectors of at most one accumulator block,
// with the same operations in the same order as the scalar loop, over the same pixels of each row
// (detail::thin_row_range); lanes outside the range but inside the image add nothing (alpha <= 0
// off the footprint), so they need no mask; lanes past the image's right edge are masked.
bool ThinStreakRows(const detail::ThinStreak& t) {
  const hn::CappedTag<float, kStreakAccumLanes> d;
  using V = hn::Vec<decltype(d)>;
  const std::size_t N = hn::Lanes(d);
  constexpr std::size_t L = kStreakAccumLanes, LF = kStreakAccumFloats;
  const V one = hn::Set(d, 1.f), zero = hn::Zero(d), half = hn::Set(d, 0.5f), minus_one = hn::Set(d, -1.f);
  const V tiny = hn::Set(d, 1e-7f), iota = hn::Iota(d, 0.f);
  const V vx0 = hn::Set(d, t.x0), vux = hn::Set(d, t.ux), vuy = hn::Set(d, t.uy), vL = hn::Set(d, t.L);
  const V vinv_L = hn::Set(d, t.inv_L), vw = hn::Set(d, t.w), vz = hn::Set(d, t.z);
  const V rgb[3] = {hn::Set(d, t.rgb[0]), hn::Set(d, t.rgb[1]), hn::Set(d, t.rgb[2])};
  const V right_edge = hn::Set(d, float(t.width));
  const bool long_streak = t.L > 1e-3f;
  const auto tent = [&](V u) {
    const V c = hn::Min(hn::Max(u, minus_one), one);
    return hn::Sub(hn::Add(half, c), hn::Mul(hn::Mul(half, c), hn::Abs(c)));
  };
  bool touched = false;
  for (int y = t.row0; y < t.row1; ++y) {
    int ia, ib;
    if (!detail::thin_row_range(t, y, ia, ib)) continue;
    const float qy = float(y) + 0.5f;
    const V sy = hn::Set(d, (qy - t.y0) * t.uy), py = hn::Set(d, (qy - t.y0) * t.ux);
    const float* depth_row = t.depth + std::size_t(y) * std::size_t(t.width);
    const std::size_t acc_row = std::size_t(y - t.acc_r0) * t.stride;
    for (std::size_t x = std::size_t(ia) / N * N; x <= std::size_t(ib); x += N) {
      const V xs = hn::Add(hn::Set(d, float(x)), iota);
      const V dx = hn::Sub(hn::Add(xs, half), vx0);
      const V s = hn::Add(hn::Mul(dx, vux), sy);
      const V p = hn::Sub(hn::Mul(dx, vuy), py);
      const V along = long_streak ? hn::Mul(hn::Sub(tent(s), tent(hn::Sub(s, vL))), vinv_L)
                                  : hn::Max(zero, hn::Sub(one, hn::Abs(s)));
      V a = hn::Mul(hn::Mul(vw, hn::Sub(one, hn::Abs(p))), along);  // <= 0 off the streak
      const bool inside = x + N <= std::size_t(t.width);
      V depth;
      if (inside) {
        depth = hn::LoadU(d, depth_row + x);
      } else {  // the row's last pixels: lanes past its end read no depth and take no part
        HWY_ALIGN float tail[kStreakAccumLanes];
        for (std::size_t l = 0; l < N; ++l) tail[l] = x + l < std::size_t(t.width) ? depth_row[x + l] : 0.f;
        depth = hn::Load(d, tail);
      }
      auto keep = hn::AndNot(hn::Lt(depth, vz), hn::Gt(a, tiny));
      if (!inside) keep = hn::And(keep, hn::Lt(xs, right_edge));
      a = hn::IfThenElseZero(keep, hn::Min(a, one));
      float* g = t.acc + ((acc_row + x) / L) * LF + x % L;
      hn::StoreU(hn::Mul(hn::LoadU(d, g), hn::Sub(one, a)), d, g);
      hn::StoreU(hn::Add(hn::LoadU(d, g + L), a), d, g + L);
      for (std::size_t k = 0; k < 3; ++k)
        hn::StoreU(hn::Add(hn::LoadU(d, g + (2 + k) * L), hn::Mul(a, rgb[k])), d, g + (2 + k) * L);
      touched |= !hn::AllFalse(d, keep);
    }
  }
  return touched;
}

}  // namespace hydrolux::rain::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
#include "src/core/simd_dispatch.hpp"

namespace hydrolux::rain {

HYDROLUX_SIMD_EXPORT(CompositeRgbRow);
HYDROLUX_SIMD_EXPORT(ThinStreakRows);

namespace detail {
void composite_rgb_row(const CompositeRow& r) { HYDROLUX_SIMD_DISPATCH(CompositeRgbRow)(r); }
bool thin_streak_rows(const ThinStreak& t) { return HYDROLUX_SIMD_DISPATCH(ThinStreakRows)(t); }
}  // namespace detail

}  // namespace hydrolux::rain
#endif  // HWY_ONCE
