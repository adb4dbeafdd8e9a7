#pragma once
// The rainbow angle of an oblate spheroid at one point of the bow by exact 3-D ray optics.
//
// The plane-section method (ellipse_rainbow.hpp) keeps the rays in the scattering plane of the
// point. That is exact where the plane is a plane of symmetry of the drop (it contains the drop's
// axis, or is normal to it); elsewhere the rays that reach the point enter the drop off the plane
// and the section's rainbow angle is off by an error of second order in the flattening (several
// degrees for axis ratios below 0.9 between the top and the side of the bow: docs/non-spherical.md).
//
// Here the rays are traced in three dimensions through the spheroid (refraction and reflection at
// its true normal, vector Snell's law). A ray of the incident beam enters at the point (u, v) of
// the drop's shadow (u along the direction of the bow's point, v normal to the scattering plane);
// the rays that leave in the scattering plane of the point, on the observer's side, form a curve
// v(u), and the bow's edge is the extremum of the scattering angle along it (the fold of the map
// from the shadow to the sky: a minimum for the primary, a maximum for the secondary). It is found
// by Newton's method on that curve (finite-difference derivatives), each of its points by Newton's
// method on v, starting from the section's rainbow ray.
//
// Units and frame as spheroid_section's: lengths in units of the equal-volume radius, the drop's
// axis `axis` (world frame, +y up, need not be normalised), the light along (0, -sin e, cos e),
// position 0 at the top of the bow, pi/2 at its side; angles in radians.
#include <optional>

#include "hydrolux/core/vec.hpp"
#include "hydrolux/scatter/ellipse_rainbow.hpp"

namespace hydrolux::scatter {

struct SpheroidBow {
  double scattering_angle = 0;  // theta of the 3-D edge
  double u = 0, v = 0;          // its ray's entry point in the shadow (u along the bow's direction)
  bool symmetric = false;       // the plane is a plane of symmetry: the section's angle, exact
};

// The 3-D edge of order p (2 primary, 3 secondary) at `position` for a spheroid of axis ratio q in
// [0.5, 1] and index n, searched from `section` (section_rainbow of spheroid_section(q, axis,
// sun_elevation, position)). Where the scattering plane is a plane of symmetry of the drop the
// section's angle is returned (it is the 3-D edge). nullopt when the search does not converge to a
// fold (the curve of rays leaving in the plane ends, or the extremum is not interior).
// The search follows the edge from the sphere's (Descartes' ray) as the flattening grows from 0 to
// 1 - q; with `seed`, the edge of a nearby drop (another index or a slightly different axis ratio,
// same axis and position), it starts there instead and follows from the sphere only if that fails.
std::optional<SpheroidBow> spheroid_bow(double n, int p, double axis_ratio, const Vec3& axis, double sun_elevation,
                                        double position, const SectionRainbow& section,
                                        const SpheroidBow* seed = nullptr);

}  // namespace hydrolux::scatter
