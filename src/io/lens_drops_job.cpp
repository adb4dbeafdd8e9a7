// A lens-drops run over files (lens_drops_job.hpp): drops on the lens as an effect of the frame
// driver (frame_driver.hpp), which owns the photograph, folder and video modes of
// `hydrolux lens-drops`.
#include "hydrolux/io/lens_drops_job.hpp"

#include <fmt/format.h>

#include "frame_job.hpp"
#include "hydrolux/core/error.hpp"
#include "hydrolux/rain/rain.hpp"

namespace hydrolux::io {

namespace {

static_assert(rain::LensDropsFileOptions{}.png_compression == kDefaultPngCompression, "one default for PNG files");

// Drops on the lens over frames: frame k of a sequence gets the drops of seed + k (each frame its own
// drops, any frame on its own), so frames may differ in size.
class LensDropsEffect final : public FrameEffect {
 public:
  explicit LensDropsEffect(const LensDropsJob& a) : a_(a) {}

  const EffectTraits& traits() const override { return lens_drops_traits(); }
  // The settings are checked before any folder is made (a frame's size is not needed for that).
  void validate() override { (void)rain::place_lens_drops(a_.settings, 1, 1); }
  void check_memory(const std::string& origin, int width, int height, int channels, bool,
                    double extra_bytes_per_pixel) const override {
    rain::check_lens_drops_memory(a_.settings, origin, width, height, channels, extra_bytes_per_pixel);
  }
  void prepare(const SequenceStart&) override {}
  void render(const Image& frame, const Image*, std::size_t k, bool, const std::string& origin,
              FrameOutput& out) override {
    rain::LensDropSettings s = a_.settings;
    s.seed = (a_.settings.seed + k) % (rain::kMaxSeed + 1);
    last_ = detail::render_frame(origin, [&] { return rain::render_lens_drops(frame, s); });
    out.image = std::move(last_.image);
    out.mask = std::move(last_.mask);
    out.stats = {{"seed", s.seed},
                 {"drops", last_.drops},
                 {"coverage", last_.coverage},
                 {"blur_diameter_px", last_.blur_diameter_px},
                 {"negative_values_clamped", last_.negative_values_clamped}};
    out.negative_values = last_.negative_values_clamped;
  }
  nlohmann::json run_json() const override {
    const auto& s = a_.settings;
    nlohmann::json drops = {{"drops", s.drops},
                            {"min_radius_mm", s.min_radius_mm},
                            {"max_radius_mm", s.max_radius_mm},
                            {"trail_fraction", s.trail_fraction},
                            {"trail_length_mm", s.trail_length_mm},
                            {"contact_angle_deg", s.contact_angle_deg},
                            {"water_ior", s.water_ior},
                            {"glass_ior", s.glass_ior},
                            {"seed", s.seed}};
    if (s.coverage) drops["coverage"] = *s.coverage;
    return {{"drops", drops},
            {"camera",
             {{"glass_distance_m", s.glass_distance_m},
              {"focal_mm", s.focal_mm},
              {"sensor_width_mm", s.sensor_width_mm},
              {"f_number", s.f_number},
              {"focus_m", s.focus_m},
              {"samples", s.samples}}}};
  }

  void fill_result(LensDropsJobResult& out) const {
    out.drops = last_.drops;
    out.coverage = last_.coverage;
    out.blur_diameter_px = last_.blur_diameter_px;
  }

 private:
  const LensDropsJob& a_;
  rain::LensDropsResult last_;  // its image and mask handed on: the counts only
};

}  // namespace

const EffectTraits& lens_drops_traits() {
  static const EffectTraits t{
      .noun = "frames with drops",
      .one_size = false,
      .paths = rain::lens_drops_path_params()};
  return t;
}

LensDropsJobResult run_lens_drops_job(const LensDropsJob& a, const FrameHooks& hooks) {
  LensDropsEffect effect(a);
  return detail::run_frame_job<LensDropsJobResult>(
      frame_request(a, a.files.png_compression, a.video_files.crf, a.given), effect, hooks);
}

std::string lens_drops_summary(const LensDropsJobResult& r) {
  return fmt::format("lens-drops: {} frame{}; {} drops covering {:.1f}% of the frame, blurred by a {:.1f} px circle of "
                     "confusion; {:.2f} s",
                     r.frames, r.frames == 1 ? "" : "s", r.drops, 100 * r.coverage, r.blur_diameter_px, r.seconds);
}

}  // namespace hydrolux::io
