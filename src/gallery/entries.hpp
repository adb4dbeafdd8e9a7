#pragma once
// The gallery's figures, shared between the files that define them (internal to the gallery).
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "hydrolux/core/image.hpp"
#include "hydrolux/gallery/gallery.hpp"
#include "hydrolux/io/svg_plot.hpp"
#include "hydrolux/rain/rain.hpp"

namespace hydrolux::gallery::detail {

struct Entry {
  Entry() = default;
  Entry(Figure f, std::function<std::string()> make) : figure(std::move(f)), render(std::move(make)) {}

  Figure figure;
  std::function<std::string()> render;  // the file's bytes: SVG text, or an encoded PNG
};

// The one way to declare a figure: its file, title and caption, and how it is made. Each figure is
// a function `Entry <file>_figure()` in the file of its part of the gallery.
// A figure made as an image, written as PNG (the sRGB curve applied).
Entry image_entry(std::string file, std::string title, std::string caption, std::function<Image()> make);
// A figure drawn as a plot, written as SVG.
Entry plot_entry(std::string file, std::string title, std::string caption, std::function<io::Plot()> make);

// Pictures (pictures.cpp).
// Panels side by side (equal heights, RGB), `gap` pixels apart on a dark grey background.
Image side_by_side(const std::vector<Image>& panels, int gap);
// Rows top to bottom, each centred, `gap` pixels apart on side_by_side's dark grey.
Image stacked(const std::vector<Image>& rows, int gap);
// A w x h crop of `img` from (x0, y0), RGB (a one-channel image as grey).
Image crop(const Image& img, int x0, int y0, int w, int h);
// A mask as --mask-out writes it (PNG codes = the mask's values), grey.
Image mask_picture(const Image& mask);
// The camera of the frame figures (rain, fog, lens drops) over the built-in street: a 35 mm lens.
rain::RainCamera street_camera(int width, int height);

// The rain drop's figures (issue #4): rendered pictures, the exact tracer beside the model, the
// undistorted view, Beard & Chuang's shapes.
std::vector<Entry> drop_entries();

// The Lee diagrams (issue #10): theories side by side, the sun's disk and a size spread, colour
// against angle, the corona and glory of cloud droplets.
std::vector<Entry> lee_entries();

// Rainbows of non-spherical drops (issue #25): the bow's arc for spherical and Beard-Chuang drops,
// and a twinned bow.
std::vector<Entry> shape_entries();

// Rainbows in a scene (issue #11): hydrolux sky's CPU renders over sun elevation, drop radius and
// rain rate, a corona, and seed 002's optimisations beside the per-pixel reference.
std::vector<Entry> sky_entries();

// Rain over a frame (issue #12): the built-in street at three rain rates, exposure, defocus, the mask.
std::vector<Entry> rain_entries();

// Drops on the lens or windshield (issue #27): before, after and the mask; sharp against defocused.
std::vector<Entry> lens_drops_entries();

// Fog over a frame (issue #27): clear against two visibilities, the lamps' glow and the mask.
std::vector<Entry> fog_entries();

}  // namespace hydrolux::gallery::detail
