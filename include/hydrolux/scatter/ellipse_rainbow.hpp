#pragma once
// The rainbow of an oblate drop, by the plane-section method: the light that reaches a point of
// the bow travels in one scattering plane; the drop's section by that plane (through its centre)
// is an ellipse, and the rays of order p are traced exactly through that ellipse in two
// dimensions. Their deviation's extremum is the section's rainbow ray: its angle, its curvature
// q = (1/2) |d^2 Theta / db^2|, the Fresnel factors along its actual path (entry, p - 1 internal
// reflections and exit all at different angles, unlike in a circle) and its internal path length.
// Airy theory of that fold (airy.hpp, with these constants in place of Descartes') gives the
// wave-optics profile: the bow, its width and its supernumeraries. The method and its domain are
// in docs/non-spherical.md.
//
// References:
// - A. F. Moebius, Abh. Math.-Phys. Kl. Saechs. Ges. Wiss. 30, 1 (1910): the shift of the bow for
//   flattened drops from their plane section.
// - J. A. Lock and G. P. Koennen, Appl. Opt. 56(19), G88 (2017): ray theory of the rainbow of a 2-D
//   ellipse at any tilt (the Moebius shift against the ellipse's orientation).
// - M. Haussmann, Appl. Opt. 54(4), B117 (2015): the plane-section Airy profile of flattened drops
//   and a twinned rainbow reconstructed from two drop populations.
//
// Units: lengths in units of the radius of the sphere of equal volume (so x = k a_eq is the usual
// size parameter and a circle of radius 1 is the sphere); angles in radians.
//
// Approximations (docs/non-spherical.md): (1) rays stay in the section (exact when the section is a
// plane of symmetry of the drop: the top and the feet of the bow with the drop's axis vertical;
// elsewhere the section's rainbow angle is off at second order in the flattening, several degrees
// below Q = 0.9: spheroid_bow.hpp finds the 3-D angle, which the Lee tables use); (2) the spread of the rays out
// of the plane is taken from the section's rainbow ray as in a sphere (the factor b_R / sin
// theta_R), which sets the brightness and not the angles; (3) Airy theory of a single fold, which
// fails where the flattening makes the fold meet another caustic (the hyperbolic umbilic: Marston
// and Trinh, Nature 312, 529, 1984), at axis ratios below about 0.75 for the primary.
#include <optional>

#include "hydrolux/core/vec.hpp"
#include "hydrolux/scatter/mie.hpp"

namespace hydrolux::scatter {

// An ellipse centred on the origin of the plane's frame (X along the incident light, Y the other
// in-plane direction: the side of the antisolar point's direction the observer sees the point at).
// Semi-axis semi_u lies along (cos tilt, sin tilt), semi_v along (-sin tilt, cos tilt).
struct EllipseSection {
  double semi_u = 1, semi_v = 1;  // in units of the equal-volume radius
  double tilt = 0;                // rad
};

// The section of an oblate spheroid of axis ratio q (polar / equatorial, in (0, 1]; volume that of
// the unit sphere: equatorial semi-axis q^(-1/3), polar q^(2/3)) whose symmetry axis points along
// `axis` (world frame: +y up; need not be normalised), by the scattering plane of the point at
// position angle `position` (0 at the top of the bow, pi/2 at its side, pi at the bottom) when the
// sun is at elevation `sun_elevation` (the light travels along (0, -sin e, cos e)).
// The section's semi_u runs along the projection of the drop's axis on the plane.
EllipseSection spheroid_section(double axis_ratio, const Vec3& axis, double sun_elevation, double position);

// One ray of order p >= 1 entering the section at height b (Y) travelling along +X, traced through
// the ellipse. `exits` is false if the ray misses the drop or is totally reflected where it should
// leave.
struct SectionRay {
  bool exits = false;
  double out_x = 0, out_y = 0;       // the leaving direction (unit)
  double power_perpendicular = 0;    // Fresnel power factor along the path, polarisation normal
  double power_parallel = 0;         //   to the plane (S1) and in it (S2)
  double path = 0;                   // geometric length inside the drop, units of a_eq
};
SectionRay trace_section(double n, int p, const EllipseSection& e, double b);

// The section's rainbow ray of order p (2 primary, 3 secondary) on the side the observer sees
// (leaving with out_y < 0), and the constants of its Airy profile. Returns nullopt when the
// deviation has no interior extremum on that side (no bow of this order for this section).
struct SectionRainbow {
  int p = 0;
  double impact = 0;            // b_R, signed height of the rainbow ray
  double scattering_angle = 0;  // theta_R
  int side = 1;                 // +1: rays at theta > theta_R (primary); -1: theta < theta_R
  double curvature = 0;         // q = (1/2) |d^2 theta / db^2| at b_R
  double power_perpendicular = 0, power_parallel = 0;  // |eps_1|^2, |eps_2|^2 along the ray
  double path = 0;              // internal path length of the rainbow ray
};
std::optional<SectionRainbow> section_rainbow(double n, int p, const EllipseSection& e);

// Airy theory of the section's bow (airy.hpp's amplitude with these constants): the intensities
// i1 = |S1|^2, i2 = |S2|^2 in the B&H normalisation at scattering angle theta for size parameter
// x = k a_eq and absorption kappa = Im m (amplitude factor exp(-x kappa path)).
struct SectionAiry {
  double theta_r = 0, scale = 0, side = 1;
  double weight_perpendicular = 0, weight_parallel = 0;  // |eps_j|^2 * amplitude^2
};
SectionAiry section_airy(const SectionRainbow& r, double x, double kappa);
// The unpolarised intensity (i1 + i2) / 2.
double section_airy_intensity(const SectionAiry& a, double theta);

}  // namespace hydrolux::scatter
