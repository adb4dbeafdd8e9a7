#pragma once
// What a rain run reports, as JSON: one frame's statistics and the run's parameters and field
// (hydrolux rain --stats-json, the Python package's stats dicts, the batch job's manifest).
#include <nlohmann/json.hpp>
#include <string>

#include "hydrolux/rain/rain.hpp"

namespace hydrolux::io {

nlohmann::json rain_stats_json(const rain::RainStats& stats);
// The program, the seed, the rain and camera settings and the field's classes; `depth` says what
// hid the rain (a depth map's path, a folder, or "ground plane").
nlohmann::json rain_run_json(const rain::RainField& field, const std::string& depth);

}  // namespace hydrolux::io
