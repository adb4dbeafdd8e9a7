// The gallery's fog (hydrolux fog, docs/fog.md): the built-in street at dusk with street lamps,
// clear and in fog of two visibilities; the mask; the lamps' glow against the same fog without it; and
// rain and fog in one pass against each alone.
#include <algorithm>
#include <vector>

#include "entries.hpp"
#include "hydrolux/rain/fog.hpp"
#include "hydrolux/rain/rain.hpp"

namespace hydrolux::gallery::detail {

namespace {

constexpr int kWidth = 400, kHeight = 225, kGap = 6;

// The built-in street at dusk (a fifth of its light) with six lamps of radiance 40 beside the road,
// from about 20 to 90 m away (rows below the horizon: on the ground plane).
Image dusk_street() {
  Image img = rain::builtin_scene(street_camera(kWidth, kHeight));
  for (auto& v : img.pixels) v *= 0.2f;
  const int lamps[][2] = {{70, 140}, {120, 127}, {155, 120}, {330, 140}, {280, 127}, {245, 120}};
  for (const auto& l : lamps)
    for (int y = l[1] - 1; y <= l[1] + 1; ++y)
      for (int x = l[0] - 1; x <= l[0] + 1; ++x)
        for (int k = 0; k < 3; ++k) img.at(x, y, k) = k == 2 ? 25.f : 40.f;
  return img;
}

rain::FogFrame foggy(const Image& clear, double visibility_m, bool glow) {
  rain::FogSettings s;
  s.visibility_m = visibility_m;
  s.glow = glow;
  return rain::render_fog(clear, nullptr, street_camera(kWidth, kHeight), s, rain::fog_optics(s));
}

Entry fog_figure() {
  return image_entry(
      "fog.png", "Fog over the street at dusk: clear, 300 m and 80 m visibility (1:1)",
      "hydrolux fog over the built-in street at a fifth of its light with six lamps (400x225, 35 mm on 36 mm, "
      "camera 1.7 m above the ground plane, backdrop 1000 m): clear (left), visibility 300 m (middle) and 80 m "
      "(right) by Koschmieder (beta = 3.912 / V), the phase function of Shettle & Fenn's advection fog (mode "
      "radius 10 um). The buildings and the horizon fade into the sky's colour (estimated from the frame's top "
      "rows: the dusk sky's blue-grey) and the near road keeps more of its contrast. Each lamp gains a small round "
      "halo of light scattered once and spread by the droplets' forward peak, in proportion to tau e^-tau: at "
      "300 m every lamp keeps its halo; at 80 m the farthest lamps (about 83 m away, optical depth about 4) are "
      "dimmer points with smaller halos, most of their light scattered many times into the veil.",
      [] {
        const Image clear = dusk_street();
        return side_by_side({clear, foggy(clear, 300, true).image, foggy(clear, 80, true).image}, kGap);
      });
}

Entry fog_glow_figure() {
  return image_entry(
      "fog_glow.png", "The lamps' glow and the mask (1:1 crops)",
      "The left lamps of the street at dusk in fog of 150 m visibility, 1:1 crops of 160x70 pixels: without the "
      "glow (left: attenuation and airlight only), with it (middle), and the mask 1 - t of the whole crop "
      "(right; white is all fog), which pairs the foggy frame with the clear one: foggy = clear t + sky (1 - t) "
      "+ glow.",
      [] {
        const Image clear = dusk_street();
        const auto with = foggy(clear, 150, true), without = foggy(clear, 150, false);
        return side_by_side({crop(without.image, 40, 100, 160, 70), crop(with.image, 40, 100, 160, 70),
                             crop(with.alpha, 40, 100, 160, 70)},
                            kGap);
      });
}

Entry rain_fog_figure() {
  return image_entry(
      "rain_fog.png", "Rain and fog in one pass: rain alone, fog alone, both as one veil (1:1 crops)",
      "hydrolux rain over the built-in street in daylight at 1280x720 (35 mm on 36 mm, backdrop 1000 m), 1:1 "
      "crops of 400x225 pixels of the road: rain of 100 mm/h with a 3 m/s wind (left), fog of 150 m visibility "
      "alone (hydrolux fog, middle), and both in one pass (hydrolux rain --visibility-m 150, right; "
      "docs/fog.md). The fog's and the unresolved rain's extinctions add along each ray and their airlights mix "
      "by optical depth, so the street fades as in the fog alone and not under two veils' sum; each streak is "
      "seen through the fog in front of it and against the fogged road behind it, so the streaks lose most of "
      "their contrast, lit as they are by the fogged scene.",
      [] {
        const rain::RainCamera cam = street_camera(1280, 720);
        const Image clear = rain::builtin_scene(cam);
        rain::RainSettings s;
        s.rain_rate_mmh = 100;
        s.wind_mps = 3;
        s.backdrop_m = 1000;
        rain::RainRenderer plain{rain::RainField(s, cam)}, fogged{rain::RainField(s, cam)};
        rain::FogSettings f;
        f.visibility_m = 150;
        fogged.set_fog(f);
        f.backdrop_m = s.backdrop_m;
        const Image fog_alone = rain::render_fog(clear, nullptr, cam, f, rain::fog_optics(f)).image;
        return side_by_side({crop(plain.render(clear, nullptr, 0).image, 340, 380, 400, 225),
                             crop(fog_alone, 340, 380, 400, 225),
                             crop(fogged.render(clear, nullptr, 0).image, 340, 380, 400, 225)},
                            kGap);
      });
}

}  // namespace

std::vector<Entry> fog_entries() { return {fog_figure(), fog_glow_figure(), rain_fog_figure()}; }

}  // namespace hydrolux::gallery::detail
