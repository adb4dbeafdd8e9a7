#pragma once
// The files of the frame jobs (`hydrolux rain`, `fog`, `lens-drops`) declared once, as the numbers
// are in core/params.hpp: each path's flag, where it goes in the request (FramePaths) and its help.
// The wording that differs between effects comes from the effect (EffectTraits::words); a path the
// effect does not take (--depth for lens drops, --layer-out but for rain) is not listed for it.
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "hydrolux/io/frame_driver.hpp"

namespace hydrolux::io {

struct FramePathParam {
  std::string_view flag;  // "--input-dir"; a short form first where there is one ("-o,--output")
  std::optional<std::string> FramePaths::*path;
  std::string help;
};

// The paths `traits`' effect takes, in --help's order: the inputs, the outputs, the statistics.
std::vector<FramePathParam> frame_path_params(const EffectTraits& traits);

}  // namespace hydrolux::io
