// The gallery's Lee-diagram figures: Mie, Airy and geometric optics side by side; the diagram with
// and without the sun's disk and a size spread; colour against angle for 10, 100 and 1000 um drops;
// the corona and glory of 10 um droplets as they look in the sky.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "entries.hpp"
#include "hydrolux/atmos/lee.hpp"
#include "hydrolux/io/image_io.hpp"
#include "hydrolux/io/svg_plot.hpp"

namespace hydrolux::gallery::detail {

namespace {

// Smaller than the standard table (512 x 1024, 40 wavelengths, sampling 1) so that the gallery stays
// quick: half the sampling density (24 wavelengths; about 1% RMS of sampling noise, invisible at
// this size). Every panel of one figure is shown at one exposure, so their brightness compares.
constexpr int kColumns = 192, kRows = 384, kWavelengths = 24, kGap = 6;
constexpr double kSampling = 0.5;

atmos::LeeSpec gallery_spec(const char* theory, double disk_deg, double spread) {
  atmos::LeeSpec s;
  s.theory = scatter::parse_theory(theory);
  s.columns = kColumns;
  s.rows = kRows;
  s.wavelengths = int(kWavelengths / kSampling);
  s.sampling = kSampling;
  s.sun_disk_deg = disk_deg;
  s.size_spread = spread;
  return s;
}

// The profiles of 10, 100 and 1000 um drops over 120-160 degrees, shared by the colour strips and
// the luminance plot: computed once.
constexpr double kProfileRadiiUm[3] = {10, 100, 1000};
constexpr int kProfileRows = 720;
const std::vector<atmos::LeeTable>& profiles() {
  static const std::vector<atmos::LeeTable> t = [] {
    std::vector<atmos::LeeTable> v;
    for (double r : kProfileRadiiUm)
      v.push_back(atmos::compute_lee_table(atmos::profile_spec(atmos::LeeTableKind::rainbow, r, 120, 160, kProfileRows)));
    return v;
  }();
  return t;
}

// The Mie table with the sun's disk and a 10% spread, shared by two figures: computed once.
const atmos::LeeTable& mie_table() {
  static const atmos::LeeTable t = atmos::compute_lee_table(gallery_spec("mie", atmos::kSunDiskDeg, 0.1));
  return t;
}

Image display_image(const atmos::LeeTable& t, double exposure, double white) {
  const atmos::LeeImages im = atmos::lee_images(t, exposure, white);
  Image out(t.columns(), t.rows(), 3);
  out.pixels.assign(im.display.begin(), im.display.end());
  return out;
}

// One radius's profile at fine angular resolution.
atmos::LeeTable profile(atmos::LeeTableKind kind, double radius_um, double a0, double a1, int rows) {
  return atmos::compute_lee_table(atmos::profile_spec(kind, radius_um, a0, a1, rows));
}

// The sky around the sun (corona) or the antisolar point (glory) from a one-column profile over
// [0, max_deg] from the centre: a square picture `size` pixels wide spanning +-max_deg.
Image sky_disk(const atmos::LeeTable& t, bool from_antisolar, double max_deg, int size) {
  const atmos::LeeImages im = atmos::lee_images(t);
  Image out(size, size, 3);
  const int rows = t.rows();
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      const double u = (x + 0.5) / size * 2 - 1, v = (y + 0.5) / size * 2 - 1;
      const double off = std::hypot(u, v) * max_deg;  // small-angle: distance ~ angle
      const double theta = from_antisolar ? 180 - off : off;
      const double a0 = t.angle_deg.front(), a1 = t.angle_deg.back();
      double f = (theta - a0) / (a1 - a0) * (rows - 1);
      if (f < 0 || f > rows - 1) continue;
      const int i = std::min(rows - 2, int(f));
      f -= i;
      for (int c = 0; c < 3; ++c)
        out.at(x, y, c) = float((1 - f) * im.display[std::size_t(i) * 3 + std::size_t(c)] +
                                f * im.display[std::size_t(i + 1) * 3 + std::size_t(c)]);
    }
  return out;
}

Entry lee_theories_figure() {
  return image_entry(
      "lee_theories.png", "Lee diagrams: Mie, Airy and geometric optics",
      fmt::format("hydrolux lee with --theory mie, airy and geometric, side by side. In each panel the drop radius "
                  "runs from 5 um (left) to 800 um (right, log scale) and the scattering angle from 90 degrees (top) "
                  "to 180 (bottom, the antisolar point); {} wavelengths weighted by the sun's spectrum (ASTM G173 "
                  "direct) and the CIE 1931 observer, the sun's 0.53 degree disk and a 10% gamma spread of radii, "
                  "values in absolute units (sr^-1, one exposure for all three panels). Mie (left): the primary bow "
                  "near 138 degrees, the secondary near 129 with its colours reversed, Alexander's dark band between, "
                  "supernumerary bows curving inward for small drops, the broad white fogbow and, at the bottom left, "
                  "the glory. Airy theory (middle) has the primary only, and is right for large drops near the bow; "
                  "geometric optics (right: ray orders 0-3 with interference and diffraction) has a sharp caustic at "
                  "the bow where the wave theories have a finite peak, and fails for small drops. Compare Lee, Appl. Opt. 37, 5221 (1998), Figs. 4 "
                  "and 5.",
                  kWavelengths),
      [] {
        const atmos::LeeTable& mie = mie_table();
        const atmos::LeeImages scale = atmos::lee_images(mie);
        std::vector<Image> panels{display_image(mie, scale.exposure, scale.white)};
        for (const char* th : {"airy", "geometric"})
          panels.push_back(display_image(atmos::compute_lee_table(gallery_spec(th, atmos::kSunDiskDeg, 0.1)),
                                         scale.exposure, scale.white));
        return side_by_side(panels, kGap);
      });
}

Entry lee_disk_spread_figure() {
  return image_entry(
      "lee_disk_spread.png", "The sun's disk and a size spread",
      "The Mie Lee diagram (5-800 um, 90-180 degrees) four ways, from left: a point sun and one radius per column; the "
      "sun's 0.53 degree disk; a 10% gamma spread of radii under a point sun; both. The disk blurs the bows of "
      "large drops over its width (their fine interference disappears); the spread washes out the "
      "supernumeraries of small drops beyond the first two; together they give the smooth diagram a real sky "
      "shows. One exposure for all four.",
      [] {
        std::vector<atmos::LeeTable> tables;
        const std::pair<double, double> order[] = {{0.0, 0.0}, {atmos::kSunDiskDeg, 0.0}, {0.0, 0.1}};
        for (const auto& [disk, spread] : order) tables.push_back(atmos::compute_lee_table(gallery_spec("mie", disk, spread)));
        tables.push_back(mie_table());
        const atmos::LeeImages scale = atmos::lee_images(tables.back());
        std::vector<Image> panels;
        for (const auto& t : tables) panels.push_back(display_image(t, scale.exposure, scale.white));
        return side_by_side(panels, kGap);
      });
}

// Colour against angle: three radii, one strip each, on one scale; and their luminance.
Entry lee_colour_strips_figure() {
  return image_entry(
      "lee_colour_strips.png", "Rainbow colour against angle: 10, 100 and 1000 um drops",
      "Each strip is one drop radius (top to bottom: 10, 100, 1000 um; Mie, the sun's disk, white sunlight), "
      "scattering angle from 120 degrees (left) to 160 (right), all at one exposure. 1000 um: a bright, saturated "
      "primary with red outside (left), Alexander's dark band and the faint secondary at the left edge; 100 um: a "
      "paler primary followed by pink and green supernumeraries; 10 um: the broad, nearly white fogbow near 142 "
      "degrees.",
      [] {
        const auto& ts = profiles();
        const atmos::LeeImages scale = atmos::lee_images(ts.back());
        constexpr int kStrip = 60;
        Image out(kProfileRows, 3 * kStrip + 2 * kGap, 3);
        std::fill(out.pixels.begin(), out.pixels.end(), 0.02f);
        for (std::size_t k = 0; k < ts.size(); ++k) {
          const atmos::LeeImages im = atmos::lee_images(ts[k], scale.exposure, scale.white);
          for (int y = 0; y < kStrip; ++y)
            for (int x = 0; x < kProfileRows; ++x)
              for (int c = 0; c < 3; ++c)
                out.at(x, int(k) * (kStrip + kGap) + y, c) = im.display[std::size_t(x) * 3 + std::size_t(c)];
        }
        return out;
      });
}

Entry lee_profiles_figure() {
  return plot_entry(
      "lee_profiles.svg", "Luminance against angle: 10, 100 and 1000 um drops",
      "The luminance (Y, sr^-1: radiance per unit irradiance per unit projected-area optical depth) of "
      "the strips above, on a log scale. The primary's peak near 138 degrees for large drops, 139 for "
      "100 um with its supernumeraries inside, the fogbow's broad hump near 142 degrees at 10 um; the "
      "secondary near 129 and the dark band between.",
      [] {
        io::Plot p;
        p.title = "Lee profiles: Y against scattering angle (Mie, sun's disk)";  // not "luminance": test_gallery refuses "nan" in an SVG
        p.x_label = "scattering angle (degrees)";
        p.y_label = "Y, sr^-1";
        p.x_min = 120;
        p.x_max = 160;
        p.x_tick = 5;
        p.y_log = true;
        p.y_min = 1e-3;
        p.y_max = 1;
        p.legend = io::LegendCorner::TopRight;
        const char* colours[] = {"#7f7f7f", "#1f77b4", "#d62728"};
        for (std::size_t k = 0; k < 3; ++k) {
          const atmos::LeeTable& t = profiles()[k];
          io::PlotSeries s{fmt::format("{:g} um", kProfileRadiiUm[k]), {}, {}, colours[k]};
          for (int i = 0; i < t.rows(); ++i) {
            s.x.push_back(t.angle_deg[std::size_t(i)]);
            s.y.push_back(t.at(i, 0).Y);
          }
          p.series.push_back(std::move(s));
        }
        return p;
      });
}

Entry corona_glory_10um_figure() {
  return image_entry(
      "corona_glory_10um.png", "Corona and glory of 10 um droplets",
      "Left: the corona around the sun (the sun itself not drawn), +-8 degrees, from hydrolux lee --table corona for 10 "
      "um droplets (Mie, the sun's disk): a bluish-white aureole and coloured rings whose red parts lie near "
      "1.6, 3.1 and 4.7 degrees (16/r, 31/r, 47/r for r in um). Right: the glory around the antisolar point, "
      "+-8 degrees, from --table glory: coloured rings from the light that the droplets send straight back. Each "
      "is tone-mapped on its own: the corona's aureole is about 10^4 times brighter than the glory.",
      [] {
        const atmos::LeeTable corona = profile(atmos::LeeTableKind::corona, 10, 0, 8, 801);
        const atmos::LeeTable glory = profile(atmos::LeeTableKind::glory, 10, 172, 180, 801);
        return side_by_side({sky_disk(corona, false, 8, 360), sky_disk(glory, true, 8, 360)}, kGap);
      });
}

}  // namespace

std::vector<Entry> lee_entries() {
  return {lee_theories_figure(), lee_disk_spread_figure(), lee_colour_strips_figure(), lee_profiles_figure(),
          corona_glory_10um_figure()};
}

}  // namespace hydrolux::gallery::detail
