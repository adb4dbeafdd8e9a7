#include "hydrolux/scene/sky_params.hpp"

#include <fmt/format.h>

#include <limits>
#include <stdexcept>
#include <string>

#include "hydrolux/atmos/lee_params.hpp"
#include "hydrolux/core/shared_params.hpp"
#include "hydrolux/scene/bow_tables.hpp"

namespace hydrolux::scene {

namespace {

using K = ParamKind;

// Why a parameter of one mode is refused in another ({mode=}: the run's).
constexpr std::string_view kCubeMapWhy = "used by {mode=cube-map} only (this run is {mode=})";
constexpr std::string_view kHalfDomeWhy = "used by {mode=half-dome} only (this run is {mode=})";


}  // namespace

// The tables are made on first use (their helps state the largest radius the tables computed here
// allow, which the library works out), in the CLI's order: hydrolux sky --help and hydrolux export
// --help register them in slices between their own flags. The sampling range is the Lee table's.
std::span<const Field<SkyOptions>> sky_params() {
  static const std::string radius_help = fmt::format(
      "Drop radius in micrometres (the table column; 10% gamma spread): 500 rain, 10-50 fogbow or corona; without "
      "--lut at most {:g}, where the largest drops of the spread reach Mie theory's size parameter limit (1e5) at 380 "
      "nm; with --lut up to {:g}, as its tables cover",
      max_sky_radius_um(), atmos::kMaxRadiusUm);
  const Param& sampling = atmos::lee_param("sampling");
  static const Field<SkyOptions> table[] = {
      {{"sun_elevation_deg", "--sun-elevation-deg", "sun", K::real, "deg", 0, 90,
        "The sun's elevation above the horizon, degrees"},
       HYDROLUX_PARAM_MEMBER(settings.sun_elevation_deg)},
      {{"sun_azimuth_deg", "--sun-azimuth-deg", "sun", K::real, "deg", -360, 360,
        "The sun's azimuth, degrees from north towards east"},
       HYDROLUX_PARAM_MEMBER(settings.sun_azimuth_deg)},
      {{"radius_um", "--radius-um", "rain", K::real, "um", atmos::kMinRadiusUm, atmos::kMaxRadiusUm, radius_help},
       HYDROLUX_PARAM_MEMBER(settings.radius_um)},
      {{"fov_deg", "--fov-deg", "camera", K::real, "deg", 1, 170, "Horizontal field of view, degrees"},
       HYDROLUX_PARAM_MEMBER(settings.camera.fov_deg)},
      {{"view_azimuth_deg", "--view-azimuth-deg", "camera", K::real, "deg", -360, 360,
        "Where the camera looks: azimuth, degrees from north towards east"},
       HYDROLUX_PARAM_MEMBER(settings.camera.azimuth_deg)},
      {{"view_elevation_deg", "--view-elevation-deg", "camera", K::real, "deg", -89, 89,
        "Where the camera looks: elevation, degrees"},
       HYDROLUX_PARAM_MEMBER(settings.camera.elevation_deg)},
      {parts_param("size", "--size", "camera", K::size, "W|H", "px", 1, kMaxImageSide, "Image size in pixels"),
       HYDROLUX_PARAM_PARTS(settings.camera.width, settings.camera.height)},
      {{"rain_rate_mmh", "--rain-rate-mmh", "rain", K::real, "mm/h", 0, kMaxRainRateMmh,
        "Rain rate in mm/h (Marshall-Palmer drops): sets the curtain's optical depth"},
       HYDROLUX_PARAM_MEMBER(settings.rain_rate_mmh)},
      {parts_param("curtain_distance_m", "--curtain-distance-m", "rain", K::span, "NEAR|FAR", "m", 0, 1e6,
                   "The rain fills NEAR to FAR metres from the camera"),
       HYDROLUX_PARAM_PARTS(settings.curtain_near_m, settings.curtain_far_m)},
      {{"turbidity", "--turbidity", "sun", K::real, "", kMinTurbidity, kMaxTurbidity,
        "Atmospheric turbidity of the sky and the sun's path (Preetham: 2 clear, 10 hazy)"},
       HYDROLUX_PARAM_MEMBER(settings.turbidity)},
      {{"environment_scale", "--environment-scale", "scene", K::real, "", 0, 1e12,
        "Multiplier on --environment's values (needs --environment)", {}, "environment", {},
        "scales {environment}'s values; without {environment} there is nothing to scale"},
       HYDROLUX_PARAM_MEMBER(environment_scale)},
      {parts_param("light_color", "--light-color", "sun", K::colour, "R|G|B", "", 0, 1000,
                   "Multipliers on the sun's light in the bow (linear Rec.709)"),
       HYDROLUX_PARAM_INDEXED(settings.light_color)},
      {flag_param("corona", "--corona", "rain",
                  "Draw the corona and the forward light around the sun (0-90 degrees; drops of 1-50 um)"),
       HYDROLUX_PARAM_MEMBER(settings.corona)},
      {flag_param("secondary", "--no-secondary", "rain", "Leave out the secondary bow (fades out below 134 degrees)"),
       HYDROLUX_PARAM_MEMBER(settings.secondary)},
      {choice_param("blend", "--blend", "scene", "physical|whitepaper",
                    "How the bow meets the scene: physical (attenuation + in-scattering) or whitepaper (scene + bow (1 - "
                    "scene))"),
       HYDROLUX_PARAM_MEMBER(settings.blend)},
      {choice_param("mode", "--mode", "mode", "per-pixel|cube-map|half-dome",
                    "How the bow is looked up: per-pixel (reference), cube-map (baked bow) or half-dome (tessellated, 1D "
                    "lookup)"),
       HYDROLUX_PARAM_MEMBER(settings.mode)},
      {{"cube_face_size", "--cube-face-size", "mode", K::integer, "", 4, 4096,
        "Cube map face size in texels (--mode cube-map only)", {}, "mode=cube-map", {}, kCubeMapWhy},
       HYDROLUX_PARAM_MEMBER(settings.cube_face_size)},
      {{"dome_rings", "--dome-rings", "mode", K::integer, "", 2, 4096,
        "Half dome rings from the antisolar point to 90 degrees (--mode half-dome only)", {}, "mode=half-dome", {},
        kHalfDomeWhy},
       HYDROLUX_PARAM_MEMBER(settings.dome_rings)},
      {{"dome_segments", "--dome-segments", "mode", K::integer, "", 3, 8192,
        "Half dome segments around (--mode half-dome only)", {}, "mode=half-dome", {}, kHalfDomeWhy},
       HYDROLUX_PARAM_MEMBER(settings.dome_segments)},
      {{"polarizer_deg", "--polarizer-deg", "camera", K::real, "deg", -180, 180,
        "A linear polariser in front of the camera: its transmission axis in the image, degrees from the horizontal "
        "towards up (0 passes the top of the bow, 90 its sides); the bow's and corona's polarisation from Stokes "
        "tables, the sky's from --sky-max-dolp; none by default"},
       HYDROLUX_PARAM_OPTIONAL(settings.polarizer_deg)},
      {{"sky_max_dolp", "--sky-max-dolp", "sun", K::real, "", 0, 1,
        "The sky's degree of linear polarisation 90 degrees from the sun (Rayleigh with depolarisation: 0.946 for "
        "air's molecules alone, 0.6-0.85 measured in clear skies; used with --polarizer-deg)",
        {}, "polarizer_deg|stokes", {},
        "sets the sky's polarisation, which only a polariser or the Stokes images show (add {polarizer_deg} or "
        "{stokes}, or omit {sky_max_dolp})"},
       HYDROLUX_PARAM_MEMBER(settings.sky_max_dolp)},
      {{"stokes", "--stokes", "camera", K::flag, "", 0, 1,
        "Write the Stokes images instead of one filter's: EXR channels R,G,B (I), Q.R,Q.G,Q.B and U.R,U.G,U.B in each "
        "pixel's image basis (x right, y up), from which a polariser at A passes (I + Q cos 2A + U sin 2A) / 2; .exr "
        "and the physical blend only, not with --polarizer-deg"},
       HYDROLUX_PARAM_MEMBER(settings.stokes)},
      {{"sampling", "--sampling", "tables", K::real, "", sampling.lo, sampling.hi,
        "Sampling multiplier of the tables computed without --lut (not with --lut); the time grows as its square: "
        "about 12 s at 1 for 500 um drops on two cores, an hour at 16 [automatic: 1, and once more at up to 4 for "
        "each table whose estimated error is above 1%]",
        {}, {}, "lut", "sets the sampling of the tables computed without {lut}; {lut} gives the tables (omit {sampling})"},
       HYDROLUX_PARAM_OPTIONAL(sampling)},
  };
  return table;
}

std::span<const Field<ExportOptions>> export_params() {
  static const std::string radius_help = [] {
    atmos::LeeSpec geometric = atmos::default_lee_spec(atmos::LeeTableKind::rainbow);
    geometric.theory = scatter::parse_theory("geometric");
    return fmt::format(
        "One drop radius in micrometres: one-column tables (a 1D slice); at most {:g} with Mie or Debye theory, {:g} "
        "with geometric (the size parameter's limit at 380 nm)",
        atmos::max_radius_um(atmos::default_lee_spec(atmos::LeeTableKind::rainbow)), atmos::max_radius_um(geometric));
  }();
  const Param& sampling = atmos::lee_param("sampling");
  const Param& shape_sun = atmos::lee_param("sun_elevation_deg");  // the non-spherical tables' range
  static const Field<ExportOptions> table[] = {
      {{"radius_um", "--radius-um", "tables", K::real, "um", atmos::kMinRadiusUm, atmos::kMaxRadiusUm, radius_help},
       HYDROLUX_PARAM_OPTIONAL(radius_um)},
      {parts_param("size", "--size", "tables", ParamKind::size, "W|H", "px", 1, kMaxImageSide,
                   "Table size WxH: W radii, H angles of the rainbow table (the corona table has 2H) [512x1024]"),
       HYDROLUX_PARAM_OPTIONAL_PARTS(size)},
      {{"sampling", "--sampling", "tables", K::real, "", sampling.lo, sampling.hi,
        "Multiplier on the tables' sampling rates [automatic: 1, and once more at up to 4 for each table whose "
        "estimated error is above 1%]"},
       HYDROLUX_PARAM_OPTIONAL(sampling)},
      {{"turbidity", "--turbidity", "sky", K::real, "", kMinTurbidity, kMaxTurbidity,
        "Turbidity of sky.json's sky and sun (Preetham)"},
       HYDROLUX_PARAM_MEMBER(turbidity)},
      {{"sun_elevation_deg", "--sun-elevation-deg", "sun", K::real, "deg", shape_sun.lo, shape_sun.hi,
        "The sun's elevation above the horizon, degrees, that the non-spherical drops' table is computed for "
        "(--shape only: the bow of such drops depends on it)"},
       HYDROLUX_PARAM_MEMBER(sun_elevation_deg)},
  };
  return table;
}

const Param& sky_param(std::string_view name) {
  if (const auto* f = find_field(sky_params(), name)) return f->param;
  throw std::logic_error("sky_param: no parameter " + std::string(name));
}

}  // namespace hydrolux::scene
