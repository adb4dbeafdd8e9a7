#include "hydrolux/rain/params.hpp"

#include <fmt/format.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "hydrolux/core/error.hpp"
#include "hydrolux/core/shared_params.hpp"

namespace hydrolux::rain {

namespace {

using K = ParamKind;


const Field<RainOptions> kRain[] = {
    // Named rate_mmh / --rate-mmh before (deprecated: taken for one release, with a warning).
    {{"rain_rate_mmh", "--rain-rate-mmh", "rain", K::real, "mm/h", 0, kMaxRainRateMmh, "Rain rate, mm/h (0: no rain)",
      {}, {}, {}, {}, "rate_mmh"},
     HYDROLUX_PARAM_MEMBER(settings.rain_rate_mmh)},
    {{"wind_mps", "--wind-mps", "rain", K::real, "m/s", 0, 50, "Horizontal wind speed, m/s (drops move with it)"},
     HYDROLUX_PARAM_MEMBER(settings.wind_mps)},
    {{"wind_dir_deg", "--wind-dir-deg", "rain", K::real, "deg", -360, 360,
      "Where the wind blows to: 0 away from the camera, 90 to its right"},
     HYDROLUX_PARAM_MEMBER(settings.wind_dir_deg)},
    {{"exposure_s", "--exposure-s", "camera", K::real, "s", 1e-6, 1, "Exposure time, s (at most 1 / fps)"},
     HYDROLUX_PARAM_MEMBER(camera.exposure_s)},
    {{"focal_mm", "--focal-mm", "camera", K::real, "mm", 1, 2000, "Focal length, mm"}, HYDROLUX_PARAM_MEMBER(camera.focal_mm)},
    {{"fov_deg", "--fov-deg", "camera", K::real, "deg", 1, 170, "Horizontal field of view, degrees (instead of --focal-mm)",
      "focal_mm"},
     HYDROLUX_PARAM_OPTIONAL(fov_deg)},
    {{"sensor_width_mm", "--sensor-width-mm", "camera", K::real, "mm", 1, 100,
      "Sensor width, mm (pixel pitch = width / image width)"},
     HYDROLUX_PARAM_MEMBER(camera.sensor_width_mm)},
    {{"pixel_pitch_um", "--pixel-pitch-um", "camera", K::real, "um", 0.1, 1000, "Pixel pitch, um (instead of --sensor-width-mm)",
      "sensor_width_mm"},
     HYDROLUX_PARAM_OPTIONAL(pixel_pitch_um)},
    {{"f_number", "--f-number", "camera", K::real, "", 0, 64,
      "Aperture f-number for defocus of near drops; 0 = pinhole (all sharp)"},
     HYDROLUX_PARAM_MEMBER(camera.f_number)},
    {{"focus_m", "--focus-m", "camera", K::real, "m", 0.01, 1e4, "Focus distance, m (with --f-number)"},
     HYDROLUX_PARAM_MEMBER(camera.focus_m)},
    {{"fps", "--fps", "camera", K::real, "1/s", 0.01, 1000,
      "Frame rate of --image / --input-dir frames (frame k is exposed from k / fps)", {}, {}, "video",
      "a video's frame rate is its own"},
     [](const RainOptions& o, int) { return o.fps.value_or(o.camera.fps); },
     [](RainOptions& o, int, double v) { o.fps = v; }},
    {{"camera_height_m", "--camera-height-m", "camera", K::real, "m", 0, 1000, "Camera height above the ground plane, m"},
     HYDROLUX_PARAM_MEMBER(camera.height_m)},
    {{"pitch_deg", "--pitch-deg", "camera", K::real, "deg", -80, 80, "Camera pitch above the horizon, degrees"},
     HYDROLUX_PARAM_MEMBER(camera.pitch_deg)},
    {{"near_m", "--near-m", "rain", K::real, "m", 0.05, 100, "No drop nearer than this, m"}, HYDROLUX_PARAM_MEMBER(settings.near_m)},
    {{"far_m", "--far-m", "rain", K::real, "m", 0.1, 1e4, "No drop drawn beyond this, m (farther rain is unresolved)"},
     HYDROLUX_PARAM_MEMBER(settings.far_m)},
    {{"min_radius_mm", "--min-radius-mm", "rain", K::real, "mm", 0.04, 2.9, "Smaller drops count only as unresolved rain, mm"},
     HYDROLUX_PARAM_MEMBER(settings.min_radius_mm)},
    {{"max_radius_mm", "--max-radius-mm", "rain", K::real, "mm", 0.04, 2.9, "Largest drop radius, mm (larger drops break up)"},
     HYDROLUX_PARAM_MEMBER(settings.max_radius_mm)},
    {{"min_alpha", "--min-alpha", "rain", K::real, "", 1e-5, 0.5,
      "A drop is drawn while its streak's peak coverage reaches this; fainter rain is unresolved"},
     HYDROLUX_PARAM_MEMBER(settings.min_alpha)},
    {{"extent_m", "--extent-m", "rain", K::real, "m", 0, 1e5, "Depth of the rain where the depth map has none (sky), m"},
     HYDROLUX_PARAM_MEMBER(settings.extent_m)},
    {{"backdrop_m", "--backdrop-m", "rain", K::real, "m", 1, 1e5,
      "Without --depth: the scene is the ground plane up to a backdrop this far, m"},
     HYDROLUX_PARAM_MEMBER(settings.backdrop_m)},
    {{"oscillation", "--oscillation", "rain", K::real, "", 0, 0.5,
      "Relative amplitude of the drops' shape oscillation (Rayleigh mode 2); 0 off"},
     HYDROLUX_PARAM_MEMBER(settings.oscillation)},
    {flag_param("unresolved", "--no-unresolved", "rain",
                "Leave out the unresolved rain's extinction and airlight (streaks only)"),
     HYDROLUX_PARAM_MEMBER(settings.unresolved)},
    {{"radius_classes", "--radius-classes", "rain", K::integer, "", 1, 256,
      "Drop radius classes, log-spaced from --min-radius-mm to --max-radius-mm (more: finer sizes, slower)"},
     HYDROLUX_PARAM_MEMBER(settings.radius_classes)},
    // Fog with the rain: the fog's own rows (rain/fog.cpp), on the rain's camera and scene.
    {fog_medium_param("visibility_m"), HYDROLUX_PARAM_OPTIONAL(fog.visibility_m)},
    {fog_medium_param("lwc_g_m3"), HYDROLUX_PARAM_OPTIONAL(fog.lwc_g_m3)},
    {fog_medium_param("mode_radius_um"), HYDROLUX_PARAM_MEMBER(fog.mode_radius_um)},
    {fog_medium_param("size_alpha"), HYDROLUX_PARAM_MEMBER(fog.size_alpha)},
    {fog_medium_param("wavelength_nm"), HYDROLUX_PARAM_MEMBER(fog.wavelength_nm)},
    {fog_medium_param("glow"), HYDROLUX_PARAM_MEMBER(fog.glow)},
    {seed_param("rain", "Random seed: the same seed gives the same rain, bytes for bytes"),
     HYDROLUX_PARAM_MEMBER(settings.seed)},
};

const Field<RainFileOptions> kRainFiles[] = {
    {{"frame_index", "--frame-index", "files", K::integer, "", 0, 1e9, "Index of the first frame in the rain field's time"},
     HYDROLUX_PARAM_MEMBER(frame_index)},
    {{"crf", "--crf", "files", K::integer, "", 0, 51,
      "H.264 quality of --video's output (0 lossless .. 51; 18 visually lossless)", {}, "video", {},
      "sets the H.264 quality of {video}'s output; pictures have none"},
     HYDROLUX_PARAM_MEMBER(crf)},
    {{"png_compression", "--png-compression", "files", K::integer, "", 0, 9,
      "Deflate level of PNG outputs (libdeflate): 0 stored, 1 fastest, 9 smallest; the same pixels at "
      "every level (BENCHMARKS.md: time and size)"},
     HYDROLUX_PARAM_MEMBER(png_compression)},
    {{"depth_scale_m", "--depth-scale-m", "files", K::real, "m", 1e-6, 1e3,
      "Metres per code of a PNG depth map (--depth, --depth-dir)", {}, "depth|depth_dir", {},
      "scales the codes of PNG depth maps; none is given"},
     HYDROLUX_PARAM_MEMBER(depth_scale_m)},
};

}  // namespace

std::span<const Field<RainOptions>> rain_params() { return kRain; }
std::span<const Field<RainFileOptions>> rain_file_params() { return kRainFiles; }

const Param& rain_param(std::string_view name) {
  if (const auto* f = find_field(rain_params(), name)) return f->param;
  if (const auto* f = find_field(rain_file_params(), name)) return f->param;
  throw std::logic_error("rain_param: no parameter " + std::string(name));
}

void refuse_fog_settings_without_fog(const RainOptions& o) {
  if (o.has_fog()) return;
  const RainOptions defaults;
  for (const auto& f : rain_params())
    if (f.param.group == "fog" && f.get(o) != f.get(defaults) && !std::isnan(f.get(o)))
      throw ParamError(fmt::format("{{{}}}: sets the fog; give {{visibility_m}} or {{lwc_g_m3}} with it", f.param.name));
}

RainCamera camera_for(const RainOptions& o, int width, int height) {
  RainCamera c = o.camera;
  c.width = width;
  c.height = height;
  if (o.pixel_pitch_um && width > 0) {
    // The sensor the pitch makes, in the sensor width's range: said as the pitch, the value given.
    const Param& sensor = rain_param("sensor_width_mm");
    c.sensor_width_mm = *o.pixel_pitch_um * 1e-3 * width;
    if (!(c.sensor_width_mm >= sensor.lo && c.sensor_width_mm <= sensor.hi))
      throw DomainError("pixel_pitch_um", *o.pixel_pitch_um, sensor.lo * 1e3 / width, sensor.hi * 1e3 / width,
                        fmt::format("a {{sensor_width_mm}} in [{:g}, {:g}] mm over a frame {} px wide", sensor.lo,
                                    sensor.hi, width));
  }
  if (o.fov_deg) c.focal_mm = focal_mm_from_fov(*o.fov_deg, c.sensor_width_mm);
  if (o.fps) c.fps = *o.fps;
  return c;
}

}  // namespace hydrolux::rain
