#pragma once
// Small numeric helpers shared by every stage. Pure, header-only, templated on the scalar type.
#include <algorithm>
#include <cmath>
#include <numbers>

namespace hydrolux {

template <typename Float = double>
inline constexpr Float kPi = std::numbers::pi_v<Float>;

template <typename Float>
constexpr Float sqr(Float x) noexcept {
  return x * x;
}

template <typename Float>
constexpr Float deg_to_rad(Float deg) noexcept {
  return deg * (kPi<Float> / Float(180));
}

template <typename Float>
constexpr Float rad_to_deg(Float rad) noexcept {
  return rad * (Float(180) / kPi<Float>);
}

// sqrt and asin/acos that tolerate round-off just outside their domain.
template <typename Float>
inline Float safe_sqrt(Float x) noexcept {
  return std::sqrt(std::max(x, Float(0)));
}
template <typename Float>
inline Float safe_asin(Float x) noexcept {
  return std::asin(std::clamp(x, Float(-1), Float(1)));
}
template <typename Float>
inline Float safe_acos(Float x) noexcept {
  return std::acos(std::clamp(x, Float(-1), Float(1)));
}

}  // namespace hydrolux
