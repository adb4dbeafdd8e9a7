#include "hydrolux/drop/model.hpp"

#include <algorithm>
#include <cmath>

#include "hydrolux/core/error.hpp"
#include "hydrolux/core/math.hpp"
#include "hydrolux/drop/params.hpp"
#include "hydrolux/optics/fresnel.hpp"

namespace hydrolux::drop {

namespace {
constexpr const char* kContext = "the Garg & Nayar drop model";

void check_mu(double mu) { require_in_range("mu", mu, 1.0 + 1e-9, 10.0, kContext); }

// n_internal's range is the drop render's declared one (drop/params.hpp).
void check_internal(int n_internal) {
  static const Param& p = drop_render_param("internal");
  require_in_range("n_internal", n_internal, p.lo, p.hi, kContext);
}

// Polar angle folded into [0, pi] with the azimuth flipped when it passes a pole, azimuth in
// [0, 2 pi).
Direction normalised(double theta, double phi) {
  theta = std::fmod(theta, 2 * kPi<>);
  if (theta < 0) theta += 2 * kPi<>;
  if (theta > kPi<>) {
    theta = 2 * kPi<> - theta;
    phi += kPi<>;
  }
  phi = std::fmod(phi, 2 * kPi<>);
  if (phi < 0) phi += 2 * kPi<>;
  return {theta, phi};
}
}  // namespace

DropPaths drop_paths(double theta_n, double phi_n, double mu, int n_internal) {
  check_mu(mu);
  require_in_range("theta_n", theta_n, kPi<> / 2, kPi<>, kContext);
  check_internal(n_internal);
  const double i = kPi<> - theta_n;                 // incidence angle (alpha = 0)
  const double q = safe_asin(std::sin(i) / mu);     // refraction angle, Snell
  const double k = optics::fr_dielectric(std::cos(i), mu);  // unpolarised Fresnel k(i, mu)
  DropPaths p;
  const double deflection = 2 * (i - q);            // eq. 8: total deflection of the refracted ray
  p.refraction = normalised(deflection, phi_n + kPi<>);        // eq. 11
  p.reflection = normalised(2 * theta_n - kPi<>, phi_n);        // eq. 13
  p.R = sqr(1 - k);                                              // eq. 12
  p.S = k;                                                       // eq. 15
  for (int n = 1; n <= n_internal; ++n) {
    // eq. 16: each internal reflection turns the ray by pi - 2q more; the chord count decides on
    // which side of the axis it leaves (phi_n + pi after an even number of reflections).
    p.internal.push_back(normalised(deflection + n * (kPi<> - 2 * q), phi_n + kPi<>));
    p.P.push_back(std::pow(k, n) * sqr(1 - k));                   // eq. 18
  }
  return p;
}

DropPaths drop_paths_at_rho(double rho, double mu, int n_internal) {
  require_in_range("rho", rho, 0.0, 1.0, kContext);
  return drop_paths(kPi<> - std::asin(rho), 0.0, mu, n_internal);
}

DropRays drop_rays(const Vec3& view, const Vec3& normal, double mu, int n_internal) {
  check_mu(mu);
  check_internal(n_internal);
  // The point must face the camera; rounding just outside [0, 1] is clamped.
  const double raw_cos_i = -glm::dot(view, normal);
  require_in_range("cos_i", raw_cos_i, -1e-12, 1.0 + 1e-12, kContext);
  const double cos_i = std::clamp(raw_cos_i, 0.0, 1.0);
  const double i = std::acos(cos_i);
  const double q = safe_asin(std::sin(i) / mu);
  const double k = optics::fr_dielectric(cos_i, mu);
  // The in-plane unit vector across the view, pointing away from the normal (towards the axis
  // through the drop's centre); any perpendicular at normal incidence, where no turn is made.
  Vec3 across = -(normal + cos_i * view);
  const double len = glm::length(across);
  if (len > 1e-300) {
    across /= len;
  } else {
    across = std::abs(view.x) < 0.9 ? glm::normalize(glm::cross(view, Vec3{1, 0, 0}))
                                    : glm::normalize(glm::cross(view, Vec3{0, 1, 0}));
  }
  const auto turned = [&](double angle) { return std::cos(angle) * view + std::sin(angle) * across; };
  DropRays r;
  const double deflection = 2 * (i - q);
  r.refraction = turned(deflection);
  r.reflection = view + 2 * cos_i * normal;
  r.R = sqr(1 - k);
  r.S = k;
  for (int n = 1; n <= n_internal; ++n) {
    r.internal.push_back(turned(deflection + n * (kPi<> - 2 * q)));
    r.P.push_back(std::pow(k, n) * sqr(1 - k));
  }
  return r;
}

double field_of_view_deg(double mu) {
  check_mu(mu);
  return rad_to_deg(2 * (kPi<> - 2 * std::asin(1 / mu)));
}

RadianceProfile radiance_profile(double mu, int samples, int n_internal) {
  require_in_range("samples", samples, 2, 1000000, kContext);
  RadianceProfile out;
  out.internal.resize(std::size_t(std::max(0, n_internal)));
  out.fov_deg = field_of_view_deg(mu);
  for (int s = 0; s < samples; ++s) {
    const double rho = double(s) / double(samples - 1);
    const auto p = drop_paths_at_rho(rho, mu, n_internal);
    out.rho.push_back(rho);
    out.refraction.push_back(p.R);
    out.reflection.push_back(p.S);
    for (std::size_t n = 0; n < p.P.size(); ++n) out.internal[n].push_back(p.P[n]);
  }
  return out;
}

}  // namespace hydrolux::drop
