// The gallery's drops on the lens (hydrolux lens-drops, docs/lens-drops.md): the built-in street
// before and after, with the mask, at 1:1; and the same drops sharp (a pinhole) against the
// aperture's defocus.
#include <vector>

#include "entries.hpp"
#include "hydrolux/rain/lens_drops.hpp"
#include "hydrolux/rain/rain.hpp"

namespace hydrolux::gallery::detail {

namespace {

constexpr int kWidth = 640, kHeight = 360, kGap = 6;

Image street() { return rain::builtin_scene(street_camera(kWidth, kHeight)); }

Entry lens_drops_figure() {
  return image_entry(
      "lens_drops.png", "Drops on the windshield: before, after and the mask (1:1)",
      "hydrolux lens-drops with its defaults (seed 2) over the built-in street (640x360): 150 drops of 0.4-2 mm "
      "footprint radius and 60 degree contact angle on glass 10 cm before a 6 mm lens (6.17 mm sensor) at f/2 "
      "focused at 10 m. Top: the whole frame after. Below, a 1:1 crop of the horizon: clean, with drops, and the "
      "mask (white = covered). Each drop is a small lens that shows the scene behind it upside down (the figure "
      "below shows it sharp); blurred, this makes the drops over the road lighter than the asphalt (they show the "
      "sky) and those over the sky greyer (they show the ground). The glass is far out of focus (a circle of "
      "confusion of about 18 px), so the drops are soft, see-through discs while the scene stays sharp, and only "
      "the larger drops reach full coverage in the mask. Clean, degraded and mask are the triple a raindrop-removal "
      "network trains on.",
      [] {
        const Image clean = street();
        rain::LensDropSettings s;
        s.seed = 2;
        const auto r = rain::render_lens_drops(clean, s);
        const int x0 = 200, y0 = 100, w = 210, h = 150;
        const Image row = side_by_side({crop(clean, x0, y0, w, h), crop(r.image, x0, y0, w, h),
                                        crop(mask_picture(r.mask), x0, y0, w, h)},
                                       kGap);
        return stacked({r.image, row}, kGap);  // the full frame above the crops
      });
}

Entry lens_drops_defocus_figure() {
  return image_entry(
      "lens_drops_defocus.png", "Drops on the lens: sharp and defocused (1:1)",
      "The same drops (seed 5, 40 drops of 1.5-3 mm footprint radius, 60 degrees) at 1:1 over the horizon of the "
      "built-in street: a pinhole (f-number 0, left), f/2 (middle) and f/8 (right), focused at 10 m. Sharp, each "
      "cap shows the inverted scene, its magnification 1 - d / f for glass at d = 10 cm and the cap's focal length "
      "f = R / (n - 1); the aperture blurs the drops by the circle of confusion at 10 cm (about 18 px at f/2, "
      "5 px at f/8), keeping their light (the kernel conserves flux).",
      [] {
        const Image clean = street();
        std::vector<Image> p;
        for (const double fnum : {0.0, 2.0, 8.0}) {
          rain::LensDropSettings s;
          s.seed = 5;
          s.drops = 40;
          s.min_radius_mm = 1.5;
          s.max_radius_mm = 3;
          s.f_number = fnum;
          p.push_back(crop(rain::render_lens_drops(clean, s).image, 200, 100, 210, 150));
        }
        return side_by_side(p, kGap);
      });
}

Entry lens_drops_trails_figure() {
  return image_entry(
      "lens_drops_trails.png", "Drops that ran down the glass (1:1)",
      "--trail-fraction 0.4 (seed 3) at f/8 over the built-in street, a 1:1 crop of the horizon: four drops in ten "
      "have run down and left a trail of small drops above them, 30 mm long on the glass 10 cm away (about 190 px "
      "here, most of them starting or ending outside the crop). The large drops show the street inverted; the trail "
      "drops are caps like them but only a few pixels wide, so they read as a dotted, slightly blurred line. The "
      "trails are chains of separate caps, not the smooth elongated rivulets of a fast-running drop "
      "(docs/lens-drops.md, limits).",
      [] {
        rain::LensDropSettings s;
        s.seed = 3;
        s.trail_fraction = 0.4;
        s.f_number = 8;
        return crop(rain::render_lens_drops(street(), s).image, 160, 60, 320, 240);
      });
}

}  // namespace

std::vector<Entry> lens_drops_entries() {
  return {lens_drops_figure(), lens_drops_defocus_figure(), lens_drops_trails_figure()};
}

}  // namespace hydrolux::gallery::detail
