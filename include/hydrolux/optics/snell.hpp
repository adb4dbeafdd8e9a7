#pragma once
// Snell's law: reflection and refraction directions, critical and Brewster angles.
//
// Conventions: directions are unit vectors pointing AWAY from the surface (the incident direction
// wi points back toward where the light came from). The unit normal n points to the "above" side;
// eta = n_below / n_above is the relative index of refraction. refract() accepts wi on either side
// and reports total internal reflection as an empty optional, never as a made-up direction.
#include <optional>

#include "hydrolux/core/vec.hpp"

namespace hydrolux::optics {

// Mirror direction of wo about n (both away from the surface; |result| = 1).
template <typename Float>
constexpr Vec3T<Float> reflect(const Vec3T<Float>& wo, const Vec3T<Float>& n) noexcept {
  return -wo + Float(2) * glm::dot(wo, n) * n;
}

template <typename Float>
struct Refraction {
  Vec3T<Float> wt;  // transmitted direction, unit, on the far side of the surface from wi
  Float eta;        // relative index along the path taken: n_t / n_i
  Float cos_t;      // cosine of the refraction angle, in [0, 1]
};

// Vector form of Snell's law: wt = -wi / eta + (cos_i / eta - cos_t) n, with eta = n_t / n_i and n
// on wi's side (n_i sin(theta_i) = n_t sin(theta_t)). Empty on total internal reflection.
template <typename Float>
std::optional<Refraction<Float>> refract(const Vec3T<Float>& wi, Vec3T<Float> n, Float eta) noexcept {
  Float cos_i = glm::dot(n, wi);
  if (cos_i < 0) {  // wi is below: the light goes from the "below" medium to the "above" one
    eta = Float(1) / eta;
    cos_i = -cos_i;
    n = -n;
  }
  const Float sin2_i = std::max(Float(0), Float(1) - cos_i * cos_i);
  const Float sin2_t = sin2_i / (eta * eta);
  if (sin2_t >= Float(1)) return std::nullopt;
  const Float cos_t = std::sqrt(Float(1) - sin2_t);
  return Refraction<Float>{-wi / eta + (cos_i / eta - cos_t) * n, eta, cos_t};
}

// Refraction angle theta_t (radians) for incidence theta_i in [0, pi/2] from index n_i into n_t;
// empty on total internal reflection.
template <typename Float>
std::optional<Float> refraction_angle(Float theta_i, Float n_i, Float n_t) noexcept {
  const Float sin_t = n_i * std::sin(theta_i) / n_t;
  if (sin_t >= Float(1)) return std::nullopt;
  return std::asin(sin_t);
}

// Critical angle (radians) for light going from n_i into a less dense n_t < n_i; empty otherwise.
template <typename Float>
std::optional<Float> critical_angle(Float n_i, Float n_t) noexcept {
  if (!(n_t < n_i)) return std::nullopt;
  return std::asin(n_t / n_i);
}

// Brewster's angle (radians) from n_i into n_t: R_p vanishes there, tan(theta_B) = n_t / n_i.
template <typename Float>
Float brewster_angle(Float n_i, Float n_t) noexcept {
  return std::atan2(n_t, n_i);
}

}  // namespace hydrolux::optics
