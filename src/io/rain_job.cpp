// A rain run over files (rain_job.hpp): rain as an effect of the frame driver (frame_driver.hpp),
// which owns the photograph, folder and video modes of `hydrolux rain`.
#include "hydrolux/io/rain_job.hpp"

#include <fmt/format.h>

#include <optional>

#include "frame_job.hpp"
#include "hydrolux/core/error.hpp"
#include "hydrolux/core/parse.hpp"
#include "hydrolux/io/rain_report.hpp"

namespace hydrolux::io {

namespace {

// The video's own frame rate, size and the exposure it allows, said in the video's terms.
void check_video_camera(const rain::RainCamera& cam, const std::string& video) {
  try {
    rain::validate(cam);
  } catch (const DomainError& e) {
    if (e.quantity() == "fps" || e.quantity() == "width" || e.quantity() == "height")
      throw Error(fmt::format("--video {}: its {} {:g} is {}", video,
                              e.quantity() == "fps" ? "frame rate (1/s)" : e.quantity().c_str(), e.value(),
                              e.range_text()));
    if (e.quantity() == "exposure_s")
      throw Error(fmt::format("--exposure-s {:g}: is longer than one frame of --video {} ({:g} frames/s); at most {:g} s",
                              e.value(), video, cam.fps, 1.0 / cam.fps));
    throw;
  }
}

// Rain over frames: one rain field for the sequence (built at its first frame), frame k rendered
// at the field's time frame_index + k.
class RainEffect final : public FrameEffect {
 public:
  explicit RainEffect(const RainJob& a) : a_(a) {}

  const EffectTraits& traits() const override { return rain_traits(); }
  void check_options(const FrameRequest&) const override {
    rain::refuse_fog_settings_without_fog(a_.options);
  }
  void check_mode(const FrameRequest& r, FrameMode mode) const override {
    if (mode == FrameMode::image && a_.size && !synthetic(r))
      throw Error("--size: goes with --image builtin (a photograph has its own size)");
  }
  bool synthetic(const FrameRequest& r) const override { return r.image && *r.image == "builtin"; }
  Image make_synthetic(const FrameRequest&, bool with_layer) const override {
    const std::string size = a_.size.value_or("1280x720");
    const auto wh = parse::pair(size, 'x');
    if (!wh) throw Error(fmt::format("--size {}: not WxH", size));
    const rain::RainCamera c = rain::camera_for(a_.options, int((*wh)[0]), int((*wh)[1]));
    rain::check_render_memory(c, 3, with_layer, "--size " + size);
    return rain::builtin_scene(c);
  }
  void check_memory(const std::string& origin, int width, int height, int channels, bool with_layer,
                    double extra_bytes_per_pixel) const override {
    rain::check_render_memory(rain::camera_for(a_.options, width, height), channels, with_layer, origin,
                              extra_bytes_per_pixel);
  }
  void prepare(const SequenceStart& s) override {
    rain::RainCamera cam = rain::camera_for(a_.options, s.width, s.height);
    if (s.mode == FrameMode::video) {
      cam.fps = s.video_fps;
      check_video_camera(cam, s.input);
    }
    rain::check_render_memory(cam, s.channels, s.with_layer, s.origin, s.extra_bytes_per_pixel);
    renderer_.emplace(make_renderer(cam, !s.depth));
  }
  void render(const Image& frame, const Image* depth, std::size_t k, bool with_layer, const std::string& origin,
              FrameOutput& out) override {
    // The output's buffers lent to the renderer and taken back: a frame's buffers are reused.
    rain::RainFrame r;
    r.image = std::move(out.image);
    r.alpha = std::move(out.mask);
    r.layer = std::move(out.layer);
    const std::int64_t index = a_.files.frame_index + std::int64_t(k);
    try {
      renderer_->render_into(frame, depth, index, with_layer, r);
    } catch (const rain::NonFinitePixel& e) {
      throw Error(fmt::format("{}: {}", origin, e.what()));
    }
    out.image = std::move(r.image);
    out.mask = std::move(r.alpha);
    out.layer = std::move(r.layer);
    out.stats = rain_stats_json(r.stats);
    out.stats["frame_index"] = index;
    out.negative_values = r.stats.negative_values_clamped;
    last_ = r.stats;
  }
  nlohmann::json run_json() const override {
    return rain_run_json(renderer_->field(), detail::depth_source(a_, "ground plane"));
  }

  void fill_result(RainJobResult& out) const {
    out.rain_rate_mmh = renderer_->field().settings().rain_rate_mmh;
    out.drops = renderer_->field().drop_count();
    out.last = last_;
  }

 private:
  // The renderer for one camera (the library's TooManyDrops names the settings to change).
  rain::RainRenderer make_renderer(const rain::RainCamera& cam, bool ground_plane) const {
    rain::RainRenderer r(rain::RainField(a_.options.settings, cam, ground_plane));
    if (a_.options.has_fog()) r.set_fog(a_.options.fog);
    return r;
  }

  const RainJob& a_;
  std::optional<rain::RainRenderer> renderer_;
  rain::RainStats last_;
};

}  // namespace

const EffectTraits& rain_traits() {
  static const EffectTraits t{
      .noun = "rainy frames",
      .paths = rain::rain_path_params()};
  return t;
}

RainJobResult run_rain_job(const RainJob& a, const RainJobHooks& hooks) {
  RainEffect effect(a);
  return detail::run_frame_job<RainJobResult>(frame_request(a, a.files.png_compression, a.files.crf, a.given,
                                                            a.files.depth_scale_m),
                                              effect, hooks);
}

std::string rain_summary(const RainJobResult& r) {
  const auto& st = r.last;
  return fmt::format(
      "rain: {} frame{} at {:g} mm/h; {} drops in the field, {} streaks in view (length p50 {:.1f} px, p95 "
      "{:.1f} px); drops {:.2f}x the luminance under them; {:.2f} s ({:.1f} frames/s)",
      r.frames, r.frames == 1 ? "" : "s", r.rain_rate_mmh, r.drops, st.drops_in_view, st.streak_length_px_p50,
      st.streak_length_px_p95,
      st.background_luminance_mean > 0 ? st.drop_luminance_mean / st.background_luminance_mean : 0.0, r.seconds,
      r.seconds > 0 ? double(r.frames) / r.seconds : 0.0);
}

}  // namespace hydrolux::io
