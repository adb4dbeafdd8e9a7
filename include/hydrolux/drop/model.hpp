#pragma once
// Garg & Nayar's geometric and photometric model of a rain drop (2004; seed 000, eqs. 6-19), for a
// drop seen on the optical axis (alpha = 0), with the drop a sphere of relative index mu.
//
// Frame: z points from the camera through the drop's centre towards the scene behind it. A visible
// surface point has normal polar angle theta_n in (pi/2, pi] and azimuth phi_n; the camera's ray
// meets it at incidence i = pi - theta_n and refracts to q = asin(sin i / mu). Its image lies at
// rho = m a sin(theta_n) = m a sin(i) from the drop's image centre (m the magnification), so
// rho / (m a) = sin(i) runs from 0 at the centre to 1 at the rim.
// Directions of the scene each path sees, as polar angle from +z (0: straight behind the drop) and
// azimuth:
//   refraction (eq. 8, 11):   theta_r = 2 (i - q),                 phi_r = phi_n + pi
//   reflection (eq. 13):      theta_s = 2 theta_n - pi,            phi_s = phi_n
//   N internal (eq. 16):      theta_p = 2 (i - q) + N (pi - 2 q),  phi_p = phi_n + pi
// with angles past pi folded back over the pole (azimuth + pi). The paper writes phi_p = phi_n with
// theta_p as a signed in-plane angle; tests/drop/test_model.cpp checks these directions against an
// exact vector ray trace of the sphere. Radiance transfer with k = k(i, mu) the unpolarised Fresnel reflectance
// (eqs. 12, 15, 18): R = (1 - k)^2, S = k, P_N = k^N (1 - k)^2 (the mu^2 and 1/mu^2 radiance factors
// of entry and exit cancel); composite (eq. 19) L = R Le(r) + S Le(s) + sum_N P_N Le(p_N).
#include <vector>

#include "hydrolux/core/vec.hpp"

namespace hydrolux::drop {

struct Direction {
  double theta = 0;  // polar angle from +z, radians, in [0, pi]
  double phi = 0;    // azimuth, radians
};

struct DropPaths {
  Direction refraction, reflection;
  std::vector<Direction> internal;  // N = 1..n_internal
  double R = 0, S = 0;              // radiance transfer of refraction and reflection
  std::vector<double> P;            // of N internal reflections
};

// The paths through the drop for the surface point with normal (theta_n, phi_n); theta_n in
// [pi/2, pi], mu > 1, n_internal in [0, 20]. DomainError otherwise.
DropPaths drop_paths(double theta_n, double phi_n, double mu, int n_internal = 2);

// The same for the image point at normalised radius rho = sin(i) in [0, 1] (azimuth 0).
DropPaths drop_paths_at_rho(double rho, double mu, int n_internal = 2);

// The same paths in vector form, for any viewing direction: the drop seen off the optical axis
// (the paper's alpha), as a perspective camera sees every pixel. `view` is the unit direction from
// the camera to the surface point, `normal` the outward unit normal there (view . normal < 0). Each
// path stays in the plane of view and normal; it leaves turned from `view` towards -n_perp (n_perp
// the part of the normal across the view) by the path's deflection: 2 (i - q) for refraction, plus
// N (pi - 2 q) for N internal reflections (the angles of eqs. 8 and 16 with alpha = 0 in this
// plane); the reflection is the mirror direction. Exact for a sphere and a distant scene.
struct DropRays {
  Vec3 refraction, reflection;
  std::vector<Vec3> internal;  // N = 1..n_internal
  double R = 0, S = 0;
  std::vector<double> P;
};
DropRays drop_rays(const Vec3& view, const Vec3& normal, double mu, int n_internal = 2);

// The drop's field of view: the full cone of scene directions the refraction mapping reaches,
// 2 theta_r at the rim = 2 (pi - 2 asin(1/mu)); 165.6 degrees for water (the paper: about 165).
double field_of_view_deg(double mu);

// Figure 4 of the paper: radiance of each path against rho for a uniform environment (Le = 1).
struct RadianceProfile {
  std::vector<double> rho, refraction, reflection;
  std::vector<std::vector<double>> internal;  // [N - 1][sample]
  double fov_deg = 0;
};
RadianceProfile radiance_profile(double mu, int samples, int n_internal = 2);

}  // namespace hydrolux::drop
