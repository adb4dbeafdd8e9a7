// The gallery's rain (hydrolux rain, docs/rain.md): the built-in street before and after rain of 5, 25
// and 100 mm/h; a short exposure (drops) against a long one (streaks); the wind's slant; and the mask
// that pairs a rainy frame with its clear one.
#include <cmath>
#include <initializer_list>
#include <vector>

#include "entries.hpp"
#include "hydrolux/rain/rain.hpp"

namespace hydrolux::gallery::detail {

namespace {

constexpr int kWidth = 400, kHeight = 225, kGap = 6;

rain::RainFrame rainy(const rain::RainSettings& s, const rain::RainCamera& c) {
  rain::RainRenderer r(rain::RainField(s, c));
  return r.render(rain::builtin_scene(c), nullptr, 0);
}

// A crop of `img` scaled up by `zoom` (nearest), so streaks a pixel wide stay visible in the figure.
Image crop_zoom(const Image& img, int x0, int y0, int w, int h, int zoom) {
  Image out(w * zoom, h * zoom, 3);
  for (int y = 0; y < h * zoom; ++y)
    for (int x = 0; x < w * zoom; ++x)
      for (int k = 0; k < 3; ++k) out.at(x, y, k) = img.at(x0 + x / zoom, y0 + y / zoom, k);
  return out;
}

// The road below the horizon, where streaks show against the asphalt: a crop at 2x.
Image road(const Image& img) { return crop_zoom(img, 120, 130, 200, 94, 2); }

// One road crop per value, the rain and camera set by `set(settings, camera, value)`, side by side.
template <typename Set>
Image road_panels(std::initializer_list<double> values, Set set) {
  std::vector<Image> p;
  for (const double v : values) {
    rain::RainSettings s;
    auto c = street_camera(kWidth, kHeight);
    set(s, c, v);
    p.push_back(road(rainy(s, c).image));
  }
  return side_by_side(p, kGap);
}

Entry rain_rates_figure() {
  return image_entry(
      "rain_rates.png", "Rain over a frame: 0, 5, 25 and 100 mm/h",
      "hydrolux rain over the built-in street (400x225, a 35 mm lens on a 36 mm sensor, 1/125 s, wind 2 m/s to the "
      "right, seed 1): clear, then 5, 25 and 100 mm/h (left to right), and below each a 2x crop of the road. "
      "Marshall-Palmer drops fall at Gunn & Kinzer's speeds; each streak is one drop's motion blur during the "
      "exposure, lit by the frame itself through Garg & Nayar's drop model, so it is lighter than the road and the "
      "grass and darker than the sky. A drop covers a pixel for a small part of the exposure (its disk passes a point "
      "in 2a / v: 0.3 ms of 8 ms for a 1 mm drop), so streaks change it by about 1%, a few per cent at most. Farther "
      "rain that no single drop resolves veils the distance (its extinction and airlight), more as the rate rises.",
      [] {
        std::vector<Image> full{rain::builtin_scene(street_camera(kWidth, kHeight))}, crops{road(full.front())};
        for (const double rate : {5.0, 25.0, 100.0}) {
          rain::RainSettings s;
          s.rain_rate_mmh = rate;
          s.wind_mps = 2;
          full.push_back(rainy(s, street_camera(kWidth, kHeight)).image);
          crops.push_back(road(full.back()));
        }
        return stacked({side_by_side(full, kGap), side_by_side(crops, kGap)}, kGap);
      });
}

Entry rain_exposure_figure() {
  return image_entry(
      "rain_exposure.png", "Drops and streaks: the exposure time",
      "25 mm/h, wind 2 m/s, a 2x crop of the road: exposures of 1/2000 s, 1/250 s and 1/30 s (left to right). A "
      "short exposure freezes the drops into dots; a longer one smears each drop over v t f / z pixels into a "
      "streak whose light is spread along it (a drop covers a pixel for only part of the exposure), so at 1/30 s "
      "the streaks are long and faint, as Garg & Nayar describe them.",
      [] {
        return road_panels({1.0 / 2000, 1.0 / 250, 1.0 / 30}, [](rain::RainSettings& s, rain::RainCamera& c, double t) {
          s.rain_rate_mmh = 25;
          s.wind_mps = 2;
          c.exposure_s = t;
          c.fps = 30;
        });
      });
}

Entry rain_wind_figure() {
  return image_entry(
      "rain_wind.png", "The wind slants the streaks",
      "100 mm/h at 1/60 s, a 2x crop of the road: calm (left), 5 m/s blowing to the right (middle) and 10 m/s to "
      "the left (right). Drops move with the air, so a streak leans by the wind speed over the fall speed: about 40 "
      "degrees for a 1 mm drop (6.5 m/s) in 5 m/s.",
      [] {
        return road_panels({0.0, 5.0, -10.0}, [](rain::RainSettings& s, rain::RainCamera& c, double w) {
          s.rain_rate_mmh = 100;
          s.wind_mps = std::abs(w);
          s.wind_dir_deg = w < 0 ? -90 : 90;
          c.exposure_s = 1.0 / 60;
        });
      });
}

Entry rain_mask_figure() {
  return image_entry(
      "rain_mask.png", "The rain layer's mask",
      "The 25 mm/h frame (left) and its mask (right, --mask-out): the rain's alpha, so that rainy = clear (1 - "
      "alpha) + layer holds exactly for a de-raining dataset. The streaks are the drops; the veil growing towards "
      "the horizon is the unresolved rain.",
      [] {
        rain::RainSettings s;
        s.rain_rate_mmh = 25;
        s.wind_mps = 2;
        const auto f = rainy(s, street_camera(kWidth, kHeight));
        return side_by_side({f.image, mask_picture(f.alpha)}, kGap);
      });
}

}  // namespace

std::vector<Entry> rain_entries() {
  return {rain_rates_figure(), rain_exposure_figure(), rain_wind_figure(), rain_mask_figure()};
}

}  // namespace hydrolux::gallery::detail
