#pragma once
// The equilibrium shape of a falling rain drop (Garg & Nayar 2004, section 2.1, seed 000; after
// K. V. Beard and C. Chuang, J. Atmos. Sci. 44, 1509, 1987): a cosine series about the sphere of
// equal volume,
//
//   r(theta) = a (1 + sum_{n=0}^{10} c_n cos(n theta)),
//
// a the equivalent-volume radius and theta the polar angle measured from the direction of fall, so
// theta = 0 points straight down at the drop's base. Aerodynamic pressure flattens the base and
// the sides bulge; surface tension keeps the top rounded. c_0 carries the volume (the other terms
// alone would change it at first and second order); c_1 shifts the shape along the axis.
//
// Coefficients: Chuang & Beard (1990, J. Atmos. Sci. 47, 1374, Table 1, uncharged drops in no
// field; the same model as Beard & Chuang 1987, whose own table was not available), tabulated for
// equivalent radii 0.5-4.5 mm (data/drop/chuang_beard_1990_shape.csv, with the provenance). The
// source measures theta from the drop's top; the table here has its odd coefficients negated
// (cos(n (pi - t)) = (-1)^n cos(n t)) so theta = 0 is the base, checked by the shape itself: the
// flattened base is the end nearer the origin, r(0) < r(pi), and the flatter one (larger radius of
// curvature) for a <= 2.75 mm. Between rows each coefficient is interpolated linearly in radius.
//
// Validity: radii 0.5-4.5 mm (DomainError "radius_m" outside). At 0.5 mm the shape departs from
// the sphere by at most 1.6% in radius (axis ratio 0.984), and the departure shrinks roughly as
// a^2 below that (c_2 goes from -0.0210 at 0.75 mm to -0.0083 at 0.5 mm), so smaller drops are
// spheres to better than 1.6%. Drops above ~4.5 mm radius are rare and break up.
//
// Checks (tests/drop/test_shape.cpp): the axis ratio from these coefficients follows Beard &
// Chuang's own axis-ratio polynomial (as quoted by Andsager, Beard & Laird 1999, J. Atmos. Sci. 56,
// 2673) within 0.0107 for equivalent diameters D = 1-7 mm (1.6% at most; the coefficients give
// the flatter drop for D = 2-5.5 mm, the rounder above 6 mm) and within 0.002 for D <= 2 mm; the
// volume is 4/3 pi a^3 within 4.3e-4 at every table row but a = 4 mm (2.5e-3 low, see the
// table's notes).
#include <array>

#include "hydrolux/core/vec.hpp"

namespace hydrolux::scatter {

inline constexpr int kShapeTerms = 11;  // c_0 .. c_10

struct DropShape {
  double radius_m = 0;                 // a, the equivalent-volume radius
  std::array<double, kShapeTerms> c{};  // c_0 .. c_10, dimensionless, theta from the fall direction
};

// The shape of a drop of equivalent radius radius_m, coefficients interpolated linearly in radius
// between the table's rows. DomainError ("radius_m") outside drop_shape_radius_range_m().
DropShape drop_shape(double radius_m);
std::array<double, 2> drop_shape_radius_range_m();  // {0.5e-3, 4.5e-3}

// r(theta) in metres, theta in radians from the fall direction (0 = base, pi = top).
double shape_radius(const DropShape& s, double theta);
// dr/dtheta, metres per radian.
double shape_radius_derivative(const DropShape& s, double theta);

// Extents of the axisymmetric drop: vertical = highest minus lowest point (r(0) + r(pi) whenever
// the poles are the extreme points, as in every row of the table); horizontal = twice the largest
// distance of the profile from the axis, max over theta of r sin(theta), which lies a few degrees
// below the equator (towards the base), not at theta = pi/2.
double vertical_extent_m(const DropShape& s);
double horizontal_extent_m(const DropShape& s);
// Vertical over horizontal extent: 1 for a sphere, < 1 for the flattened drop.
double axis_ratio(const DropShape& s);
// (2 pi / 3) int_0^pi r^3 sin(theta) dtheta, by Gauss-Legendre quadrature in cos(theta) (exact for
// the degree-30 polynomial r^3 is in cos(theta)).
double volume_m3(const DropShape& s);

// World frame: +y is up and the drop falls along -y, so theta = 0 is the -y direction and
// cos(theta) = -unit_dir.y. The distance from the drop's centre (the series' origin) to its surface
// along unit_dir, metres; cos(n theta) by the Chebyshev recurrence in cos(theta), no trigonometric
// calls. unit_dir must have length 1.
double shape_radius_toward(const DropShape& s, const Vec3& unit_dir);
// The outward unit normal of the surface at the point along unit_dir (same frame).
Vec3 shape_normal_toward(const DropShape& s, const Vec3& unit_dir);

}  // namespace hydrolux::scatter
