#pragma once
// What a user sets for rain (hydrolux rain, hydrolux.rain / RainRenderer, the batch job
// hydrolux.batch rain), declared once (core/params.hpp): each value's name, unit, range, default and
// help. The defaults are RainSettings' and RainCamera's initializers (rain.hpp).
#include <cstdint>
#include <optional>
#include <span>

#include "hydrolux/core/params.hpp"
#include "hydrolux/rain/fog.hpp"
#include "hydrolux/rain/rain.hpp"

namespace hydrolux::rain {

// The rain and camera a user asks for, before the frames' size is known.
struct RainOptions {
  RainSettings settings;
  RainCamera camera;                     // width and height come from the frames
  std::optional<double> fov_deg;         // instead of camera.focal_mm
  std::optional<double> pixel_pitch_um;  // instead of camera.sensor_width_mm (times the width)
  std::optional<double> fps;             // of still frames (a video has its own); else camera.fps
  // Fog with the rain (one veil: RainRenderer::set_fog), on when visibility_m or lwc_g_m3 is given.
  FogSettings fog;
  bool has_fog() const { return fog.visibility_m || fog.lwc_g_m3; }
};

// The options of a run over files: where the sequence starts, how video and PNG files are encoded,
// how PNG depth maps are scaled. The CLI and the batch job take them; the Python functions take
// arrays instead.
struct RainFileOptions {
  std::int64_t frame_index = 0;
  int crf = 18;
  int png_compression = 1;  // the deflate level of PNG outputs: io::kDefaultPngCompression
  double depth_scale_m = 0.001;
};

std::span<const Field<RainOptions>> rain_params();
std::span<const Field<RainFileOptions>> rain_file_params();
// A rain parameter by name (either table); throws std::logic_error for a name not declared.
const Param& rain_param(std::string_view name);

// The camera for frames of width x height: the field of view and the pixel pitch, where given,
// turned into the focal length and the sensor width; the still frames' rate where given. Not
// validated (validate(RainCamera) names what is out of range).
RainCamera camera_for(const RainOptions& options, int width, int height);
// Refuses a fog parameter set away from its default while the fog is off (no visibility_m or lwc_g_m3):
// ParamError "{size_alpha}: sets the fog; give {visibility_m} or {lwc_g_m3} with it".
void refuse_fog_settings_without_fog(const RainOptions& options);

}  // namespace hydrolux::rain
