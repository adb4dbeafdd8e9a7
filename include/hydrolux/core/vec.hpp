#pragma once
// Vectors (glm) and the local shading frame used by all BSDF code.
//
// Convention (as pbrt): in the local frame the surface normal is +z; directions are unit vectors
// pointing away from the surface; cos(theta) = w.z, so a direction with w.z < 0 lies below the
// surface (inside the medium the normal points out of).
#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "hydrolux/core/math.hpp"

namespace hydrolux {

template <typename Float>
using Vec3T = glm::vec<3, Float, glm::defaultp>;
using Vec3 = Vec3T<double>;

template <typename Float>
constexpr Float cos_theta(const Vec3T<Float>& w) noexcept {
  return w.z;
}
template <typename Float>
constexpr Float abs_cos_theta(const Vec3T<Float>& w) noexcept {
  return w.z < 0 ? -w.z : w.z;
}
template <typename Float>
constexpr Float cos2_theta(const Vec3T<Float>& w) noexcept {
  return w.z * w.z;
}
template <typename Float>
constexpr Float sin2_theta(const Vec3T<Float>& w) noexcept {
  return std::max(Float(0), Float(1) - cos2_theta(w));
}
template <typename Float>
inline Float tan2_theta(const Vec3T<Float>& w) noexcept {
  return sin2_theta(w) / cos2_theta(w);
}
// cos(phi) and sin(phi) of the direction's azimuth; (1, 0) at the pole.
template <typename Float>
inline Float cos_phi(const Vec3T<Float>& w) noexcept {
  const Float s = std::sqrt(sin2_theta(w));
  return s == 0 ? Float(1) : std::clamp(w.x / s, Float(-1), Float(1));
}
template <typename Float>
inline Float sin_phi(const Vec3T<Float>& w) noexcept {
  const Float s = std::sqrt(sin2_theta(w));
  return s == 0 ? Float(0) : std::clamp(w.y / s, Float(-1), Float(1));
}
template <typename Float>
constexpr bool same_hemisphere(const Vec3T<Float>& a, const Vec3T<Float>& b) noexcept {
  return a.z * b.z > 0;
}
// Unit vector from spherical angles (theta from +z, phi from +x).
template <typename Float>
inline Vec3T<Float> spherical_direction(Float theta, Float phi) noexcept {
  const Float st = std::sin(theta);
  return {st * std::cos(phi), st * std::sin(phi), std::cos(theta)};
}
// v flipped, if needed, to lie in the hemisphere around n.
template <typename Float>
constexpr Vec3T<Float> face_forward(const Vec3T<Float>& v, const Vec3T<Float>& n) noexcept {
  return glm::dot(v, n) < 0 ? -v : v;
}

}  // namespace hydrolux
