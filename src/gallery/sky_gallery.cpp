// The gallery's rainbow scenes (hydrolux sky, docs/sky.md): the bow as the sun climbs, for rain,
// drizzle and fog drops, in a shower and a downpour; the corona of cloud droplets around the sun;
// and seed 002's cube map and half dome, coarsened so their errors show, beside the per-pixel
// reference.
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <initializer_list>
#include <map>
#include <optional>
#include <tuple>
#include <vector>

#include "entries.hpp"
#include "hydrolux/atmos/lee.hpp"
#include "hydrolux/color/srgb.hpp"
#include "hydrolux/scene/sky_model.hpp"
#include "hydrolux/scene/bow_tables.hpp"
#include "hydrolux/scene/compositor.hpp"

namespace hydrolux::gallery::detail {

namespace {

constexpr int kWidth = 420, kHeight = 236, kGap = 6;
constexpr double kPiD = 3.14159265358979323846;

// One radius's tables (hydrolux sky's, at half its standard sampling), computed once per radius;
// with the Stokes Q when `stokes` (a polariser's scenes).
const scene::BowSlice& slice(atmos::LeeTableKind kind, double radius_um, bool stokes = false) {
  static std::map<std::tuple<int, double, bool>, scene::BowSlice> cache;
  const auto key = std::make_tuple(int(kind), radius_um, stokes);
  auto it = cache.find(key);
  if (it == cache.end()) {
    atmos::LeeSpec spec = scene::bow_table_spec(kind, radius_um);
    spec.sampling = 0.5;
    spec.stokes = stokes;
    it = cache.emplace(key, scene::compute_bow_slice(spec)).first;
  }
  return it->second;
}

scene::SkySettings base() {
  scene::SkySettings s;
  s.camera.width = kWidth;
  s.camera.height = kHeight;
  return s;
}

// Exposed as hydrolux sky's PNG: one stop more with a polariser.
Image render(const scene::SkySettings& s) {
  const bool stokes = s.polarizer_deg.has_value();
  const scene::BowSlice corona =
      s.corona ? slice(atmos::LeeTableKind::corona, s.radius_um, stokes) : scene::BowSlice{};
  const scene::SkyCompositor comp(s, slice(atmos::LeeTableKind::rainbow, s.radius_um, stokes), corona);
  return scene::tone_map(comp.render(), comp.sun_sky().l_ref * (stokes ? 0.5 : 1.0));
}

// One panel per value, the scene otherwise `base()` changed by `set(settings, value)`, side by side.
template <typename T, typename Set>
Image panels(std::initializer_list<T> values, Set set) {
  std::vector<Image> p;
  for (const T& v : values) {
    auto s = base();
    set(s, v);
    p.push_back(render(s));
  }
  return side_by_side(p, kGap);
}

// The sky's polarisation over the whole sky (scene::sky_dolp; docs/sky.md, "Polarisation") as seen
// looking up, in an equidistant fisheye centred on the zenith, north up and east right: the degree of
// linear polarisation as grey (black 0, white 1, displayed linearly), and the angle of polarisation
// from the local meridian as hue (red 0, through yellow and green at 60, cyan at 90, blue at 120, to red at 180).
Image polarization_map(double sun_elevation_deg, double p90) {
  constexpr int n = 236;
  Image dolp(n, n, 3), aop(n, n, 3);
  const Vec3 sun = scene::direction_from_angles(90, sun_elevation_deg);  // in the east
  const auto display = [](double v) { return float(color::srgb_decode(std::clamp(v, 0.0, 1.0))); };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const double x = (2 * (i + 0.5) / n - 1), y = (1 - 2 * (j + 0.5) / n);
      const double r = std::sqrt(x * x + y * y);
      if (r > 1) continue;
      // Zenith angle 90 r; azimuth from north (up) towards east (right).
      const double zenith = r * kPiD / 2, az = std::atan2(x, y);
      const Vec3 d{std::sin(az) * std::sin(zenith), std::cos(zenith), std::cos(az) * std::sin(zenith)};
      const double p = scene::sky_dolp(glm::dot(d, sun), p90);
      for (int k = 0; k < 3; ++k) dolp.at(i, j, k) = display(p);
      // The polarisation (normal to the scattering plane) against the local meridian (towards the
      // zenith) and the direction 90 degrees from it (d x meridian).
      const Vec3 e = glm::cross(d, sun);
      const Vec3 up = Vec3{0, 1, 0} - d.y * d;
      if (glm::length(e) < 1e-9 || glm::length(up) < 1e-9) continue;
      const Vec3 m = glm::normalize(up), w = glm::cross(d, m);
      double chi = std::atan2(glm::dot(e, w), glm::dot(e, m)) * 180 / kPiD;
      chi = std::fmod(chi + 360, 180);
      // Hue over 180 degrees, full saturation, value = the degree (unpolarised light is black).
      const double h = chi / 30;  // 0-6
      const double c = 1, xh = c * (1 - std::abs(std::fmod(h, 2) - 1));
      const std::array<double, 3> rgb = h < 1 ? std::array<double, 3>{c, xh, 0}
                                        : h < 2 ? std::array<double, 3>{xh, c, 0}
                                        : h < 3 ? std::array<double, 3>{0, c, xh}
                                        : h < 4 ? std::array<double, 3>{0, xh, c}
                                        : h < 5 ? std::array<double, 3>{xh, 0, c}
                                                : std::array<double, 3>{c, 0, xh};
      for (int k = 0; k < 3; ++k) aop.at(i, j, k) = display(rgb[std::size_t(k)] * std::sqrt(p));
    }
  return side_by_side({dolp, aop}, kGap);
}

Entry sky_sun_elevation_figure() {
  return image_entry(
      "sky_sun_elevation.png", "A rainbow as the sun climbs",
      "hydrolux sky, 500 um drops (10% spread), rain of 5 mm/h between 1 and 3 km, Preetham's sky (turbidity 2.5) "
      "and a grass ground, looking north 10 degrees up with a 90 degree lens; the sun behind the camera at 10, 25 "
      "and 40 degrees (left to right). The bow is a circle of 42 degrees around the antisolar point, which sinks as "
      "the sun climbs: at 40 degrees only its top clears the horizon, and above 42 there is no bow. The secondary "
      "(51 degrees, colours reversed) stands outside, Alexander's dark band between, and the sky inside the primary "
      "is brighter. Each panel exposed for its own daylight (docs/sky.md's tone map); the low sun is redder.",
      [] { return panels({10.0, 25.0, 40.0}, [](scene::SkySettings& s, double el) { s.sun_elevation_deg = el; }); });
}

Entry sky_radius_figure() {
  return image_entry(
      "sky_radius.png", "Rain, drizzle and fog: the drop radius",
      "The same scene (sun 25 degrees up) with drops of 1000, 100 and 20 um radius (left to right), each a 10% "
      "gamma spread. Large drops give narrow saturated bows; at 100 um the bands widen and supernumerary arcs "
      "appear inside the primary; 20 um drops give the broad, nearly white fogbow a few degrees inside the "
      "rainbow's radius, with faint inner rings and only a broad, faint secondary. Brightness is absolute: the same rain optical depth in each "
      "panel, the same exposure.",
      [] { return panels({1000.0, 100.0, 20.0}, [](scene::SkySettings& s, double r) { s.radius_um = r; }); });
}

Entry sky_rain_rate_figure() {
  return image_entry(
      "sky_rain_rate.png", "Drizzle, shower, downpour: the rain rate",
      "500 um drops with the curtain's optical depth from Marshall and Palmer's drop-size distribution at 0.5, 5 "
      "and 50 mm/h (projected-area optical depth 0.24, 1.0 and 4.3 over the 2 km curtain). Attenuation plus "
      "in-scattering: a drizzle gives a faint bow over a bright sky, a downpour dims the sky behind the rain and "
      "the bow saturates at E_sun T / 2. Same exposure in every panel.",
      [] { return panels({0.5, 5.0, 50.0}, [](scene::SkySettings& s, double rate) { s.rain_rate_mmh = rate; }); });
}

Entry sky_corona_figure() {
  return image_entry(
      "sky_corona.png", "A corona around the sun",
      "Looking at the sun (25 degrees up) through a thin veil of 10 um droplets (hydrolux sky's corona table, "
      "0-90 degrees; projected-area optical depth 0.03) with a 24 degree lens. Left, the physical blend: the sun's disk and its "
      "aureole (the droplets' diffraction peak, saturated in the display as in a photograph) ringed by the "
      "corona's colours, red outside (the rings' angles are checked in tests/atmos/test_lee.cpp: 1.6, 3.1 and "
      "4.7 degrees). Right, the whitepaper's blend over the same sky: near the sun the sky is brighter than the "
      "reference white, so bow x (1 - scene) is zero and the corona disappears; the blend only works over a "
      "dark background.",
      [] {
        return panels({scene::Blend::physical, scene::Blend::whitepaper}, [](scene::SkySettings& s, scene::Blend blend) {
          s.radius_um = 10;
          s.corona = true;
          s.sun_azimuth_deg = 180;
          s.camera.azimuth_deg = 180;
          s.camera.elevation_deg = 25;
          s.camera.fov_deg = 24;
          s.curtain_near_m = 1000;
          s.curtain_far_m = 1060;
          s.blend = blend;
        });
      });
}

Entry sky_optimisations_figure() {
  return image_entry(
      "sky_optimisations.png", "Seed 002's shortcuts against the per-pixel answer",
      "The top of a 500 um bow through a 30 degree lens, three ways (left to right): per pixel (the reference), "
      "from a cube map of 64 x 64 texels per face, and from a half dome of 12 rings x 24 segments, both far "
      "coarser than hydrolux's defaults so that their errors show: the cube map blurs the bow into texel-sized "
      "steps, the dome's flat triangles bend the bands between rings. At the defaults (512 texels; 90 x 180) the "
      "errors fall to 9.6% and 1.5% of the peak at worst, 0.29% and 0.09% RMS (docs/sky.md).",
      [] {
        return panels({scene::BowMode::per_pixel, scene::BowMode::cube_map, scene::BowMode::half_dome},
                      [](scene::SkySettings& s, scene::BowMode mode) {
          s.camera.elevation_deg = 15;
          s.camera.fov_deg = 30;
          s.mode = mode;
          s.cube_face_size = 64;
          s.dome_rings = 12;
          s.dome_segments = 24;
        });
      });
}

Entry sky_polarizer_figure() {
  return image_entry(
      "sky_polarizer.png", "The bow through a polarising filter",
      "The scene of the first figure (500 um drops, sun 10 degrees up, 5 mm/h) without a filter and through a "
      "linear polariser whose axis is horizontal (0), diagonal (45) and vertical (90 degrees), left to right "
      "(hydrolux sky --polarizer-deg; the filtered panels exposed one stop more, as a camera would). The bow's light "
      "is ~90% polarised tangentially to the arc (Stokes Lee tables): the horizontal axis keeps the top of the bow "
      "and dims its feet, the vertical axis removes the top (97% of its light) and keeps the feet, the diagonal "
      "keeps one shoulder. The sky, polarised up to 80% at 90 degrees from the sun (Rayleigh with "
      "depolarisation), darkens most overhead with the vertical axis; the grass and the sun's disk are "
      "unpolarised: each filter passes half.",
      [] {
        return panels({std::optional<double>{}, std::optional<double>{0.0}, std::optional<double>{45.0},
                       std::optional<double>{90.0}},
                      [](scene::SkySettings& s, std::optional<double> a) {
                        s.sun_elevation_deg = 10;
                        s.polarizer_deg = a;
                      });
      });
}

Entry sky_polarization_figure() {
  return image_entry(
      "sky_polarization.png", "The sky's polarisation",
      "The model of the polarised sky (Rayleigh single scattering with depolarisation, P90 = 0.8; docs/sky.md) looking "
      "up, an equidistant fisheye from the zenith (centre) to the horizon (rim), north up, east right, the sun 30 "
      "degrees up in the east and 45 degrees up in the east (pairs, left to right). In each pair, left: the degree "
      "of linear polarisation, black 0 to white 1: zero at the sun and at the antisolar point below the western "
      "horizon (the model's only neutral points; the dark spot right of centre is the sun), 0.8 on the band 90 "
      "degrees from the sun, left of the zenith. Right: the angle of polarisation from the local meridian as hue "
      "(red 0, green 60, cyan 90, blue 120 degrees): cyan, normal to the meridian, all along the solar meridian (the "
      "horizontal line through the centre), and every hue once around the sun, the pattern's singular point; the "
      "pattern Rayleigh's sky shows in all-sky polarimetry (Horvath and Varju, Polarized Light in Animal Vision, "
      "2004, ch. 18), without the real sky's Arago and Babinet points.",
      [] { return side_by_side({polarization_map(30, 0.8), polarization_map(45, 0.8)}, 3 * kGap); });
}

}  // namespace

std::vector<Entry> sky_entries() {
  return {sky_sun_elevation_figure(), sky_radius_figure(), sky_rain_rate_figure(), sky_corona_figure(),
          sky_optimisations_figure(), sky_polarizer_figure(), sky_polarization_figure()};
}

}  // namespace hydrolux::gallery::detail
