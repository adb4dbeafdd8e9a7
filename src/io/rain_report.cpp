#include "hydrolux/io/rain_report.hpp"

#include "frame_job.hpp"

namespace hydrolux::io {

nlohmann::json rain_stats_json(const rain::RainStats& s) {
  nlohmann::json j = {{"drops_total", s.drops_total},
          {"drops_in_view", s.drops_in_view},
          {"drops_visible", s.drops_visible},
          {"streak_length_px", {{"mean", s.streak_length_px_mean}, {"p50", s.streak_length_px_p50},
                                {"p95", s.streak_length_px_p95}, {"max", s.streak_length_px_max}}},
          {"streak_width_px", {{"mean", s.streak_width_px_mean}, {"max", s.streak_width_px_max}}},
          {"drop_luminance_mean", s.drop_luminance_mean},
          {"background_luminance_under_streaks", s.background_luminance_mean},
          {"streak_luminance_gain", s.streak_luminance_gain},
          {"streak_pixel_fraction", s.streak_pixel_fraction},
          {"alpha_mean", s.alpha_mean},
          {"unresolved_transmittance_mean", s.unresolved_transmittance_mean},
          {"negative_values_clamped", s.negative_values_clamped}};
  if (s.fog_beta_per_m > 0)
    j["fog"] = {{"beta_per_m", s.fog_beta_per_m},
                {"visibility_m", s.fog_visibility_m},
                {"transmittance_mean", s.fog_transmittance_mean},
                {"sky", {s.fog_sky.x, s.fog_sky.y, s.fog_sky.z}},
                {"glow_mean", s.fog_glow_mean}};
  return j;
}

nlohmann::json rain_run_json(const rain::RainField& field, const std::string& depth) {
  const auto& s = field.settings();
  const auto& c = field.camera();
  nlohmann::json camera = detail::camera_json(c);
  camera.update({{"focal_px", c.focal_px()},
                 {"pixel_pitch_um", c.pixel_pitch_m() * 1e6},
                 {"f_number", c.f_number},
                 {"focus_m", c.focus_m},
                 {"exposure_s", c.exposure_s},
                 {"fps", c.fps}});
  nlohmann::json classes = nlohmann::json::array();
  for (const auto& rc : field.classes())
    classes.push_back({{"radius_mm", {rc.radius_lo_m * 1e3, rc.radius_hi_m * 1e3}},
                       {"number_per_m3", rc.number_per_m3},
                       {"beta_per_m", rc.beta_per_m},
                       {"resolved_to_m", rc.resolved_to_m},
                       {"drops", rc.count}});
  return {{"program", "hydrolux rain"},
          {"seed", s.seed},
          {"rain", {{"rain_rate_mmh", s.rain_rate_mmh}, {"wind_mps", s.wind_mps}, {"wind_dir_deg", s.wind_dir_deg},
                    {"near_m", s.near_m}, {"far_m", s.far_m}, {"min_radius_mm", s.min_radius_mm},
                    {"max_radius_mm", s.max_radius_mm}, {"min_alpha", s.min_alpha}, {"extent_m", s.extent_m},
                    {"backdrop_m", s.backdrop_m}, {"oscillation", s.oscillation},
                    {"refractive_index", s.refractive_index}, {"unresolved", s.unresolved},
                    {"radius_classes", s.radius_classes}}},
          {"camera", camera},
          {"depth", depth},
          {"field", {{"drops", field.drop_count()}, {"beta_total_per_m", field.beta_total_per_m()},
                     {"classes", classes}}}};
}

}  // namespace hydrolux::io
