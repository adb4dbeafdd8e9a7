#pragma once
// Geometric optics with interference for a homogeneous sphere: every ray of order p that leaves the
// drop in a given direction, its complex amplitude, and the coherent sum over orders, optionally
// with Fraunhofer diffraction. The equations and their derivation are in docs/rainbow-theories.md.
//
// References:
// - H. C. van de Hulst, "Light Scattering by Small Particles" (1957), ch. 12 (sections 12.2-12.3:
//   deviation, divergence factor D, focal lines) and ch. 13 (section 13.1: Descartes' rainbow).
// - E. A. Hovenac and J. A. Lock, J. Opt. Soc. Am. A 9, 781 (1992): the Debye series term p and
//   its geometric-optics limit.
//
// Conventions: those of hydrolux/scatter/mie.hpp (Bohren & Huffman amplitudes; S1 perpendicular,
// S2 parallel; theta the scattering angle, 0 forward; x = 2 pi a / lambda; m = n + i k relative
// index, time dependence exp(-i omega t)); Fresnel amplitudes of hydrolux/optics/fresnel.hpp.
//
// Ray order p: p = 0 external reflection, p = 1 transmission straight through, p >= 2 transmission
// after p - 1 internal reflections (p = 2 primary rainbow, p = 3 secondary). A ray enters at
// incidence angle theta_i (impact parameter b = sin theta_i, in units of the radius a) and is
// refracted to theta_t, n sin theta_t = sin theta_i. Its deviation is
//     Theta_0 = pi - 2 theta_i,    Theta_p = 2 theta_i - 2 p theta_t + (p - 1) pi   (p >= 1),
// and it reaches the scattering angle theta in [0, pi] when Theta_p = +-theta (mod 2 pi).
//
// Amplitude of one ray, per polarisation j (1 = perpendicular, 2 = parallel):
//     S_j = x eps_j sqrt(D) exp(i delta) (-i)^(N + 1)
// - eps_j: Fresnel factors, r_j for p = 0 and t_j t'_j (r'_j)^(p-1) = (1 - r_j^2)(-r_j)^(p-1)
//   for p >= 1 (Stokes relations, Hecht section 4.10), r_j, t_j the external amplitudes at theta_i;
// - D = sin theta_i cos theta_i / (sin theta |dTheta_p/dtheta_i|), the divergence factor
//   (van de Hulst eq. 12.23); D = 1/4 for p = 0 at every angle;
// - delta = 2 x (p m cos theta_t - cos theta_i): the optical path relative to a ray through the
//   centre, in the exp(-i omega t) convention (van de Hulst's 2x (sin tau - p m sin tau') with its
//   sign reversed for his exp(+i omega t)); theta_t from Re m, so that for absorbing m the
//   amplitude decays as exp(-2 x Im(m) cos theta_t) along each of the p chords;
// - N: the focal lines the ray passes (tangential caustics and crossings of the symmetry axis),
//   each a phase -pi/2 in this time convention (van de Hulst section 12.3);
// - the extra (-i) is B&H's 1/(-i k r) in E_s = exp(ikr)/(-ikr) S E_i.
// Then |S_j|^2 = x^2 eps_j^2 D: for p = 0, i = x^2 R / 4 at every angle, and the rays of all
// orders together scatter the geometric cross-section pi a^2 (Q_sca = 1 without diffraction).
//
// Validity: x >> 1 and away from caustics, where D diverges: the rainbow angles (use
// scatter/airy.hpp; within 1e-12 rad of a rainbow's deviation, where the two merging rays cannot
// be told apart in double precision, they are left out), and the forward and backward axis
// (glories). Exactly on the axis (theta within 1e-9 rad of 0 or pi) only the central ray
// theta_i = 0 is kept, with its finite limit D = 1 / (dTheta/dtheta_i)^2; rays from theta_i > 0
// that focus onto the axis (the glory caustic, infinite in geometric optics) are left out there.
// Complex m: the ray geometry uses Re m, the Fresnel factors and the internal attenuation use m
// (van de Hulst section 14.2); valid for weak absorption, Im m << Re m - 1.
// Checked order by order against the Debye series (p = 1-3, x = 1e3 and 1e4, water):
// tests/scatter/test_claims_rainbow.cpp, docs/rainbow-theories.md.
#include <complex>
#include <span>
#include <vector>

#include "hydrolux/scatter/mie.hpp"

namespace hydrolux::scatter {

// Valid domain (DomainError outside): 1 < Re m <= 10 (rays enter a denser drop), 0 <= Im m <= 1,
// x in [1e-3, 1e7], ray orders 0..kMaxRayOrder, theta in [0, pi].
inline constexpr double kMinGeometricIndex = 1.000001;
inline constexpr double kMaxGeometricIndex = 10.0;
inline constexpr double kMaxGeometricSizeParameter = 1e7;
inline constexpr int kMaxRayOrder = 1000;

// Deviation Theta_p(theta_i) in radians (header comment) for a real index n > 1, and its
// derivative dTheta_p / dtheta_i = 2 - 2 p cos theta_i / (n cos theta_t) (p >= 1), -2 (p = 0).
double deviation(double n, int p, double theta_i);
double deviation_derivative(double n, int p, double theta_i);

// The Fresnel factors eps_j of a ray of order p entering at theta_i (radians, [0, pi/2]):
// perpendicular (s, S1) and parallel (p, S2). Real for real m; |eps|^2 is the fraction of the
// ray's power that leaves in order p.
struct RayFresnelFactors {
  Complex perpendicular, parallel;
};
RayFresnelFactors ray_fresnel_factors(Complex m, int p, double theta_i);

// The number N of focal lines (tangential caustics plus crossings of the symmetry axis) that a ray
// of order p entering at theta_i passes between entering and the far field; derived in
// docs/rainbow-theories.md. N_tangential = p - [dTheta_p/dtheta_i < 0]; N_axial counts where the
// ray's path crosses the axis. The central ray (theta_i -> 0) takes the limit from theta_i > 0.
int focal_lines(double n, int p, double theta_i);

// One ray that leaves the drop at the requested scattering angle.
struct GeometricRay {
  int p = 0;
  double theta_i = 0;     // incidence angle, rad (impact parameter b = sin theta_i)
  double theta_t = 0;     // refraction angle, rad (from Re m)
  double deviation = 0;   // Theta_p(theta_i), rad
  double divergence = 0;  // D (dimensionless)
  int focal_lines = 0;    // N
  Complex phase_path;     // delta = 2 x (p m cos theta_t - cos theta_i); complex for absorbing m
  Complex s1, s2;         // the ray's amplitudes (B&H normalisation)
};

// Every ray of order p that reaches theta (radians, [0, pi]), found by safeguarded Newton on each
// branch of theta_i where Theta_p is monotonic (p >= 2 has two, split at the rainbow ray).
// Order of the result: by branch, then by theta_i.
std::vector<GeometricRay> geometric_rays(Complex m, double x, int p, double theta);

// Sum of the rays of one order p at each theta (s1, s2 the same size as theta_rad).
void geometric_amplitudes_order(Complex m, double x, int p, std::span<const double> theta_rad,
                                std::span<Complex> s1, std::span<Complex> s2);

// Coherent sum over p = 0..p_max, plus Fraunhofer diffraction if `diffraction` is set.
void geometric_amplitudes(Complex m, double x, int p_max, std::span<const double> theta_rad,
                          std::span<Complex> s1, std::span<Complex> s2, bool diffraction);

// Fraunhofer diffraction by the drop's projected disk, the same for S1 and S2 (van de Hulst
// section 8.31 in B&H normalisation): S = x^2 J1(x sin theta) / (x sin theta) for theta <= pi/2
// (S(0) = x^2 / 2, real and positive so that the optical theorem gives Q_ext = 2), 0 beyond.
// No obliquity factor. Integrated over the forward hemisphere it scatters pi a^2 more, for large x.
Complex fraunhofer_amplitude(double x, double theta);

// The rainbow (minimum-deviation) ray of order p >= 2, for 1 < n < p (DomainError otherwise).
// Descartes: cos^2 theta_i = (n^2 - 1) / (p^2 - 1) (van de Hulst eq. 13.1).
struct RainbowRay {
  int p = 0;
  double n = 0;
  double theta_i = 0, theta_t = 0;  // rad
  double impact_parameter = 0;      // b_R = sin theta_i
  double deviation = 0;             // Theta_p at the rainbow ray, rad (its minimum)
  double scattering_angle = 0;      // theta_R in [0, pi]
  // +1 if theta = Theta_p (mod 2 pi) near the bow (p = 2), -1 if theta = -Theta_p (p = 3): the lit
  // side, where rays exist, is sign * (theta - theta_R) > 0.
  int side = 1;
  // q = (1/2) d^2 Theta_p / db^2 at the ray (van de Hulst's h, section 13.21):
  // q = (p^2 - 1)^2 sqrt(p^2 - n^2) / (p^2 (n^2 - 1)^(3/2)).
  double curvature = 0;
};
RainbowRay rainbow_ray(double n, int p);

// theta_R, the geometric rainbow's scattering angle in radians; pi - theta_R is its angular radius
// around the antisolar point (42.08 degrees for n = 1.333, p = 2).
double rainbow_angle(double n, int p);

}  // namespace hydrolux::scatter
