#pragma once
// What the frame jobs (rain_job.cpp, fog_job.cpp, lens_drops_job.cpp) share beyond the driver: the
// job's result with the driver's part filled in, a frame's failure said with its origin, the depth
// the effect used and the camera, said alike in every statistics file.
#include <fmt/format.h>

#include <nlohmann/json.hpp>
#include <string>
#include <utility>

#include "hydrolux/core/error.hpp"
#include "hydrolux/io/frame_driver.hpp"
#include "hydrolux/rain/rain.hpp"

namespace hydrolux::io::detail {

// Runs `effect` over the request's frames: the job's result, the driver's counts, left-out frames
// and time with what the effect adds (`effect.fill_result(out)`: its settings, the last frame's
// statistics).
template <typename Result, typename Effect>
Result run_frame_job(const FrameRequest& request, Effect& effect, const FrameHooks& hooks) {
  Result out;
  static_cast<FrameRunResult&>(out) = run_frames(request, effect, hooks);
  effect.fill_result(out);
  return out;
}

// Calls `render` for the frame read from `origin`: a setting's DomainError passes unchanged (the
// door names its parameter), any other Error is said with the frame's origin.
template <typename Render>
auto render_frame(const std::string& origin, Render&& render) {
  try {
    return std::forward<Render>(render)();
  } catch (const DomainError&) {
    throw;
  } catch (const Error& e) {
    throw Error(fmt::format("{}: {}", origin, e.what()));
  }
}

// What hid the scene: the depth map's path or folder, else `otherwise` (the ground plane).
inline std::string depth_source(const FramePaths& paths, std::string otherwise) {
  return paths.depth ? *paths.depth : paths.depth_dir ? *paths.depth_dir : std::move(otherwise);
}

// The camera over the ground plane, as every frame job's statistics say it.
inline nlohmann::json camera_json(const rain::RainCamera& c) {
  return {{"width", c.width},
          {"height", c.height},
          {"focal_mm", c.focal_mm},
          {"sensor_width_mm", c.sensor_width_mm},
          {"height_m", c.height_m},
          {"pitch_deg", c.pitch_deg}};
}

}  // namespace hydrolux::io::detail
