#pragma once
// The files of the frame jobs (`hydrolux rain`, `fog`, `lens-drops`) as declared parameters of the
// path kind (core/params.hpp): each path's name, flag, help and the member of FramePaths it fills,
// one table per effect, read by every door as the numbers are (the CLI's flags, the batch jobs'
// folder options, docs/reference.md, `hydrolux spec --json`). The driver that reads and writes the
// files is io/frame_driver.hpp's; a path an effect does not take (--depth for lens drops, --layer-out
// but for rain) is not in its table.
#include <optional>
#include <span>
#include <string>

#include "hydrolux/core/params.hpp"

namespace hydrolux::rain {

// What to read and where the results go, as the CLI's flags name them (messages quote them so).
// Exactly one of image, input_dir, video. Every effect's job (io::RainJob, FogJob, LensDropsJob) is
// one; a door leaves unset what its effect does not take.
struct FramePaths {
  std::optional<std::string> image, input_dir, video;
  std::optional<std::string> depth, depth_dir;
  std::optional<std::string> output, output_dir, mask_out, mask_dir, layer_out, layer_dir, stats_json;
};

// Each effect's paths, in --help's order: the inputs, the outputs, the statistics.
std::span<const Field<FramePaths>> rain_path_params();
std::span<const Field<FramePaths>> fog_path_params();
std::span<const Field<FramePaths>> lens_drops_path_params();

}  // namespace hydrolux::rain
