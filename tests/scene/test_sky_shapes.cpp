// Non-spherical drops in the scene (hydrolux sky --shape; docs/sky.md, "Drop shapes"): the
// rainbow by position angle, interpolated per direction. Spheres keep the one-slice path bit for
// bit; each pixel's position angle agrees with an independent spherical-trigonometry computation;
// the frame of Beard-Chuang drops shows the Lee profiles' Moebius shift between the top and the
// side of the bow; the cube map and the half dome follow the position angle too.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <vector>

#include "hydrolux/atmos/lee.hpp"
#include "hydrolux/core/error.hpp"
#include "hydrolux/core/math.hpp"
#include "hydrolux/scene/bow_tables.hpp"
#include "hydrolux/scene/compositor.hpp"
#include "hydrolux/scene/sky_model.hpp"
#include "hydrolux/scene/sky_scene.hpp"
#include "support/bow_slices.hpp"

namespace {

using namespace hydrolux;
using scene::BowSlice;
using scene::RainbowSlices;
using scene::SkyCompositor;
using scene::SkySettings;

constexpr double kRad = 180.0 / kPi<double>;

using test::synthetic_slice;

// A bow-like slice: a sharp peak at 138 degrees with fringes inside, different per channel.
BowSlice bow_like_slice() {
  return synthetic_slice(90, 180, 1024, [](double t) {
    std::array<double, 3> v{};
    for (int k = 0; k < 3; ++k) {
      const double x = t - (137.6 + 0.4 * k);
      v[std::size_t(k)] = x < 0 ? 0.05 * std::exp(x / 0.3) : 0.05 * (0.6 + 0.4 * std::cos(3 * x)) / (1 + x);
    }
    return v;
  });
}

// The direction of pixel (i, j) by docs/sky.md's camera, in double precision.
Vec3 pixel_dir(const SkySettings& s, int i, int j) {
  const Vec3 f = scene::direction_from_angles(s.camera.azimuth_deg, s.camera.elevation_deg);
  const Vec3 r = glm::normalize(glm::cross(Vec3{0, 1, 0}, f));
  const Vec3 u = glm::cross(f, r);
  const double t = std::tan(s.camera.fov_deg / 2 / kRad);
  const double px = (2 * (i + 0.5) / s.camera.width - 1) * t;
  const double py = (1 - 2 * (j + 0.5) / s.camera.height) * t * s.camera.height / s.camera.width;
  return glm::normalize(f + px * r + py * u);
}

// The scattering angle and the position angle of a direction, degrees, independently of the
// compositor's vector projection: the position angle is the angle at the antisolar point A of the
// spherical triangle zenith Z - A - P (law of cosines: cos ZP = cos AZ cos AP + sin AZ sin AP cos psi).
struct Angles {
  double theta, psi;
};
Angles angles(const SkySettings& s, const Vec3& d) {
  const Vec3 sun = scene::direction_from_angles(s.sun_azimuth_deg, s.sun_elevation_deg);
  const double cos_ap = -glm::dot(d, sun);                             // P from the antisolar point
  const double cos_az = -std::sin(s.sun_elevation_deg / kRad);         // the antisolar point from the zenith
  const double cos_zp = d.y;                                           // P from the zenith
  const double sin_ap = std::sqrt(std::max(0.0, 1 - cos_ap * cos_ap));
  const double sin_az = std::cos(s.sun_elevation_deg / kRad);
  const double c = (cos_zp - cos_az * cos_ap) / (sin_az * sin_ap);
  return {180 - std::acos(std::clamp(cos_ap, -1.0, 1.0)) * kRad, std::acos(std::clamp(c, -1.0, 1.0)) * kRad};
}

double luminance(const float* p) { return 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2]; }

bool same_bits(const Image& a, const Image& b) {
  return a.width == b.width && a.height == b.height && a.channels == b.channels && a.pixels == b.pixels;
}

// (a) Spheres: one slice, and the same slice at all 19 positions, give the same frame bit for bit
// in every mode (the interpolation between equal slices adds f * 0), bow colour and composite.
TEST(SkyShapes, OneSliceEqualsNineteenIdenticalSlices) {
  const BowSlice one = bow_like_slice();
  for (const auto mode : {scene::BowMode::per_pixel, scene::BowMode::cube_map, scene::BowMode::half_dome}) {
    SkySettings s;
    s.camera.width = 320;
    s.camera.height = 180;
    s.mode = mode;
    s.cube_face_size = 128;
    const SkyCompositor a(s, one, {});
    const SkyCompositor b(s, RainbowSlices(std::vector<BowSlice>(scene::kShapePositions, one)), {});
    EXPECT_EQ(a.rainbow_positions(), 1);
    EXPECT_EQ(b.rainbow_positions(), scene::kShapePositions);
    EXPECT_TRUE(same_bits(a.bow_colour(), b.bow_colour())) << scene::bow_mode_name(mode);
    EXPECT_TRUE(same_bits(a.render(), b.render())) << scene::bow_mode_name(mode);
  }
}

// Each pixel's position angle: slice k holds the constant 10 k (its own position, degrees), so the
// bow colour is the interpolated position angle itself, which must equal the spherical-triangle
// angle of the pixel's double-precision direction. Tolerance 1e-3 degree: the compositor's float
// direction (components rounded to ~6e-8) moves the position angle by at most 6e-8 / sin(AP) rad,
// 7e-6 rad = 4e-4 degree at the 0.5 degree from the antisolar point (AP) this check comes to
// (measured: 1e-4 degree). Checked over a frame that holds the top (0), the sides (90) and the
// bottom (180) of the circle around the antisolar point, for three sun elevations.
TEST(SkyShapes, PositionAngleOfEachPixel) {
  for (const double sun_el : {0.0, 5.0, 40.0}) {
    SkySettings s;
    s.camera.width = 241;
    s.camera.height = 161;
    s.camera.fov_deg = 150;
    s.camera.azimuth_deg = 0;  // the antisolar azimuth for the default sun (azimuth 180)
    s.camera.elevation_deg = -sun_el;
    s.sun_elevation_deg = sun_el;
    std::vector<BowSlice> slices;
    for (int k = 0; k < scene::kShapePositions; ++k)
      slices.push_back(synthetic_slice(90, 180, 4, [k](double) {
        const double v = k * scene::kShapePositionStepDeg;
        return std::array<double, 3>{v, v, v};
      }));
    const SkyCompositor comp(s, RainbowSlices(std::move(slices)), {});
    const Image im = comp.bow_colour();
    double worst = 0, lo = 180, hi = 0;
    int checked = 0;
    for (int j = 0; j < s.camera.height; ++j)
      for (int i = 0; i < s.camera.width; ++i) {
        const Angles a = angles(s, pixel_dir(s, i, j));
        if (a.theta < 90.5 || a.theta > 179.5) continue;  // the slices' rows; the antisolar point's neighbourhood
        const double got = im.at(i, j, 0);
        worst = std::max(worst, std::abs(got - a.psi));
        lo = std::min(lo, a.psi), hi = std::max(hi, a.psi);
        ++checked;
      }
    std::printf("sun %.0f deg: %d pixels, position angles %.2f-%.2f deg, worst difference %.2e deg\n", sun_el, checked,
                lo, hi, worst);
    EXPECT_GT(checked, 10000);
    EXPECT_LT(lo, 1.0);
    EXPECT_GT(hi, 179.0);
    EXPECT_LT(worst, 1e-3);
    // Symmetric left and right: the frame is centred on the antisolar azimuth.
    for (int j = 0; j < s.camera.height; j += 7)
      for (int i = 0; i < s.camera.width / 2; i += 5)
        EXPECT_NEAR(im.at(i, j, 0), im.at(s.camera.width - 1 - i, j, 0), 1e-3);
  }
}

// The slices by position must share their rows.
TEST(SkyShapes, SlicesMustShareTheirRows) {
  SkySettings s;
  s.camera.width = 32;
  s.camera.height = 18;
  std::vector<BowSlice> v(3, bow_like_slice());
  v[1] = synthetic_slice(90, 180, 512, [](double) { return std::array<double, 3>{1, 1, 1}; });
  EXPECT_THROW(SkyCompositor(s, RainbowSlices(v), {}), Error);
}

// The scene of (b): 800 um Beard-Chuang drops (axis ratio 0.953), the sun 5 degrees up; primary
// only (the secondary lies 10 degrees away and is not measured), at sampling 0.5 (a quarter of the
// work; the profiles' peaks, which both sides of the comparison share, are what matters here).
constexpr double kRadiusUm = 800, kSunElevationDeg = 5;
const RainbowSlices& beard_chuang_800() {
  static const RainbowSlices r = scene::compute_shaped_rainbow(atmos::parse_drop_shape("beard-chuang"), kRadiusUm,
                                                               0.5, kSunElevationDeg, /*secondary=*/false);
  return r;
}

SkySettings bow_view() {
  SkySettings s;
  s.sun_azimuth_deg = 180;
  s.sun_elevation_deg = kSunElevationDeg;
  s.camera.azimuth_deg = 0;  // centred on the antisolar point's azimuth: the centre column is psi = 0
  s.camera.elevation_deg = 15;
  s.camera.fov_deg = 120;
  s.camera.width = 1201;  // odd: the centre column's px is exactly 0
  s.camera.height = 801;
  return s;
}

// The peak of a slice's luminance: its scattering angle (a row's), degrees.
double slice_peak_deg(const BowSlice& sl) {
  int best = 0;
  for (int r = 0; r < sl.rows; ++r)
    if (luminance(&sl.rgb[std::size_t(r) * 3]) > luminance(&sl.rgb[std::size_t(best) * 3])) best = r;
  return sl.first + (sl.last - sl.first) * double(best) / double(sl.rows - 1);
}

// The scattering angle of the frame's brightest pixel within 0.5 degree of position angle psi0
// (and between 130 and 165 degrees: the primary).
double frame_peak_deg(const SkySettings& s, const Image& im, double psi0) {
  double best = -1, theta = 0;
  for (int j = 0; j < s.camera.height; ++j)
    for (int i = 0; i < s.camera.width; ++i) {
      const Angles a = angles(s, pixel_dir(s, i, j));
      if (std::abs(a.psi - psi0) > 0.5 || a.theta < 130 || a.theta > 165) continue;
      const double l = luminance(&im.pixels[(std::size_t(j) * s.camera.width + std::size_t(i)) * 3]);
      if (l > best) best = l, theta = a.theta;
    }
  return theta;
}

// (b) The frame shows the bow's Moebius shift: its top (position 0) lies at a smaller angular radius
// (180 - theta) than its side (90) by what the Lee profiles at those positions give. Tolerance:
// each frame peak is within one pixel's angle of its profile's peak row (the profiles fall away
// from their peaks over 0.5-3.7 degrees, far more than a pixel, so the brightest pixel is one of
// those bracketing the peak), and a pixel of this camera subtends at most 2 tan(60) / 1201 rad =
// 0.165 degree (at the centre; less off-axis): 2 pixels for the difference of two peaks.
TEST(SkyShapes, FrameShowsTheMoebiusShiftOfTheProfiles) {
  const auto& bow = beard_chuang_800();
  ASSERT_EQ(int(bow.by_position.size()), scene::kShapePositions);
  const double top_profile = slice_peak_deg(bow.by_position[0]);
  const double side_profile = slice_peak_deg(bow.by_position[9]);  // 90 degrees
  const SkySettings s = bow_view();
  const Image im = SkyCompositor(s, bow, {}).bow_colour();
  const double top_frame = frame_peak_deg(s, im, 0), side_frame = frame_peak_deg(s, im, 90);
  const double pixel_deg = 2 * std::tan(60 / kRad) / s.camera.width * kRad;
  std::printf("bow radius (180 - theta of the luminance peak): top %.2f deg (profile %.2f), side %.2f deg (profile "
              "%.2f); shift %.2f deg in the frame, %.2f in the profiles; pixel %.3f deg\n",
              180 - top_frame, 180 - top_profile, 180 - side_frame, 180 - side_profile, top_frame - side_frame,
              top_profile - side_profile, pixel_deg);
  // The profiles' shift is large against a pixel (docs/non-spherical.md: K (1 - Q) with K = -132
  // degrees and Q = 0.953 is about 6 degrees to first order), so the comparison means something.
  EXPECT_GT(top_profile - side_profile, 3.0);
  // The top lies nearer the antisolar point than the side ...
  EXPECT_LT(180 - top_frame, 180 - side_frame);
  // ... by the profiles' shift, each peak within a pixel of its profile's.
  EXPECT_NEAR(top_frame, top_profile, pixel_deg);
  EXPECT_NEAR(side_frame, side_profile, pixel_deg);
  EXPECT_NEAR(top_frame - side_frame, top_profile - side_profile, 2 * pixel_deg);
}

// (2) The cube map bakes the position-dependent bow and the half dome takes the position angle from
// the view ray: both stay within the bounds test_compositor sets for a sphere's bow (measured here:
// cube 512 max 0.060, RMS 0.0012; dome 90 x 180 max 0.018, RMS 0.0006). Drawing one slice (the
// side's) all round, as a mode that ignored the position angle would, puts the top of this bow 7
// degrees off: an error of 1.55 times the peak (bound 0.3).
TEST(SkyShapes, CubeMapAndHalfDomeFollowThePositionAngle) {
  const auto& bow = beard_chuang_800();
  SkySettings s = bow_view();
  s.camera.width = 640;
  s.camera.height = 360;
  const Image ref = SkyCompositor(s, bow, {}).bow_colour();
  s.mode = scene::BowMode::cube_map;
  s.cube_face_size = 512;
  const auto cube = scene::bow_error(SkyCompositor(s, bow, {}).bow_colour(), ref);
  s.mode = scene::BowMode::half_dome;
  const auto dome = scene::bow_error(SkyCompositor(s, bow, {}).bow_colour(), ref);
  // Against one slice (the side's) everywhere: what ignoring the position would cost.
  s.mode = scene::BowMode::per_pixel;
  const auto round = scene::bow_error(SkyCompositor(s, bow.by_position[9], {}).bow_colour(), ref);
  std::printf("beard-chuang 800 um: cube 512 max %.4f rms %.5f; dome 90x180 max %.4f rms %.5f; one slice for all: max "
              "%.3f rms %.4f\n",
              cube.max_rel, cube.rms_rel, dome.max_rel, dome.rms_rel, round.max_rel, round.rms_rel);
  EXPECT_LT(cube.max_rel, 0.15);
  EXPECT_LT(cube.rms_rel, 0.005);
  EXPECT_LT(dome.max_rel, 0.03);
  EXPECT_LT(dome.rms_rel, 0.002);
  EXPECT_GT(round.max_rel, 0.3);
}

// The shapes' limits as the sky states them: beard-chuang drops up to where the spread's largest
// drop reaches the axis ratio 0.77 (docs/non-spherical.md: Beard and Chuang's drops reach 0.78 at 2 mm,
// the 10% spread's largest drop is about 2.3 times its column's radius: about 0.9 mm); the profiles
// validate up to there and not beyond.
TEST(SkyShapes, RadiusLimitOfBeardChuangDrops) {
  const auto bc = atmos::parse_drop_shape("beard-chuang");
  const double rmax = scene::max_sky_radius_um(bc);
  std::printf("beard-chuang: radii up to %g um\n", rmax);
  EXPECT_GT(rmax, 800);
  EXPECT_LT(rmax, 1000);
  EXPECT_NO_THROW(atmos::validate(scene::sky_shape_profile_spec(bc, rmax, 1, 5, 0)));
  EXPECT_THROW(atmos::validate(scene::sky_shape_profile_spec(bc, rmax + 1, 1, 5, 0)), DomainError);
  EXPECT_EQ(scene::max_sky_radius_um(atmos::parse_drop_shape("sphere")), scene::max_sky_radius_um());
  // A spheroid's limit is Airy theory's size parameter only.
  const auto sph = atmos::parse_drop_shape("spheroid:0.9");
  EXPECT_EQ(scene::max_sky_radius_um(sph), atmos::max_radius_um(scene::sky_shape_profile_spec(sph, 500, 1, 0, 0)));
}

// The profiles' error reaches the frame's report: the largest of the slices that state one (a slice
// read from a file states none), and above the Lee tables' 1% a note naming the sampling that meets it,
// doubled until error * sampling / need is within 1% (the error falls about as 1 / sampling).
TEST(SkyShapes, TheProfilesErrorIsReportedWithTheSamplingThatMeetsIt) {
  BowSlice a, b, c;
  a.error = 0.004;
  b.error = 0.012;
  std::vector<BowSlice> by_position{a, b, c};
  EXPECT_EQ(scene::largest_error(RainbowSlices(by_position), BowSlice{}), 0.012);
  EXPECT_FALSE(scene::largest_error(RainbowSlices(c), BowSlice{}));
  EXPECT_EQ(scene::largest_error(RainbowSlices(a), b), 0.012);
  EXPECT_FALSE(scene::sky_profile_note(std::nullopt, 1, Door::cli));
  EXPECT_FALSE(scene::sky_profile_note(0.0099, 1, Door::cli));
  const auto two = scene::sky_profile_note(0.012, 1, Door::cli);
  ASSERT_TRUE(two);
  EXPECT_NE(two->find("1.2% RMS in luminance, more than 1%: give --sampling 2 "), std::string::npos) << *two;
  const auto eight = scene::sky_profile_note(0.05, 1, Door::python);  // 0.05 / 4 > 1%, 0.05 / 8 < 1%
  ASSERT_TRUE(eight);
  EXPECT_NE(eight->find("give sampling 8 "), std::string::npos) << *eight;
  const auto most = scene::sky_profile_note(0.5, 1, Door::cli);  // never beyond the declared range
  ASSERT_TRUE(most);
  EXPECT_NE(most->find(fmt::format("give --sampling {:g} ", scene::sky_param("sampling").hi)), std::string::npos)
      << *most;
}

// Without a sampling the sky's profiles choose theirs as hydrolux lee's tables do (atmos::compute_lee_table:
// 1, and once more at the sampling the 1 / sampling rule names, at most 4, where the estimate is above 1%).
// The bow's bottom (position 180) of Q = 0.9 spheroids at 200 um, the sun 25 degrees up, states 2.0% at
// sampling 1 (measured): the profile is computed again at 2, and is then the profile computed at a given
// sampling of 2, float for float; a given sampling is computed once. The profiles' report carries the
// largest sampling and first-pass estimate (profile_accuracy).
TEST(SkyShapes, ProfilesWithoutASamplingChooseOneAsLeeTablesDo) {
  const atmos::DropShapeSpec q09 = atmos::parse_drop_shape("spheroid:0.9");
  const atmos::LeeSpec automatic = scene::sky_shape_profile_spec(q09, 200, std::nullopt, 25, 180, 2);
  EXPECT_EQ(automatic.sampling, 1);
  EXPECT_EQ(automatic.sampling_most, atmos::kAutoSamplingMost);
  const BowSlice chosen = scene::compute_bow_slice(automatic);
  ASSERT_TRUE(chosen.error && chosen.first_error);
  std::printf("first pass %.3g%%, second at sampling %g: %.3g%%\n", 100 * *chosen.first_error, chosen.sampling,
              100 * *chosen.error);
  EXPECT_GT(*chosen.first_error, atmos::kLeeErrorTolerance);
  EXPECT_LT(*chosen.first_error, 2 * atmos::kLeeErrorTolerance);  // the rule names 2
  EXPECT_EQ(chosen.sampling, 2);
  EXPECT_LT(*chosen.error, *chosen.first_error / 1.5);

  const atmos::LeeSpec at2 = scene::sky_shape_profile_spec(q09, 200, 2.0, 25, 180, 2);
  EXPECT_EQ(at2.sampling_most, 0);
  const BowSlice given = scene::compute_bow_slice(at2);
  EXPECT_EQ(given.rgb, chosen.rgb);
  EXPECT_EQ(given.error, chosen.error);
  EXPECT_FALSE(given.first_error);
  EXPECT_EQ(given.sampling, 2);

  // The report: the largest sampling and first-pass estimate of the slices (a slice read from a file
  // has sampling 0 and neither).
  BowSlice once;
  once.sampling = 1;
  once.error = 0.002;
  const std::vector<BowSlice> by_position{once, chosen, BowSlice{}};
  const scene::ProfileAccuracy a = scene::profile_accuracy(RainbowSlices(by_position), BowSlice{});
  EXPECT_EQ(a.sampling, 2);
  EXPECT_EQ(a.first_error, chosen.first_error);
  EXPECT_EQ(a.error, chosen.error);
  const scene::ProfileAccuracy none = scene::profile_accuracy(RainbowSlices(std::vector<BowSlice>{once}), BowSlice{});
  EXPECT_EQ(none.sampling, 1);
  EXPECT_FALSE(none.first_error);
}

}  // namespace
