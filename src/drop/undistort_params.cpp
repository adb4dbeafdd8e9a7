#include "hydrolux/drop/undistort.hpp"

namespace hydrolux::drop {

namespace {

using K = ParamKind;

// The ranges undistort() and validate(UndistortView) hold to, with a floor on the two that must be
// above zero (a radius of a hundredth of a pixel, a field of a hundredth of a degree).
const Field<UndistortRequest> kUndistort[] = {
    {{"drop_radius_px", "--drop-radius-px", "drop", K::real, "px", 0.01, 1e6, "The drop's radius on the image in pixels"},
     HYDROLUX_PARAM_OPTIONAL(drop_radius_px)},
    {{"fov_deg", "--fov-deg", "view", K::real, "deg", 0.01, 179, "Horizontal field of view of the perspective view"},
     HYDROLUX_PARAM_MEMBER(fov_deg)},
    {{"yaw_deg", "--yaw-deg", "view", K::real, "deg", -360, 360,
      "View direction turned about the vertical, positive to the right"},
     HYDROLUX_PARAM_MEMBER(yaw_deg)},
    {{"pitch_deg", "--pitch-deg", "view", K::real, "deg", -90, 90, "View direction tilted, positive up"},
     HYDROLUX_PARAM_MEMBER(pitch_deg)},
    {{"mu", "--mu", "drop", K::real, "", 1.0001, 10, "Refractive index of the drop relative to the air"},
     HYDROLUX_PARAM_MEMBER(mu)},
    {{"width", "--width", "view", K::integer, "px", 1, 16384, "Output width in pixels (height = width if not given)"},
     HYDROLUX_PARAM_OPTIONAL(width)},
    {{"height", "--height", "view", K::integer, "px", 1, 16384, "Output height in pixels (width = height if not given)"},
     HYDROLUX_PARAM_OPTIONAL(height)},
    {{"transmission_correction", "--no-transmission-correction", "drop", K::flag, "", 0, 1,
      "Keep the drop's brightness: do not divide by the refraction transmission (1 - k)^2"},
     HYDROLUX_PARAM_MEMBER(transmission_correction)},
};

}  // namespace

std::span<const Field<UndistortRequest>> undistort_params() { return kUndistort; }

UndistortView UndistortRequest::view() const {
  UndistortView v;
  v.yaw_deg = yaw_deg;
  v.pitch_deg = pitch_deg;
  v.fov_deg = fov_deg;
  if (width || height) {
    v.width = width ? *width : *height;
    v.height = height ? *height : *width;
  }
  return v;
}

}  // namespace hydrolux::drop
