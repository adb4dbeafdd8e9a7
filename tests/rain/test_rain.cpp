// The rain field and its streaks (rain/rain.hpp): geometry of a streak against the pinhole camera,
// the drop counts against Marshall-Palmer, determinism and frame-to-frame coherence, depth
// occlusion, the area-time integral of a footprint, and the drops' brightness against their
// background (Garg & Nayar 2004, seed 000, section 2 and Figure 2).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <random>
#include <set>

#include "hydrolux/core/math.hpp"
#include "hydrolux/core/simd.hpp"
#include "hydrolux/drop/physics.hpp"
#include "hydrolux/rain/rain.hpp"
#include "hydrolux/scene/compositor.hpp"
#include "support/stats.hpp"

namespace hydrolux::rain {
namespace {

RainCamera small_camera() {
  RainCamera c;
  c.width = 480;
  c.height = 270;
  c.focal_mm = 35;
  c.sensor_width_mm = 36;
  return c;
}

// A street-like frame: a sky of luminance `sky` over the top 40%, a scene of `scene` below.
Image frame(const RainCamera& c, float sky, float scene) {
  Image img(c.width, c.height, 3);
  for (int y = 0; y < c.height; ++y)
    for (int x = 0; x < c.width; ++x)
      for (int k = 0; k < 3; ++k) img.at(x, y, k) = y < c.height * 2 / 5 ? sky : scene;
  return img;
}

std::map<std::uint32_t, Streak> by_drop(const std::vector<Streak>& list) {
  std::map<std::uint32_t, Streak> m;
  for (const auto& s : list) m[s.drop] = s;
  return m;
}

TEST(RainCamera, FocalFromFieldOfView) {
  // 36 mm wide sensor, 54.43 degrees: the 35 mm lens.
  EXPECT_NEAR(focal_mm_from_fov(2 * rad_to_deg(std::atan(18.0 / 35.0)), 36), 35, 1e-9);
  RainCamera c = small_camera();
  const auto p = c.project(Vec3(0.1, -0.05, 2.0));
  const Vec3 r = c.ray(p[0], p[1]);
  EXPECT_NEAR(glm::length(glm::cross(r, glm::normalize(Vec3(0.1, -0.05, 2.0)))), 0, 1e-12);
}

TEST(RainField, StreakLengthIsSpeedTimesExposureOverDepth) {
  // No wind and a level camera: a drop falls straight down at constant depth z, so its streak is
  // v t_exp f / (z p) pixels long (f / p the focal length in pixels), exactly.
  RainSettings s;
  s.rain_rate_mmh = 25;
  RainCamera c = small_camera();
  c.exposure_s = 1.0 / 60;
  c.fps = 30;
  const RainRenderer r(RainField(s, c));
  std::vector<Streak> list;
  r.streaks(3, list);
  ASSERT_GT(list.size(), 100u);
  const double f_over_pitch = c.focal_mm * 1e-3 / c.pixel_pitch_m();
  EXPECT_NEAR(f_over_pitch, c.focal_px(), 1e-9);
  for (const Streak& st : list) {
    const double v = -r.field().velocity(st.drop).y;
    const double expected = v * c.exposure_s * f_over_pitch / st.z;
    const double length = std::hypot(st.x1 - st.x0, st.y1 - st.y0);
    ASSERT_NEAR(length, expected, 1e-4 * expected + 1e-3) << "drop " << st.drop;
    // Straight down the image (rows grow downwards).
    ASSERT_NEAR(st.x1, st.x0, 1e-3);
    ASSERT_GT(st.y1, st.y0);
    // The velocity is Gunn & Kinzer's for the drop's radius.
    ASSERT_NEAR(v, drop::terminal_velocity_gunn_kinzer_mps(r.field().radius_m(st.drop)), 0.01);
  }
}

TEST(RainField, SlantFollowsTheWind) {
  // Wind blowing to the camera's right at w: the drop moves (w, -v) across the view at constant depth,
  // so its streak leans right by dx / dy = w / v; blowing to the left it leans left.
  for (const double dir : {90.0, -90.0}) {
    RainSettings s;
    s.rain_rate_mmh = 25;
    s.wind_mps = 4;
    s.wind_dir_deg = dir;
    const RainRenderer r(RainField(s, small_camera()));
    std::vector<Streak> list;
    r.streaks(0, list);
    ASSERT_GT(list.size(), 100u);
    for (const Streak& st : list) {
      const double v = -r.field().velocity(st.drop).y;
      const double dx = st.x1 - st.x0, dy = st.y1 - st.y0;
      ASSERT_NEAR(dx / dy, (dir > 0 ? 4.0 : -4.0) / v, 1e-3 * 4.0 / v + 1e-4);
    }
  }
}

TEST(RainField, DropCountsFollowMarshallPalmer) {
  // The classes' densities are Marshall & Palmer's integrals: with N0 = 1.6e7 m^-4 per radius
  // (8000 m^-3 mm^-1 per diameter, Marshall & Palmer 1948) and Lambda = 8200 h^-0.21 m^-1, the
  // drops of 0.1-2.9 mm at 10 mm/h number N0 / Lambda (e^{-Lambda 1e-4} - e^{-Lambda 2.9e-3}) per m^3.
  RainSettings s;
  s.rain_rate_mmh = 10;
  const RainField f(s, small_camera());
  const double lambda = 8200 * std::pow(10.0, -0.21);
  double total = 0;
  for (const auto& rc : f.classes()) total += rc.number_per_m3;
  EXPECT_NEAR(total, 1.6e7 / lambda * (std::exp(-lambda * 1e-4) - std::exp(-lambda * 2.9e-3)), 1e-9 * total);
  EXPECT_NEAR(marshall_palmer_per_m4(1e-3, 10), 1.6e7 * std::exp(-lambda * 1e-3), 1e-6);

  // The drawn drops: within each class, their count is the density times the box's volume (an
  // unbiased whole count: within 1), and over all classes their radii follow N(a) (chi-square over
  // 12 radius bins of equal expected count, p > 0.001).
  std::uint64_t drawn = 0;
  for (const auto& rc : f.classes()) {
    const double mean = rc.number_per_m3 * rc.box_size.x * rc.box_size.y * rc.box_size.z;
    if (rc.resolved_to_m > s.near_m) {
      EXPECT_NEAR(double(rc.count), mean, 1.0);
    }
    drawn += rc.count;
  }
  ASSERT_GT(drawn, 1000u);
  // Expected counts per radius bin from each class's N(a) over its box.
  const int bins = 12;
  std::vector<double> edges;
  for (int b = 0; b <= bins; ++b) edges.push_back(1e-4 * std::pow(29.0, double(b) / bins));
  std::vector<double> expected(bins, 0), observed(bins, 0);
  for (const auto& rc : f.classes()) {
    if (rc.count == 0) continue;
    const double volume = rc.box_size.x * rc.box_size.y * rc.box_size.z;
    for (int b = 0; b < bins; ++b) {
      const double lo = std::max(edges[b], rc.radius_lo_m), hi = std::min(edges[b + 1], rc.radius_hi_m);
      if (hi > lo)
        expected[b] += volume * 1.6e7 / lambda * (std::exp(-lambda * lo) - std::exp(-lambda * hi)) *
                       double(rc.count) / (rc.number_per_m3 * volume);
    }
    for (std::uint64_t i = rc.first_index; i < rc.first_index + rc.count; ++i) {
      const double a = f.radius_m(i);
      ASSERT_GE(a, rc.radius_lo_m);
      ASSERT_LE(a, rc.radius_hi_m);
      const int b = int(std::upper_bound(edges.begin(), edges.end(), a) - edges.begin()) - 1;
      observed[std::clamp(b, 0, bins - 1)] += 1;
    }
  }
  double chi2 = 0;
  int dof = 0;
  for (int b = 0; b < bins; ++b)
    if (expected[b] >= 5) {
      chi2 += (observed[b] - expected[b]) * (observed[b] - expected[b]) / expected[b];
      ++dof;
    }
  EXPECT_GT(test::chi_square_survival(chi2, dof - 1), 1e-3) << "chi2 " << chi2 << " dof " << dof - 1;

  // Positions fill each box uniformly: chi-square over its 8 octants for the largest class.
  const auto& big = *std::max_element(f.classes().begin(), f.classes().end(),
                                      [](const RadiusClass& a, const RadiusClass& b) { return a.count < b.count; });
  std::vector<double> oct(8, 0);
  for (std::uint64_t i = big.first_index; i < big.first_index + big.count; ++i) {
    const Vec3 u = (f.position(i, 0) - big.box_lo) / big.box_size;
    oct[std::size_t((u.x > 0.5) + 2 * (u.y > 0.5) + 4 * (u.z > 0.5))] += 1;
  }
  double chi_oct = 0;
  for (double o : oct) chi_oct += (o - double(big.count) / 8) * (o - double(big.count) / 8) / (double(big.count) / 8);
  EXPECT_GT(test::chi_square_survival(chi_oct, 7), 1e-3);
}

TEST(RainField, ExtinctionMatchesTheSkyCompositorsRain) {
  // All the rain's geometric extinction, pi integral a^2 N(a) da, is what scene::rain_beta_geo_per_m
  // gives for the rain curtain (5.03e-4 m^-1 at 5 mm/h); drops over 2.9 mm, which break up, are a
  // negligible part of it (e^{-Lambda 2.9 mm} ~ 1e-4).
  for (const double rate : {1.0, 5.0, 50.0}) {
    RainSettings s;
    s.rain_rate_mmh = rate;
    const RainField f(s, small_camera());
    EXPECT_NEAR(f.beta_total_per_m(), scene::rain_beta_geo_per_m(rate), 2e-3 * f.beta_total_per_m());
  }
  // Unresolved rain: with every class left unresolved, the optical depth of a sky pixel is the
  // whole extinction over extent_m - near_m.
  RainSettings s;
  s.rain_rate_mmh = 5;
  s.min_alpha = 0.5;
  s.far_m = 0.6;
  const RainField f(s, small_camera());
  const double tau = f.unresolved_optical_depth(std::numeric_limits<double>::infinity(), 1.0);
  EXPECT_GT(tau, 0.9 * f.beta_total_per_m() * (s.extent_m - s.near_m));
  EXPECT_LE(tau, f.beta_total_per_m() * (s.extent_m - s.near_m) * (1 + 1e-12));
}

TEST(RainField, SameSeedSameRainDifferentSeedDifferentRain) {
  RainSettings s;
  s.rain_rate_mmh = 25;
  s.wind_mps = 2;
  const RainCamera c = small_camera();
  const Image img = frame(c, 0.8f, 0.1f);
  RainRenderer a(RainField(s, c)), b(RainField(s, c));
  const RainFrame fa = a.render(img, nullptr, 5), fb = b.render(img, nullptr, 5);
  EXPECT_EQ(fa.image.pixels, fb.image.pixels);
  EXPECT_EQ(fa.alpha.pixels, fb.alpha.pixels);
  s.seed = 2;
  RainRenderer d(RainField(s, c));
  const RainFrame fd = d.render(img, nullptr, 5);
  std::size_t differ = 0;
  for (std::size_t i = 0; i < fa.alpha.pixels.size(); ++i) differ += fa.alpha.pixels[i] != fd.alpha.pixels[i];
  EXPECT_GT(differ, fa.alpha.pixels.size() / 20);
}

TEST(RainField, StreaksContinueFromFrameToFrame) {
  // With the shutter open the whole frame interval, a drop's streak in frame k + 1 starts where its
  // streak in frame k ended (unless it wrapped round its box in between); with a shorter exposure it
  // starts where the drop has moved on to during the gap.
  RainSettings s;
  s.rain_rate_mmh = 25;
  s.wind_mps = 3;
  s.wind_dir_deg = 60;
  s.min_alpha = 0.001;  // more drops drawn
  RainCamera c = small_camera();
  c.fps = 100;
  c.exposure_s = 1.0 / 100;
  const RainRenderer r(RainField(s, c));
  std::vector<Streak> k0, k1;
  r.streaks(10, k0);
  r.streaks(11, k1);
  const auto m1 = by_drop(k1);
  int matched = 0;
  for (const Streak& a : k0) {
    const auto it = m1.find(a.drop);
    if (it == m1.end()) continue;
    const Streak& b = it->second;
    if (std::hypot(b.x0 - a.x1, b.y0 - a.y1) > 50) continue;  // wrapped round the box
    EXPECT_NEAR(b.x0, a.x1, 2e-2);
    EXPECT_NEAR(b.y0, a.y1, 2e-2);
    ++matched;
  }
  EXPECT_GT(matched, 100);
  // The world positions: the end of frame 10's exposure plus the velocity over the gap is the start of
  // frame 11's (modulo the box) for a shorter exposure too.
  c.exposure_s = 1.0 / 100;
  const RainField f(s, c);
  for (std::uint64_t i = 0; i < f.drop_count(); i += 97) {
    const Vec3 end = f.position(i, 10 / c.fps) + f.velocity(i) * c.exposure_s;
    const Vec3 next = f.position(i, 11 / c.fps);
    const Vec3 moved = end + f.velocity(i) * (1 / c.fps - c.exposure_s);
    const auto& rc = *std::find_if(f.classes().rbegin(), f.classes().rend(),
                                   [&](const RadiusClass& k) { return k.count > 0 && i >= k.first_index; });
    for (int k = 0; k < 3; ++k) {
      const double d = std::remainder(moved[k] - next[k], rc.box_size[k]);
      ASSERT_NEAR(d, 0, 1e-9) << "drop " << i;
    }
  }
}

TEST(RainRenderer, NoStreakInFrontOfNearerGeometry) {
  // A wall at depth D over the left half of the frame: no drop beyond D may show on it. With the wall
  // nearer than every drop (D < near_m) its pixels keep their values exactly; with D = 4 m they carry
  // exactly the streaks of the drops nearer than 4 m, rendered without the wall over an open scene.
  RainSettings s;
  s.rain_rate_mmh = 50;
  s.unresolved = false;
  const RainCamera c = small_camera();
  const Image img = frame(c, 0.8f, 0.2f);
  for (const double wall : {0.3, 4.0}) {
    Image depth(c.width, c.height, 1);
    for (int y = 0; y < c.height; ++y)
      for (int x = 0; x < c.width; ++x)
        depth.at(x, y, 0) = x < c.width / 2 ? float(wall) : std::numeric_limits<float>::infinity();
    RainRenderer r(RainField(s, c, false));
    const RainFrame out = r.render(img, &depth, 0);
    double wall_alpha = 0, open_alpha = 0;
    for (int y = 0; y < c.height; ++y)
      for (int x = 0; x < c.width / 2 - 2; ++x) wall_alpha += out.alpha.at(x, y, 0);
    for (int y = 0; y < c.height; ++y)
      for (int x = c.width / 2 + 2; x < c.width; ++x) open_alpha += out.alpha.at(x, y, 0);
    if (wall < s.near_m) {
      EXPECT_EQ(wall_alpha, 0);
      for (int y = 0; y < c.height; ++y)
        for (int x = 0; x < c.width / 2; ++x) ASSERT_EQ(out.image.at(x, y, 1), img.at(x, y, 1));
    } else {
      EXPECT_GT(wall_alpha, 0);
      EXPECT_LT(wall_alpha, open_alpha);
      // Every streak pixel on the wall comes from a drop nearer than the wall.
      std::vector<Streak> list;
      r.streaks(0, list);
      Image near_mask(c.width, c.height, 1);
      for (const Streak& st : list) {
        if (st.z >= wall) continue;
        const float ext = st.R < 1 ? 1.f : st.R + 0.5f;
        for (int y = std::max(0, int(std::min(st.y0, st.y1) - ext) - 1);
             y <= std::min(c.height - 1, int(std::max(st.y0, st.y1) + ext) + 1); ++y)
          for (int x = std::max(0, int(std::min(st.x0, st.x1) - ext) - 1);
               x <= std::min(c.width - 1, int(std::max(st.x0, st.x1) + ext) + 1); ++x)
            near_mask.at(x, y, 0) = 1;
      }
      for (int y = 0; y < c.height; ++y)
        for (int x = 0; x < c.width / 2; ++x)
          if (out.alpha.at(x, y, 0) > 0) {
            ASSERT_EQ(near_mask.at(x, y, 0), 1) << x << "," << y;
          }
    }
  }
}

TEST(RainRenderer, FootprintsKeepTheDropsAreaTimeIntegral) {
  // A drop of image radius r covers pi r^2 pixel-exposures whatever its streak's length, slant,
  // defocus or size against a pixel: the sum of one streak's alpha over the pixels is pi r^2. Thin
  // footprints (R < 1, the tent) sum exactly when the streak runs along a pixel axis, within 1% for
  // a slanted long one and 4% for a slanted short one (a rotated tent is no partition of unity on the
  // pixel grid; rain streaks run near the vertical); wide ones (the disk, sampled at pixel centres) within 2% for R >= 1.5 (its edge cuts
  // pixel centres unevenly: the lattice-point error of a disk of radius R is O(R) against pi R^2); a
  // drop at rest has a soft edge whose integral exceeds pi R^2 by pi / 12 (2% at R = 2, within 3%).
  const struct {
    float r, R, length, angle_deg;
    double tol;
  } cases[] = {{0.2f, 0.2f, 0, 0, 1e-5},     {0.3f, 0.3f, 12, 0, 1e-5},   {0.3f, 0.3f, 12, 90, 1e-5},
               {0.4f, 0.5f, 25, 17, 1e-2},   {0.1f, 0.9f, 40, 33, 1e-2},  {0.5f, 0.5f, 1.5f, 60, 4e-2},
               {2.0f, 2.0f, 0, 0, 3e-2},     {3.0f, 3.0f, 30, 10, 2e-2},  {1.5f, 6.0f, 20, 80, 2e-2},
               {4.0f, 4.0f, 60, 45, 2e-2}};
  for (const auto& k : cases) {
    for (const float offset : {0.0f, 0.37f, 0.5f}) {
      Streak st{};
      st.x0 = 64.3f + offset;
      st.y0 = 40.1f + offset * 0.7f;
      st.x1 = st.x0 + k.length * std::sin(deg_to_rad(k.angle_deg));
      st.y1 = st.y0 + k.length * std::cos(deg_to_rad(k.angle_deg));
      st.r = k.r;
      st.R = k.R;
      st.z = 1;
      const Image a = streak_alpha(st, 160, 128);
      double sum = 0, peak = 0;
      for (float v : a.pixels) {
        sum += v;
        peak = std::max(peak, double(v));
      }
      ASSERT_LE(peak, 1.0);
      EXPECT_NEAR(sum, kPi<double> * k.r * k.r, k.tol * kPi<double> * k.r * k.r)
          << "r " << k.r << " R " << k.R << " L " << k.length << " angle " << k.angle_deg << " offset " << offset;
    }
  }
}

TEST(RainRenderer, OscillationBeadsTheStreak) {
  // A drop whose apparent radius oscillates as r (1 + A sin(2 pi (phase + cycles tau))) along a
  // vertical streak: the alpha down the streak follows (1 + A sin)^2, so its extremes are (1 +- A)^2
  // of the still drop's, with `cycles` periods over the streak.
  Streak st{};
  st.x0 = st.x1 = 20.5f;
  st.y0 = 10;
  st.y1 = 110;
  st.r = st.R = 0.4f;
  st.z = 1;
  const Image still = streak_alpha(st, 41, 120);
  st.osc_amp = 0.3f;
  st.osc_cycles = 2;
  const Image beaded = streak_alpha(st, 41, 120);
  double lo = 1e9, hi = 0;
  int crossings = 0;
  double prev = 0;
  for (int y = 14; y < 106; ++y) {
    const double ratio = beaded.at(20, y, 0) / still.at(20, y, 0);
    lo = std::min(lo, ratio);
    hi = std::max(hi, ratio);
    if (y > 14 && (ratio - 1) * (prev - 1) < 0) ++crossings;
    prev = ratio;
  }
  EXPECT_NEAR(hi, 1.69, 0.02);
  EXPECT_NEAR(lo, 0.49, 0.02);
  EXPECT_NEAR(crossings, 4, 1);  // two periods cross 1 four times
}

TEST(RainRenderer, DropsAreBrighterThanTheirBackground) {
  // Garg & Nayar: a drop refracts light from a ~165 degree cone, mostly the bright sky and the ground
  // beyond the frame, so over a scene darker than the sky drops are brighter than what they cover, on
  // a dark scene and on a bright one alike; drops take the frame's colour (a blue sky, blue drops).
  RainSettings s;
  s.rain_rate_mmh = 25;
  const RainCamera c = small_camera();
  for (const float scene : {0.03f, 0.35f}) {
    RainRenderer r(RainField(s, c));
    const RainFrame out = r.render(frame(c, 0.8f, scene), nullptr, 0);
    EXPECT_GT(out.stats.streak_luminance_gain, 0) << "scene " << scene;
    EXPECT_GT(out.stats.drop_luminance_mean, out.stats.background_luminance_mean) << "scene " << scene;
    EXPECT_GT(out.stats.drops_visible, 100u);
  }
  // Uniform grey all round: a drop passes on ~(1 - k)^2 + k + ... of its surroundings: a little less
  // than the background, never more (energy: no path gains light).
  RainRenderer r(RainField(s, c));
  r.render(frame(c, 0.5f, 0.5f), nullptr, 0);
  const Vec3 mid = r.light().at(c.width / 2.0, c.height / 2.0);
  EXPECT_LE(mid.y, 0.5 * (1 + 1e-9));
  EXPECT_GT(mid.y, 0.5 * 0.85);
}

// The composite of RGB frames runs in SIMD over whole blocks of 8 pixels a row (rain/composite.cpp),
// the rest of the row and frames of other channel counts in the scalar reference (render.cpp): the
// same operations in the same order. A 3-channel frame (SIMD) against the same frame with a 4th
// channel (scalar): every RGB value, alpha and layer value equal, and the statistics within 1e-6
// (float lane sums against double). A width of 101 exercises the scalar tail.
TEST(RainRenderer, SimdCompositeAgreesWithScalar) {
  RainCamera c = small_camera();
  c.width = 101;
  c.height = 60;
  RainSettings s;
  s.rain_rate_mmh = 60;
  s.wind_mps = 3;
  RainRenderer a{RainField(s, c)}, b{RainField(s, c)};
  Image rgb = frame(c, 0.7f, 0.2f), rgba(c.width, c.height, 4);
  for (int y = 0; y < c.height; ++y)
    for (int x = 0; x < c.width; ++x) {
      rgb.at(x, y, 1) *= 1 + 0.01f * float(x % 7);
      for (int k = 0; k < 3; ++k) rgba.at(x, y, k) = rgb.at(x, y, k);
      rgba.at(x, y, 3) = 0.5f;
    }
  const RainFrame fa = a.render(rgb, nullptr, 2, true), fb = b.render(rgba, nullptr, 2, true);
  ASSERT_GT(fa.stats.drops_visible, 20u);
  double worst = 0;
  for (int y = 0; y < c.height; ++y)
    for (int x = 0; x < c.width; ++x) {
      for (int k = 0; k < 3; ++k)
        worst = std::max(worst, double(std::abs(fa.image.at(x, y, k) - fb.image.at(x, y, k))));
      for (int k = 0; k < 4; ++k)
        worst = std::max(worst, double(std::abs(fa.layer.at(x, y, k) - fb.layer.at(x, y, k))));
      worst = std::max(worst, double(std::abs(fa.alpha.at(x, y, 0) - fb.alpha.at(x, y, 0))));
      EXPECT_EQ(fb.image.at(x, y, 3), 0.5f);
    }
  EXPECT_EQ(worst, 0.0);
  EXPECT_NEAR(fa.stats.alpha_mean, fb.stats.alpha_mean, 1e-6 * fb.stats.alpha_mean);
  EXPECT_NEAR(fa.stats.unresolved_transmittance_mean, fb.stats.unresolved_transmittance_mean, 1e-6);
  EXPECT_NEAR(fa.stats.streak_pixel_fraction, fb.stats.streak_pixel_fraction, 1e-12);
  EXPECT_NEAR(fa.stats.streak_luminance_gain, fb.stats.streak_luminance_gain,
              1e-6 * std::abs(fb.stats.streak_luminance_gain) + 1e-9);
}

// Thin streaks are rasterised in SIMD (composite.cpp): the same alpha, bit for bit, as the scalar
// reference raster (the streaks' colour sums are the same operations on the same alpha; the 1080p
// street's EXR was compared byte for byte when the SIMD raster came in), over streaks of every length (still drops, L under 1e-3, long ones), direction
// (vertical, horizontal, oblique, upward), position (straddling accumulator blocks, off the image's
// edges) and width (not a whole number of blocks: the row's last block reads no depth past the
// row), on every SIMD target this CPU runs.
TEST(RainRenderer, SimdRasterAgreesWithScalar) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(0.f, 1.f);
  int streaks = 0, targets = 0;
  for (int bit = 0; bit < 63; ++bit) {
    const std::int64_t t = std::int64_t(1) << bit;
    if (!(simd::supported_targets() & t)) continue;
    simd::set_targets_for_test(t);
    ++targets;
    for (int n = 0; n < 300; ++n) {
      const int width = n % 3 == 0 ? 37 : 64;
      Streak st{};
      st.x0 = -4 + (width + 8) * u(rng);
      st.y0 = -4 + 48 * u(rng);
      const float len = n % 10 == 0 ? 0.f : n % 10 == 1 ? 5e-4f : 60 * u(rng) * u(rng);
      const float angle = n % 7 == 0 ? 0.f : n % 7 == 1 ? 1.5707964f : 6.2831855f * u(rng);
      st.x1 = st.x0 + len * std::sin(angle);
      st.y1 = st.y0 + len * std::cos(angle);
      st.r = 0.05f + 0.8f * u(rng);
      st.R = st.r + (0.99f - st.r) * u(rng);  // thin: R < 1
      st.z = 1;
      const Image simd = streak_alpha(st, width, 40, true), scalar = streak_alpha(st, width, 40, false);
      ASSERT_EQ(simd.pixels.size(), scalar.pixels.size());
      EXPECT_EQ(std::memcmp(simd.pixels.data(), scalar.pixels.data(), simd.pixels.size() * sizeof(float)), 0)
          << simd::target_name(t) << ", streak " << n;
      streaks += std::any_of(scalar.pixels.begin(), scalar.pixels.end(), [](float v) { return v > 0; });
    }
  }
  simd::set_targets_for_test(0);
  EXPECT_GE(targets, 2);
  EXPECT_GT(streaks, 400);
}

// Every SIMD target this CPU runs (AVX-512, AVX2, SSE4, SSSE3, the emulated 128-bit fallback) gives
// the same floats: the lanes do the same operations whatever their count, and none is fused
// (src/CMakeLists.txt compiles the composite without contraction), so a data set rendered on one
// machine is the same bytes on another.
TEST(RainRenderer, SameFloatsOnEverySimdTarget) {
  RainCamera c = small_camera();
  RainSettings s;
  s.rain_rate_mmh = 25;
  const Image img = frame(c, 0.8f, 0.15f);
  std::vector<float> first;
  int targets = 0;
  for (int bit = 0; bit < 63; ++bit) {
    const std::int64_t t = std::int64_t(1) << bit;
    if (!(simd::supported_targets() & t)) continue;
    simd::set_targets_for_test(t);
    RainRenderer r{RainField(s, c)};
    const RainFrame f = r.render(img, nullptr, 1, true);
    if (first.empty()) {
      first = f.image.pixels;
    } else {
      double worst = 0;
      std::size_t n = 0;
      for (std::size_t i = 0; i < first.size(); ++i) {
        worst = std::max(worst, double(std::abs(f.image.pixels[i] - first[i])));
        n += f.image.pixels[i] != first[i];
      }
      EXPECT_EQ(n, 0u) << simd::target_name(t) << ": worst " << worst;
    }
    ++targets;
  }
  simd::set_targets_for_test(0);
  EXPECT_GE(targets, 2);
}

}  // namespace
}  // namespace hydrolux::rain
