#pragma once
// Undoing a rain drop's distortion (Garg & Nayar 2004, section 5 and Figure 9; seed 000): the
// picture inside a drop is a wide-angle (about 165 degree) view of the world, squeezed and turned
// upside down by refraction. Inverting the refraction mapping of model.hpp turns it back into an
// ordinary perspective view, as from a pinhole camera placed at the drop.
//
// The forward mapping (model.hpp, drop on the optical axis, alpha = 0): the drop-image point at
// normalised radius rho = sin(i) and azimuth phi_n sees the scene direction at polar angle
// theta_r = 2 (i - q), q = asin(sin i / mu), from +z and azimuth phi_n + pi. Its inverse for a scene
// direction d at polar angle theta_r and azimuth phi_d:
//   - i from theta_r: with h = theta_r / 2 = i - q, Snell's law sin(q + h) = mu sin(q) gives
//     tan(q) = sin(h) / (mu - cos(h)), and i = q + h. theta_r grows monotonically with i (its
//     derivative 2 (1 - cos i / (mu cos q)) is positive for mu > 1), from 0 at the centre to
//     pi - 2 asin(1/mu) at the rim (82.8 degrees for water); directions further from +z are not
//     seen by refraction at all.
//   - rho = sin(i), at azimuth phi_n = phi_d + pi: the drop's picture is inverted through its
//     centre.
// In image coordinates (x to the right = world +x, y down = world -y) the point lies at
//   (x, y) = centre + rho R (-cos phi_d, +sin phi_d),   R the drop's image radius in pixels.
//
// Photometry (eq. 12): the refracted path carries the fraction (1 - k(i, mu))^2 of the scene
// radiance (k the unpolarised Fresnel reflectance; the mu^2 and 1/mu^2 factors of entry and exit
// cancel). Dividing by it recovers the scene radiance where refraction dominates the drop's
// brightness; near the rim the reflected and internally reflected paths, which the drop image also
// contains, take over (Figure 4) and the correction amplifies them.
//
// Resolution: d rho / d theta_r falls to zero at the rim (rho = sin i and d theta_r / d i = 2 there),
// so the outer field of view is packed into a thin ring of the drop image; an undistorted view is
// sharp near theta_r = 0 only.
#include <optional>
#include <span>

#include "hydrolux/core/image.hpp"
#include "hydrolux/core/params.hpp"
#include "hydrolux/core/vec.hpp"

namespace hydrolux::drop {

// Largest deflection of the refracted path, at the rim (i = pi/2): pi - 2 asin(1/mu), half the
// drop's field of view. mu in (1, 10]; DomainError "mu" otherwise.
double max_refraction_deflection(double mu);

// The incidence angle i in [0, pi/2] whose refracted path is deflected by theta_r = 2 (i - q(i)),
// theta_r in [0, max_refraction_deflection(mu)] (radians). DomainError "theta_r" or "mu" otherwise.
double incidence_for_deflection(double theta_r, double mu);

// Where the drop's image shows a scene direction by refraction.
struct DropImagePoint {
  double x = 0, y = 0;        // offset from the drop's image centre in units of its image radius,
                              // image axes (x right, y down); hypot(x, y) = rho = sin(i)
  double incidence = 0;       // i, radians
  double transmission = 0;    // (1 - k(i, mu))^2, eq. 12
};

// The drop-image point that sees unit direction `dir` (world frame, +z straight behind the drop),
// or nullopt if the direction lies outside the drop's field of view (theta_r greater than
// max_refraction_deflection(mu)). DomainError "mu" for mu outside (1, 10].
std::optional<DropImagePoint> drop_image_point(const Vec3& dir, double mu);

// A virtual pinhole camera at the drop: looking along +z turned by yaw about +y (positive towards
// +x, to the right) and then by pitch about its own x axis (positive up), horizontal field of view
// fov_deg, square pixels, row 0 at the top.
struct UndistortView {
  double yaw_deg = 0;
  double pitch_deg = 0;
  double fov_deg = 60;
  int width = 512, height = 512;

  // Unit world direction through image position (px, py), pixel centres at half-integers.
  Vec3 direction(double px, double py) const;
};

// DomainError "yaw_deg" [-360, 360], "pitch_deg" [-90, 90], "fov_deg" (0, 179], "width" or
// "height" [1, 16384].
void validate(const UndistortView& view);

// What a user sets for an undistortion (hydrolux drop undistort, hydrolux.drop_undistort), declared
// once (undistort_params: each value's name, unit, range, default and help). The drop's radius has
// no default (every door requires it); of width and height, one given sets both (a square view),
// neither gives UndistortView's 512 x 512.
struct UndistortRequest {
  std::optional<double> drop_radius_px;
  double fov_deg = 60;
  double yaw_deg = 0;
  double pitch_deg = 0;
  double mu = 1.333;
  std::optional<int> width, height;
  bool transmission_correction = true;

  // The view these values ask for (not validated: check_fields(undistort_params(), request)).
  UndistortView view() const;
};

std::span<const Field<UndistortRequest>> undistort_params();

// Resamples the drop in `drop_image` (centre (cx, cy) in pixels, pixel centres at half-integers,
// image radius radius_px) into the perspective view `view`. For each output pixel: its direction,
// the drop-image point that sees it (drop_image_point), a bilinear sample of the drop image there,
// divided by the transmission (1 - k)^2 if `transmission_correction`.
// Output: RGBA, linear. RGB from the first three channels (one or two channels: the first is grey).
// Alpha is the coverage mask: 1 where the drop resolves the direction, 0 (and RGB 0) where the
// direction lies outside the drop's field of view or its image point falls outside drop_image.
// DomainError "mu" (1, 10], "radius_px" (0, 1e6], "center_x_px" / "center_y_px" not finite,
// "image_width" / "image_height" / "image_channels" for an empty image, and as validate(view).
Image undistort(const Image& drop_image, double cx, double cy, double radius_px, double mu,
                const UndistortView& view, bool transmission_correction = true);

// The fraction of an undistorted view's pixels that the drop resolves (alpha above 0), in [0, 1];
// 0 for an empty image or one without an alpha channel.
double resolved_fraction(const Image& undistorted);

}  // namespace hydrolux::drop
