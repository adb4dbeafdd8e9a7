// The gallery's figures of non-spherical drops (docs/non-spherical.md): the upper half of the bow's
// arc as the sky shows it, for the same rain of spherical and of Beard-Chuang drops side by side,
// and a twinned bow from two drop populations.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "entries.hpp"
#include "hydrolux/atmos/lee.hpp"

namespace hydrolux::gallery::detail {

namespace {

constexpr double kDeg = 3.14159265358979323846 / 180;
// Positions every 10 degrees from the top (0) to the side (90), profiles over 128-180 degrees of
// scattering angle (bow radii 0-52 degrees), half the standard sampling: quick, and the
// sampling noise (~1%) is invisible at this size.
constexpr int kPositions = 10, kRows = 1041, kWavelengths = 16, kGap = 6;
constexpr double kAngle0 = 128, kAngle1 = 180;

// One population mixture's colour (X, Y, Z per row) at each position: the table's columns weighted.
using Profile = std::vector<double>;  // rows x 3

Profile mix(const atmos::LeeTable& t, const std::vector<double>& weight) {
  Profile p(std::size_t(t.rows()) * 3, 0.0);
  double total = 0;
  for (double w : weight) total += w;
  for (int c = 0; c < t.columns(); ++c)
    for (int r = 0; r < t.rows(); ++r) {
      const color::Xyz v = t.at(r, c);
      const double w = weight[std::size_t(c)] / total;
      p[std::size_t(r) * 3 + 0] += w * v.X;
      p[std::size_t(r) * 3 + 1] += w * v.Y;
      p[std::size_t(r) * 3 + 2] += w * v.Z;
    }
  return p;
}

struct Arc {
  std::vector<Profile> at_position;  // kPositions profiles, position 10 k degrees
  color::Mat3 xyz_to_rgb{};
  color::RgbSpace space = color::RgbSpace::rec709;
};

// The profiles of a rain whose columns are `spec`'s radii weighted by `weight(radius_um)` (per
// projected area) at each position; spheres are the same at every position and computed once.
template <typename Weight>
Arc arc(atmos::LeeSpec spec, Weight weight) {
  Arc a;
  spec.theory = scatter::parse_theory("airy");
  spec.angle_min_deg = kAngle0;
  spec.angle_max_deg = kAngle1;
  spec.rows = kRows;
  spec.wavelengths = kWavelengths * 2;
  spec.sampling = 0.5;
  for (int k = 0; k < kPositions; ++k) {
    if (spec.shape.spherical() && k > 0) {
      a.at_position.push_back(a.at_position.front());
      continue;
    }
    spec.position_deg = 10.0 * k;
    const atmos::LeeTable t = atmos::compute_lee_table(spec);
    std::vector<double> w;
    for (double r : t.radius_um) w.push_back(weight(r));
    a.at_position.push_back(mix(t, w));
    a.xyz_to_rgb = t.xyz_to_rgb;
    a.space = t.spec.rgb_space;
  }
  return a;
}

// The upper half of the sky around the antisolar point, bow radii up to 52 degrees, as linear RGB
// scaled by `exposure` (the arc's colour at position psi interpolated between the two nearest
// profiles; the sky's own light left out: the bow on black, as in a Lee diagram).
Image picture(const Arc& a, double exposure, int size) {
  const double reach = 180 - kAngle0;  // the largest bow radius shown, degrees
  Image out(size, size / 2, 3);
  for (int y = 0; y < size / 2; ++y)
    for (int x = 0; x < size; ++x) {
      const double u = ((x + 0.5) / size * 2 - 1) * reach, v = (1 - (y + 0.5) / (size / 2)) * reach;
      const double rho = std::hypot(u, v);  // angular distance from the antisolar point (small-angle map)
      const double theta = 180 - rho;
      if (theta < kAngle0 || theta > kAngle1) continue;
      const double psi = std::min(90.0, std::atan2(std::abs(u), v) / kDeg);
      const int k0 = std::min(kPositions - 2, int(psi / 10));
      const double fk = psi / 10 - k0;
      double f = (theta - kAngle0) / (kAngle1 - kAngle0) * (kRows - 1);
      const int i = std::min(kRows - 2, int(f));
      f -= i;
      color::Xyz xyz{0, 0, 0};
      double* dst[3] = {&xyz.X, &xyz.Y, &xyz.Z};
      for (int c = 0; c < 3; ++c) {
        const auto at = [&](int k, int row) { return a.at_position[std::size_t(k)][std::size_t(row) * 3 + std::size_t(c)]; };
        const double lo = (1 - f) * at(k0, i) + f * at(k0, i + 1), hi = (1 - f) * at(k0 + 1, i) + f * at(k0 + 1, i + 1);
        *dst[c] = ((1 - fk) * lo + fk * hi) * exposure;
      }
      const color::Rgb rgb = color::desaturate_into_gamut(color::matmul(a.xyz_to_rgb, xyz), a.space);
      for (int c = 0; c < 3; ++c) out.at(x, y, c) = float(std::clamp(rgb[std::size_t(c)], 0.0, 1.0));
    }
  return out;
}

// The drops of a figure: `columns` radii from `radius_min_um` to `radius_max_um` (log spaced), each
// with a gamma spread of relative width `size_spread`.
atmos::LeeSpec drops(double radius_min_um, double radius_max_um, int columns, double size_spread) {
  atmos::LeeSpec s;
  s.radius_min_um = radius_min_um;
  s.radius_max_um = radius_max_um;
  s.columns = columns;
  s.size_spread = size_spread;
  return s;
}

// The exposure that puts the brightest point of the first arc's profiles at `level`.
double exposure_for(const Arc& a, double level) {
  double peak = 0;
  for (const auto& p : a.at_position)
    for (std::size_t i = 1; i < p.size(); i += 3) peak = std::max(peak, p[i]);
  return peak > 0 ? level / peak : 1;
}

Entry bow_real_drops_figure() {
  return image_entry(
      "bow_real_drops.png", "The same rain, spherical drops and real (Beard-Chuang) drops",
      "The upper half of the primary bow around the antisolar point (out to a bow radius of 52 degrees; the top of the "
      "bow at the top, its sides at left and right), the sun 2 degrees up, Marshall-Palmer rain of 5 mm/h with drops "
      "of 0.1-1.1 mm radius, Airy theory of each drop's plane section with the bow's angle from 3-D rays through it, "
      "the sun's disk; both panels at one exposure. Left: spherical drops, the same bow all round, its supernumeraries "
      "washed out by the spread of sizes. Right: the same drops with Beard & Chuang's flattening (axis ratio 0.999 at "
      "0.1 mm to 0.91 at 1.1 mm): the sides are unchanged, but towards the top the larger drops' bows move inward and "
      "spread (the Moebius shift, about a degree per percent of flattening) so the top is dimmer and broader, and the "
      "small drops whose Moebius shift offsets their Airy offset leave faint supernumeraries inside it: the natural "
      "rainbow, supernumeraries at the top and none at the sides (compare the photographs in Haussmann, Appl. Opt. "
      "54(4), B117, 2015, and Koennen's explanation there).",
      [] {
        atmos::LeeSpec s = drops(100, 1100, 48, 0);
        s.sun_elevation_deg = 2;
        const double lambda = 8200 * std::pow(5.0, -0.21);  // Marshall-Palmer at 5 mm/h, m^-1
        const auto mp = [lambda](double r_um) {            // n(a) a (per ln a) x a^2, log columns
          const double a = r_um * 1e-6;
          return a * a * a * std::exp(-lambda * a) * 1e12;
        };
        const Arc sphere = arc(s, mp);
        s.shape = atmos::parse_drop_shape("beard-chuang");
        const Arc real = arc(s, mp);
        const double exposure = exposure_for(sphere, 0.9);
        return side_by_side({picture(sphere, exposure, 720), picture(real, exposure, 720)}, kGap);
      });
}

Entry bow_twinned_figure() {
  return image_entry(
      "bow_twinned.png", "A twinned rainbow: two populations of drops",
      "The upper half of the primary bow (as above), the sun on the horizon, from two equal populations (by "
      "projected area) of Beard-Chuang drops: 200 um (axis ratio 0.997) and 600 um (0.974), each with a 5% spread "
      "of radii. At the sides (the feet of the bow, where the scattering plane cuts the drops along their round "
      "equator) the two bows coincide; towards the top the flattened 600 um drops' bow moves inward by the "
      "Moebius shift (about a degree per percent of flattening: some 2.4-2.5 degrees more than the 200 um "
      "drops' at the top), and the bow splits into two that share their feet: a twinned rainbow, the extra bow "
      "inside, as in the photographs Haussmann (Appl. Opt. 54(4), B117, 2015) reconstructs from a bimodal drop "
      "population.",
      [] {
        atmos::LeeSpec s = drops(200, 600, 2, 0.05);
        s.shape = atmos::parse_drop_shape("beard-chuang");
        const Arc twin = arc(s, [](double) { return 1.0; });
        return picture(twin, exposure_for(twin, 0.9), 720);
      });
}

}  // namespace

std::vector<Entry> shape_entries() { return {bow_real_drops_figure(), bow_twinned_figure()}; }

}  // namespace hydrolux::gallery::detail
