// A fog run over files (fog_job.hpp): fog as an effect of the frame driver (frame_driver.hpp), which
// owns the photograph, folder and video modes of `hydrolux fog`.
#include "hydrolux/io/fog_job.hpp"

#include <fmt/format.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include "frame_job.hpp"
#include "hydrolux/core/error.hpp"
#include "hydrolux/rain/rain.hpp"

namespace hydrolux::io {

namespace {

nlohmann::json stats_json(const rain::FogStats& st) {
  return {{"transmittance", {{"mean", st.transmittance_mean}, {"min", st.transmittance_min}, {"max", st.transmittance_max}}},
          {"range_m_median", st.range_m_median},
          {"sky_fraction", st.sky_fraction},
          {"sky_rgb", {st.sky[0], st.sky[1], st.sky[2]}},
          {"glow_luminance_mean", st.glow_mean},
          {"glow_source_fraction", st.glow_source_fraction},
          {"negative_values_clamped", st.negative_values_clamped}};
}

// Fog over frames: the optics once for the run, the camera from the first frame, and one sky colour
// for a sequence (the first frame's: no flicker from frame to frame).
class FogEffect final : public FrameEffect {
 public:
  explicit FogEffect(const FogJob& a) : a_(a) {}

  const EffectTraits& traits() const override { return fog_traits(); }
  // The library's quantity names -> the flags (a DomainError from validate() names the quantity).
  void validate() override {
    const auto& s = a_.options.settings;
    rain::validate(s);
    optics_ = rain::fog_optics(s);
  }
  // A frame too large for the memory left, refused from its header, naming what would fit.
  void check_memory(const std::string& origin, int width, int height, int channels, bool,
                    double extra_bytes_per_pixel) const override {
    // check_fog_memory's estimate with the pipeline's frames in flight.
    const bool glow = a_.options.settings.glow;
    rain::check_frame_memory(origin, "fog", width, height,
                             rain::estimated_fog_bytes(width, height, channels, glow, extra_bytes_per_pixel),
                             rain::estimated_fog_bytes(0, 0, channels, glow));
  }
  void prepare(const SequenceStart& s) override { cam_ = rain::fog_camera_for(a_.options, s.width, s.height); }
  void render(const Image& frame, const Image* depth, std::size_t, bool, const std::string& origin,
              FrameOutput& out) override {
    rain::FogFrame r = detail::render_frame(
        origin, [&] { return rain::render_fog(frame, depth, cam_, a_.options.settings, optics_, sky_); });
    if (!sky_) sky_ = r.stats.sky;
    out.image = std::move(r.image);
    out.mask = std::move(r.alpha);
    out.stats = stats_json(r.stats);
    out.negative_values = r.stats.negative_values_clamped;
    last_ = r.stats;
  }
  nlohmann::json run_json() const override {
    const auto& s = a_.options.settings;
    const auto& o = optics_;
    const auto num = [](double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); };
    return {{"fog",
             {{"route", s.visibility_m ? "koschmieder" : "mie"},
              {"beta_per_m", o.beta_per_m},
              {"visibility_m", o.visibility_m},
              {"lwc_g_m3", num(o.lwc_g_m3)},
              {"number_per_cm3", num(o.number_per_cm3)},
              {"mode_radius_um", s.mode_radius_um},
              {"size_alpha", s.size_alpha},
              {"effective_radius_um", o.effective_radius_um},
              {"asymmetry_g", o.g},
              {"wavelength_nm", s.wavelength_nm},
              {"glow", s.glow}}},
            {"camera", detail::camera_json(cam_)},
            {"depth", detail::depth_source(a_, fmt::format("ground plane, backdrop {:g} m", s.backdrop_m))}};
  }

  void fill_result(FogJobResult& out) const {
    out.optics = optics_;
    out.last = last_;
  }

 private:
  const FogJob& a_;
  rain::FogOptics optics_;
  rain::RainCamera cam_;
  std::optional<Vec3> sky_;
  rain::FogStats last_;
};

}  // namespace

const EffectTraits& fog_traits() {
  static const EffectTraits t{
      .noun = "foggy frames",
      .folder_input_key = "input_dir",
      .paths = rain::fog_path_params()};
  return t;
}

FogJobResult run_fog_job(const FogJob& a, const FogJobHooks& hooks) {
  FogEffect effect(a);
  return detail::run_frame_job<FogJobResult>(frame_request(a, a.files.png_compression, a.video_files.crf, a.given,
                                                           a.files.depth_scale_m),
                                             effect, hooks);
}

std::string fog_summary(const FogJobResult& r) {
  const auto& st = r.last;
  return fmt::format(
      "fog: {} frame{}; beta {:.4g} /m (visibility {:.4g} m); transmittance mean {:.3f} (min {:.3f}); sky ({:.3g}, {:.3g}, "
      "{:.3g}); glow {:.3g} mean luminance; {:.2f} s",
      r.frames, r.frames == 1 ? "" : "s", r.optics.beta_per_m, r.optics.visibility_m, st.transmittance_mean,
      st.transmittance_min, st.sky[0], st.sky[1], st.sky[2], st.glow_mean, r.seconds);
}

}  // namespace hydrolux::io
