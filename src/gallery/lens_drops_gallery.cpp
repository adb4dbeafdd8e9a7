// The gallery's drops on the lens (hydrolux lens-drops, docs/lens-drops.md): the built-in street
// before and after, with the mask, at 1:1; and the same drops sharp (a pinhole) against the
// aperture's defocus.
#include <algorithm>
#include <vector>

#include "entries.hpp"
#include "hydrolux/color/srgb.hpp"
#include "hydrolux/rain/lens_drops.hpp"
#include "hydrolux/rain/rain.hpp"

namespace hydrolux::gallery::detail {

namespace {

constexpr int kWidth = 640, kHeight = 360, kGap = 6;

Image street() {
  rain::RainCamera c;
  c.width = kWidth;
  c.height = kHeight;
  c.focal_mm = 35;
  return rain::builtin_scene(c);
}

Image crop(const Image& img, int x0, int y0, int w, int h) {
  Image out(w, h, 3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int k = 0; k < 3; ++k) out.at(x, y, k) = img.at(x0 + x, y0 + y, std::min(k, img.channels - 1));
  return out;
}

// The mask as --mask-out writes it (PNG codes = coverage), grey.
Image mask_picture(const Image& mask) {
  Image out(mask.width, mask.height, 3);
  for (int y = 0; y < mask.height; ++y)
    for (int x = 0; x < mask.width; ++x)
      for (int k = 0; k < 3; ++k) out.at(x, y, k) = float(color::srgb_decode(double(mask.at(x, y, 0))));
  return out;
}

}  // namespace

std::vector<Entry> lens_drops_entries() {
  std::vector<Entry> e;
  e.push_back(image_entry(
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
        // The full frame above the crops, centred on the same dark grey.
        Image out(row.width, kHeight + kGap + row.height, 3);
        std::fill(out.pixels.begin(), out.pixels.end(), 0.02f);
        const int off = std::max(0, (row.width - kWidth) / 2);
        for (int y = 0; y < kHeight; ++y)
          for (int x = 0; x < std::min(kWidth, row.width); ++x)
            for (int k = 0; k < 3; ++k) out.at(off + x, y, k) = r.image.at(x, y, k);
        for (int y = 0; y < row.height; ++y)
          for (int x = 0; x < row.width; ++x)
            for (int k = 0; k < 3; ++k) out.at(x, kHeight + kGap + y, k) = row.at(x, y, k);
        return out;
      }));
  e.push_back(image_entry(
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
      }));
  e.push_back(image_entry(
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
      }));
  return e;
}

}  // namespace hydrolux::gallery::detail
