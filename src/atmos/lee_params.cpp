#include "hydrolux/atmos/lee_params.hpp"

#include <fmt/format.h>

#include <limits>
#include <stdexcept>
#include <string>

#include "hydrolux/core/shared_params.hpp"

namespace hydrolux::atmos {

namespace {

using K = ParamKind;

// Each entry: the parameter, then how it is read from and written to the request. The order is the
// CLI's (hydrolux lee --help registers them in slices between its own flags).

const Field<LeeRequest> kLee[] = {
    {choice_param("table", "--table", "table", "rainbow|corona|glory",
                  "rainbow (90-180 deg, 5-800 um), corona (0-20 deg, 1-50 um) or glory (160-180 deg, 1-50 um)"),
     HYDROLUX_PARAM_MEMBER(table)},
    {choice_param("radius_scale", "--radius-scale", "table", "log|linear", "Column spacing: log or linear"),
     HYDROLUX_PARAM_MEMBER(radius_scale)},
    {parts_param("angle_deg", "--angle-deg", "table", ParamKind::span, "A|B", "deg", 0, 180,
                 "Scattering angles A:B in degrees (0 forward, 180 antisolar) [table's default]"),
     HYDROLUX_PARAM_OPTIONAL_PARTS(angle_deg)},
    {choice_param("axis", "--axis", "table", "angle|cos", "Rows in scattering angle (angle) or in its cosine (cos)"),
     HYDROLUX_PARAM_MEMBER(axis)},
    {parts_param("size", "--size", "table", ParamKind::size, "W|H", "px", 1, kMaxImageSide,
                 "Table size WxH in pixels: W radii, H angles [512x1024; 1xH for one radius]"),
     HYDROLUX_PARAM_OPTIONAL_PARTS(size)},
    {{"sun_disk_deg", "--sun-disk-deg", "sun", K::real, "deg", 0, 5, "The sun's angular diameter in degrees (0: a point)"},
     HYDROLUX_PARAM_MEMBER(sun_disk_deg)},
    {flag_param("limb_darkening", "--limb-darkening", "sun",
                "Darken the sun's limb (linear law, u = 0.6; not with --sun-disk-deg 0)"),
     HYDROLUX_PARAM_MEMBER(limb_darkening)},
    {{"size_spread", "--size-spread", "drops", K::real, "", 0, 0.5,
      "Relative standard deviation of each column's gamma size distribution (0: one radius; else 0.01-0.5)"},
     HYDROLUX_PARAM_MEMBER(size_spread)},
    {temperature_param("drops", "Water temperature in Celsius (0 to 100) [20]"),
     HYDROLUX_PARAM_OPTIONAL(temperature_c)},
    {{"sun_elevation_deg", "--sun-elevation-deg", "drops", K::real, "deg", 0, 89,
      "Non-spherical drops: the sun's elevation above the horizon in degrees (spheres: no effect)"},
     HYDROLUX_PARAM_MEMBER(sun_elevation_deg)},
    {{"position_deg", "--position-deg", "drops", K::real, "deg", 0, 180,
      "Non-spherical drops: the bow's position angle around the antisolar point in degrees (0 top, 90 side, 180 bottom)"},
     HYDROLUX_PARAM_MEMBER(position_deg)},
    {{"canting_deg", "--canting-deg", "drops", K::real, "deg", 0, 30,
      "Non-spherical drops: standard deviation of the tilt of their axes from the vertical, per component, in degrees"},
     HYDROLUX_PARAM_MEMBER(canting_deg)},
    {{"sampling", "--sampling", "sampling", K::real, "", 0.25, 16,
      "Multiplier on every sampling rate (wavelengths, radius grid) [automatic: 1, and once more at up to 4 where "
      "the table's estimated error is above 1%]"},
     HYDROLUX_PARAM_OPTIONAL(sampling)},
    {seed_param("sampling", "Seed of the sampling pattern"),
     HYDROLUX_PARAM_MEMBER(seed)},
    {threads_param("sampling", "Threads (0: every core)"), HYDROLUX_PARAM_MEMBER(threads)},
    {{"stokes", "--stokes", "output", K::flag, "", 0, 1,
      "Also the Stokes Q in the scattering-plane basis (> 0 tangential to the bow; U = 0): EXR channels Q.X, Q.Y, "
      "Q.Z, and the profile's dolp = Q_Y / I_Y"},
     HYDROLUX_PARAM_MEMBER(stokes)},
};

}  // namespace

std::span<const Field<LeeRequest>> lee_params() { return kLee; }

std::string shape_only_message(std::string_view param, double value, std::string_view name, std::string_view shape) {
  const std::string_view what = param == "sun_elevation_deg" ? "the sun"
                                : param == "position_deg"    ? "the bow's position angle"
                                                             : "the canting";
  return fmt::format("{} {:g}: sets {} of the non-spherical drops' table ({}); the spheres' tables do not depend "
                     "on it (omit it or give {})",
                     name, value, what, shape, shape);
}

const Param& lee_param(std::string_view name) {
  if (const auto* f = find_field(lee_params(), name)) return f->param;
  throw std::logic_error("lee_param: no parameter " + std::string(name));
}

}  // namespace hydrolux::atmos
