// A polariser in front of the camera (hydrolux sky --polarizer-deg; docs/sky.md, "Polarisation"):
// I' = (I + Q cos 2A + U sin 2A) / 2 per pixel, with the bow's Q from Stokes Lee tables and the
// sky's from Rayleigh scattering with depolarisation (scene::sky_dolp). Tested against:
//   - no filter: the frame is bit for bit the one without (Q present or not);
//   - Malus's law as an invariant: two crossed filters pass the whole unfiltered frame, every
//     pixel (F(A) + F(A + 90) = F), and A and A + 180 are one filter;
//   - the sky 90 degrees from the sun: (1 +- P90) / 2 of its light with the filter along and across
//     the polarisation (the model's degree, exactly), and the model's neutral points;
//   - the bow of a Stokes Airy table: with the axis horizontal the top of the bow keeps most of its
//     light and its side little; with the axis vertical the reverse (photographers' experience,
//     e.g. Koennen, Polarized Light in Nature, 1985, ch. 11: the bow is ~90% polarised tangentially);
//     and each pixel's passed fraction against an independent double-precision computation of the
//     filter's angle to the bow's tangent;
//   - the cube map and the half dome carry the filter too.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <string>
#include <string_view>
#include <vector>

#include "hydrolux/atmos/lee.hpp"
#include "hydrolux/core/error.hpp"
#include "hydrolux/core/math.hpp"
#include "hydrolux/scene/bow_tables.hpp"
#include "hydrolux/scene/compositor.hpp"
#include "hydrolux/scene/sky_model.hpp"
#include "support/asan.hpp"
#include "support/bow_slices.hpp"

namespace {

using namespace hydrolux;
using scene::BowSlice;
using scene::SkyCompositor;
using scene::SkySettings;

constexpr double kRad = 180.0 / kPi<double>;

// A bow-like slice with a Stokes Q of `dolp` times the intensity (tangential for dolp > 0).
BowSlice polarized_slice(double dolp) {
  BowSlice s = test::synthetic_slice(90, 180, 1024, [](double t) {
    std::array<double, 3> v{};
    for (int k = 0; k < 3; ++k) {
      const double x = t - (137.6 + 0.4 * k);
      v[std::size_t(k)] = x < 0 ? 0.05 * std::exp(x / 0.3) : 0.05 * (0.6 + 0.4 * std::cos(3 * x)) / (1 + x);
    }
    return v;
  });
  s.q.resize(s.rgb.size());
  for (std::size_t i = 0; i < s.rgb.size(); ++i) s.q[i] = float(dolp * s.rgb[i]);
  return s;
}

// The view of docs/sky.md's tests: the sun low behind, the whole primary in the frame.
SkySettings bow_view() {
  SkySettings s;
  s.sun_azimuth_deg = 180;
  s.sun_elevation_deg = 10;
  s.camera.azimuth_deg = 0;
  s.camera.elevation_deg = 20;
  s.camera.fov_deg = 120;
  s.camera.width = 240;
  s.camera.height = 160;
  s.rain_rate_mmh = 10;
  return s;
}

Image render(SkySettings s, std::optional<double> a, const BowSlice& slice) {
  s.polarizer_deg = a;
  return SkyCompositor(s, slice, BowSlice{}).render();
}

bool same_bits(const Image& a, const Image& b) { return a.pixels == b.pixels; }

// The direction of pixel (i, j) and the camera's right, in double precision (docs/sky.md's camera).
struct Ray {
  Vec3 d, right;
};
Ray pixel_ray(const SkySettings& s, int i, int j) {
  const Vec3 f = scene::direction_from_angles(s.camera.azimuth_deg, s.camera.elevation_deg);
  const Vec3 r = glm::normalize(glm::cross(Vec3{0, 1, 0}, f));
  const Vec3 u = glm::cross(f, r);
  const double t = std::tan(s.camera.fov_deg / 2 / kRad);
  const double px = (2 * (i + 0.5) / s.camera.width - 1) * t;
  const double py = (1 - 2 * (j + 0.5) / s.camera.height) * t * s.camera.height / s.camera.width;
  return {glm::normalize(f + px * r + py * u), r};
}

// cos 2 (angle between the filter's axis and the normal to the scattering plane), computed
// differently from the compositor: the filter's axis as an angle in the plane normal to the ray,
// the normal's angle by atan2 in an orthonormal basis of that plane.
double cos2_filter(const SkySettings& s, const Ray& ray, double a_deg) {
  const Vec3 sun = scene::direction_from_angles(s.sun_azimuth_deg, s.sun_elevation_deg);
  const Vec3 h = glm::normalize(ray.right - glm::dot(ray.right, ray.d) * ray.d);
  const Vec3 v = glm::cross(ray.d, h);
  const Vec3 e = glm::normalize(glm::cross(ray.d, sun));
  const double chi = std::atan2(glm::dot(e, v), glm::dot(e, h));
  return std::cos(2 * (chi - a_deg / kRad));
}

TEST(SkyPolarizer, NoFilterIsBitIdenticalWithOrWithoutQ) {
  const SkySettings s = bow_view();
  BowSlice plain = polarized_slice(0.9);
  plain.q.clear();
  const Image without_q = render(s, std::nullopt, plain);
  const Image with_q = render(s, std::nullopt, polarized_slice(0.9));
  EXPECT_TRUE(same_bits(without_q, with_q));
}

TEST(SkyPolarizer, CrossedFiltersPassTheWholeFrame) {
  const SkySettings s = bow_view();
  const BowSlice slice = polarized_slice(0.9);
  const Image none = render(s, std::nullopt, slice);
  for (const double a : {0.0, 30.0, 45.0, -60.0}) {
    const Image f1 = render(s, a, slice), f2 = render(s, a + 90 > 180 ? a - 90 : a + 90, slice);
    const Image f3 = render(s, a + 180 > 180 ? a - 180 : a + 180, slice);
    double worst = 0, worst_half = 0;
    for (std::size_t i = 0; i < none.pixels.size(); ++i) {
      // float arithmetic on values of ~1e3-1e4 cd/m^2: 1e-5 relative.
      worst = std::max(worst, std::abs(double(f1.pixels[i]) + f2.pixels[i] - none.pixels[i]) / (none.pixels[i] + 1e-3));
      worst_half = std::max(worst_half, std::abs(double(f1.pixels[i]) - f3.pixels[i]) / (none.pixels[i] + 1e-3));
    }
    EXPECT_LT(worst, 1e-5) << "A = " << a;
    EXPECT_LT(worst_half, 1e-5) << "A = " << a;  // A and A + 180 are the same filter
  }
}

TEST(SkyPolarizer, SkyAt90DegreesFromTheSunDarkensByTheModelsDegree) {
  // The sun on the eastern horizon, the camera looking north 10 degrees up: the centre pixel is 90
  // degrees from the sun, its scattering plane horizontal, its light polarised vertically.
  SkySettings s;
  s.sun_azimuth_deg = 90;
  s.sun_elevation_deg = 0;
  s.camera.azimuth_deg = 0;
  s.camera.elevation_deg = 10;
  s.camera.fov_deg = 40;
  s.camera.width = 101;
  s.camera.height = 51;
  s.rain_rate_mmh = 0;  // the sky alone
  const std::size_t centre = (std::size_t(25) * 101 + 50) * 3;
  for (const double p90 : {0.8, 0.5, 0.946}) {
    s.sky_max_dolp = p90;
    const Image none = render(s, std::nullopt, BowSlice{});
    const Image across = render(s, 0.0, BowSlice{}), along = render(s, 90.0, BowSlice{});
    for (int k = 0; k < 3; ++k) {
      EXPECT_NEAR(across.pixels[centre + k] / none.pixels[centre + k], (1 - p90) / 2, 1e-5) << p90;
      EXPECT_NEAR(along.pixels[centre + k] / none.pixels[centre + k], (1 + p90) / 2, 1e-5) << p90;
    }
  }
}

TEST(SkyPolarizer, SkyModelAndItsNeutralPoints) {
  for (const double p90 : {0.0, 0.5, 0.8, 1.0}) {
    EXPECT_DOUBLE_EQ(scene::sky_dolp(1, p90), 0);   // the sun
    EXPECT_DOUBLE_EQ(scene::sky_dolp(-1, p90), 0);  // the antisolar point
    EXPECT_NEAR(scene::sky_dolp(0, p90), p90, 1e-15);
  }
  // P90 = 1: Rayleigh's sin^2 / (1 + cos^2); air's molecular depolarisation ratio gives
  // (1 - rho) / (1 + rho) = 0.946 at 90 degrees (Young 1980, Appl. Opt. 19, 3427).
  for (const double g : {20.0, 60.0, 120.0}) {
    const double c = std::cos(g / kRad);
    EXPECT_NEAR(scene::sky_dolp(c, 1), (1 - c * c) / (1 + c * c), 1e-15);
  }
  const double rho = scene::kAirDepolarizationRatio;
  EXPECT_NEAR((1 - rho) / (1 + rho), 0.9457, 1e-4);
  // Monotonic from the sun to 90 degrees.
  double last = -1;
  for (int g = 0; g <= 90; g += 5) {
    const double p = scene::sky_dolp(std::cos(g / kRad), 0.8);
    EXPECT_GT(p, last);
    last = p;
  }
}

// The bow's light alone: the frame with the bow minus the frame with an empty table, same filter.
struct BowLight {
  Image with, without;
  double at(int i, int j) const {
    const std::size_t p = (std::size_t(j) * with.width + i) * 3;
    double sum = 0;
    for (int k = 0; k < 3; ++k) sum += double(with.pixels[p + k]) - without.pixels[p + k];
    return sum;
  }
};
BowLight bow_light(const SkySettings& s, std::optional<double> a, const BowSlice& slice) {
  BowSlice empty = slice;
  std::fill(empty.rgb.begin(), empty.rgb.end(), 0.f);
  std::fill(empty.q.begin(), empty.q.end(), 0.f);
  return {render(s, a, slice), render(s, a, empty)};
}

TEST(SkyPolarizer, TheTopOfTheBowVanishesWithTheAxisVerticalAndItsSidesWithItHorizontal) {
  // A Stokes Airy profile of 500 um drops (the primary ~90% polarised tangentially at its peak).
  atmos::LeeSpec spec = scene::sky_profile_spec(atmos::LeeTableKind::rainbow, 500, 0.25);
  spec.theory = scatter::parse_theory("airy");
  spec.stokes = true;
  const BowSlice slice = scene::compute_bow_slice(spec);
  ASSERT_TRUE(slice.has_q());
  const SkySettings s = bow_view();
  const BowLight none = bow_light(s, std::nullopt, slice), horizontal = bow_light(s, 0.0, slice),
                 vertical = bow_light(s, 90.0, slice);
  // The brightest bow pixel on the centre column (the top of the primary) and on the row through
  // the antisolar point's level ~40 degrees to the side (the bow's side).
  const int W = s.camera.width, H = s.camera.height;
  int top_j = 0;
  for (int j = 0; j < H; ++j)
    if (none.at(W / 2, j) > none.at(W / 2, top_j)) top_j = j;
  // The side: the brightest bow pixel on the left half of the row 2 degrees above the horizon (the
  // antisolar point is 10 degrees below it: there the bow is ~15 degrees from vertical).
  int side_j = 0;
  while (side_j + 1 < H && pixel_ray(s, W / 2, side_j + 1).d.y > std::sin(2 / kRad)) ++side_j;
  int side_i = 0;
  for (int i = 0; i < W / 2; ++i)
    if (none.at(i, side_j) > none.at(side_i, side_j)) side_i = i;
  const double top = none.at(W / 2, top_j), side = none.at(side_i, side_j);
  ASSERT_GT(top, 0);
  ASSERT_GT(side, 0);
  std::printf("bow light passed: top (row %d) horizontal %.3f vertical %.3f; side (%d, %d) horizontal %.3f vertical %.3f\n",
              top_j, horizontal.at(W / 2, top_j) / top, vertical.at(W / 2, top_j) / top, side_i, side_j,
              horizontal.at(side_i, side_j) / side, vertical.at(side_i, side_j) / side);
  // The top: horizontal axis passes most, vertical almost none.
  EXPECT_GT(horizontal.at(W / 2, top_j) / top, 0.85);
  EXPECT_LT(vertical.at(W / 2, top_j) / top, 0.15);
  // The side: the reverse, a little less complete (the bow is not quite vertical there).
  EXPECT_GT(vertical.at(side_i, side_j) / side, 0.6);
  EXPECT_LT(horizontal.at(side_i, side_j) / side, 0.4);
  // Each pixel's passed fraction against the independent filter angle, per channel, where the bow
  // is bright: (1 + dolp cos 2 (chi - A)) / 2 with the table's own dolp at that pixel's angle.
  const BowLight diagonal = bow_light(s, 45.0, slice);
  int checked = 0;
  for (int j = 0; j < H; j += 7)
    for (int i = 0; i < W; i += 7) {
      if (none.at(i, j) < 0.3 * top) continue;
      const Ray ray = pixel_ray(s, i, j);
      const Vec3 sun = scene::direction_from_angles(s.sun_azimuth_deg, s.sun_elevation_deg);
      const float c = float(glm::dot(ray.d, sun));
      const float theta = float(std::acos(c) * kRad);
      float iv[3], qv[3];
      slice.lookup(c, theta, iv);
      slice.lookup_q(c, theta, qv);
      const double dolp = (qv[0] + qv[1] + qv[2]) / double(iv[0] + iv[1] + iv[2]);
      for (const double a : {0.0, 45.0, 90.0}) {
        const BowLight& f = a == 0 ? horizontal : a == 90 ? vertical : diagonal;
        const double expect = (1 + dolp * cos2_filter(s, ray, a)) / 2;
        // 2e-3: float directions and angles (1e-4 rad) over a table interpolated in float.
        EXPECT_NEAR(f.at(i, j) / none.at(i, j), expect, 2e-3) << i << "," << j << " A = " << a;
      }
      ++checked;
    }
  EXPECT_GT(checked, 10);
}

TEST(SkyPolarizer, CubeMapAndHalfDomeCarryTheFilter) {
  SkySettings s = bow_view();
  s.polarizer_deg = 90;
  const BowSlice slice = polarized_slice(0.9);
  const Image per_pixel = SkyCompositor(s, slice, BowSlice{}).render();
  for (const auto mode : {scene::BowMode::cube_map, scene::BowMode::half_dome}) {
    s.mode = mode;
    s.cube_face_size = 512;
    const Image approx = SkyCompositor(s, slice, BowSlice{}).render();
    const auto err = scene::bow_error(approx, per_pixel);
    // The modes' own error without a filter is ~1-3% of the peak (test_compositor.cpp); the
    // filtered frames keep it.
    EXPECT_LT(err.rms_rel, 0.01) << scene::bow_mode_name(mode);
  }
}

TEST(SkyPolarizer, RefusesWhatItCannotDo) {
  SkySettings s = bow_view();
  s.polarizer_deg = 0;
  BowSlice plain = polarized_slice(0.9);
  plain.q.clear();
  EXPECT_THROW(SkyCompositor(s, plain, BowSlice{}), Error);  // no Stokes Q
  s.polarizer_deg = 181;
  EXPECT_THROW(scene::validate(s), DomainError);
  s.polarizer_deg = std::nan("");
  EXPECT_THROW(scene::validate(s), DomainError);
  s.polarizer_deg = 0;
  s.sky_max_dolp = 1.5;
  EXPECT_THROW(scene::validate(s), DomainError);
}

// The one polariser check (scene::check_polarization), which the compositor, hydrolux sky's job and
// hydrolux.sky make: the compositor's sentences, each parameter spelled by the door.
TEST(SkyPolarizer, OneCheckInEachDoorsSpelling) {
  const auto message = [](const SkySettings& s, bool rainbow_q, bool corona_q, Door door) {
    try {
      scene::check_polarization(s, rainbow_q, corona_q, door);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  SkySettings s;
  EXPECT_EQ(message(s, false, false, Door::python), "accepted");  // no filter: no Q needed
  s.stokes = true;
  s.polarizer_deg = 10;
  EXPECT_EQ(message(s, true, true, Door::cli),
            "--stokes: the Stokes images are the light before any filter: ask for them or for a polariser "
            "(--polarizer-deg 10), not both");
  EXPECT_EQ(message(s, true, true, Door::python),
            "stokes: the Stokes images are the light before any filter: ask for them or for a polariser "
            "(polarizer_deg 10), not both");
  s.polarizer_deg.reset();
  s.blend = scene::Blend::whitepaper;
  EXPECT_EQ(message(s, true, true, Door::cli),
            "--stokes: the Stokes images need the physical blend (the whitepaper's is not linear in the light)");
  s.blend = scene::Blend::physical;
  EXPECT_EQ(message(s, false, true, Door::python),
            "stokes: the Stokes images need the rainbow's Stokes Q, and its table has none (compute it with stokes "
            "on: hydrolux lee --stokes, or hydrolux export)");
  s.stokes = false;
  s.polarizer_deg = -30;
  EXPECT_EQ(message(s, false, true, Door::cli),
            "--polarizer-deg -30: a polariser needs the rainbow's Stokes Q, and its table has none (compute it with "
            "stokes on: hydrolux lee --stokes, or hydrolux export)");
  EXPECT_EQ(message(s, true, false, Door::cli), "accepted");  // no corona drawn
  s.corona = true;
  EXPECT_EQ(message(s, true, false, Door::python).rfind("polarizer_deg -30: a polariser needs the corona's Stokes Q", 0),
            0u);
  EXPECT_EQ(message(s, true, true, Door::python), "accepted");
}

}  // namespace

namespace {
TEST(SkyPolarizer, FilterFramesFollowFromTheStokesImages) {
  SkySettings s = bow_view();
  const BowSlice slice = polarized_slice(0.9);
  s.stokes = true;
  const Image iqu = SkyCompositor(s, slice, BowSlice{}).render();
  ASSERT_EQ(iqu.channels, 9);
  s.stokes = false;
  for (const double a : {0.0, 45.0, -30.0}) {
    s.polarizer_deg = a;
    const Image f = SkyCompositor(s, slice, BowSlice{}).render();
    const double c = std::cos(2 * a / kRad), sn = std::sin(2 * a / kRad);
    double worst = 0;
    for (std::size_t p = 0; p < std::size_t(f.width) * f.height; ++p)
      for (int k = 0; k < 3; ++k) {
        const float* v = &iqu.pixels[p * 9];
        const double expect = (v[k] + v[3 + k] * c + v[6 + k] * sn) / 2;
        worst = std::max(worst, std::abs(f.pixels[p * 3 + k] - expect) / (v[k] + 1e-3));
      }
    EXPECT_LT(worst, 1e-5) << "A = " << a;
  }
}
}  // namespace
