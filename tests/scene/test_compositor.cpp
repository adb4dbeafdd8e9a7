// The rainbow scene: Preetham's sky and the sun, the camera and the table lookup (checked against
// an independent double-precision computation of each pixel's scattering angle), the rain curtain
// (Marshall-Palmer optical depth, the ground, the moisture mask), the two blends, and seed 002's
// two optimisations against the per-pixel reference.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "hydrolux/atmos/lee.hpp"
#include "hydrolux/core/error.hpp"
#include "hydrolux/core/math.hpp"
#include "hydrolux/scene/compositor.hpp"
#include "hydrolux/scene/sky_model.hpp"
#include "support/bow_slices.hpp"

namespace {

using namespace hydrolux;
using scene::BowSlice;
using scene::SkyCompositor;
using scene::SkySettings;

constexpr double kRad = 180.0 / kPi<double>;

using test::synthetic_slice;

// A 500 um rainbow profile (Airy theory, primary and secondary with supernumeraries: the
// structure the optimisations must keep), computed once.
const BowSlice& rainbow_500() {
  static const BowSlice s = [] {
    atmos::LeeSpec spec = atmos::profile_spec(atmos::LeeTableKind::rainbow, 500, 90, 180, 1024);
    spec.theory = scatter::parse_theory("airy:3");
    spec.size_spread = 0.1;
    return scene::slice_at_radius(scene::bow_table(atmos::compute_lee_table(spec)), 500);
  }();
  return s;
}

SkySettings small(int w = 320, int h = 180) {
  SkySettings s;
  s.camera.width = w;
  s.camera.height = h;
  return s;
}

// The scattering angle of pixel (i, j) by docs/sky.md's camera, in double precision.
double pixel_theta_deg(const SkySettings& s, int i, int j, Vec3* dir = nullptr) {
  const Vec3 f = scene::direction_from_angles(s.camera.azimuth_deg, s.camera.elevation_deg);
  const Vec3 r = glm::normalize(glm::cross(Vec3{0, 1, 0}, f));
  const Vec3 u = glm::cross(f, r);
  const double t = std::tan(s.camera.fov_deg / 2 / kRad);
  const double px = (2 * (i + 0.5) / s.camera.width - 1) * t;
  const double py = (1 - 2 * (j + 0.5) / s.camera.height) * t * s.camera.height / s.camera.width;
  const Vec3 d = glm::normalize(f + px * r + py * u);
  if (dir) *dir = d;
  return std::acos(std::clamp(glm::dot(d, scene::direction_from_angles(s.sun_azimuth_deg, s.sun_elevation_deg)), -1.0,
                              1.0)) *
         kRad;
}

double luminance(const float* p) { return 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2]; }

TEST(SkyModel, AirMassOfTheStandardSpectrum) {
  // ASTM G173-03 defines air mass 1.5 at a solar zenith angle of 48.19 degrees (sec z = 1.4999, a
  // plane-parallel atmosphere); Kasten and Young's curved atmosphere gives 1.498 there.
  EXPECT_NEAR(scene::kasten_young_air_mass(90 - 48.19), 1.5, 3e-3);
  EXPECT_NEAR(scene::kasten_young_air_mass(90), 1.0, 1e-3);
  // Monotone towards the horizon, where it stays finite (~38).
  double last = 0;
  for (double h = 90; h >= 0; h -= 1) {
    const double m = scene::kasten_young_air_mass(h);
    EXPECT_GT(m, last);
    last = m;
  }
  EXPECT_GT(last, 35);
  EXPECT_LT(last, 40);
}

TEST(SkyModel, SunIsNeutralAtAirMassOneAndAHalfAndReddensLow) {
  const auto am15 = scene::make_sun_sky(90 - 48.19, 2.5);
  // The scene's white balance is G173's sun (docs/sky.md): neutral to the tolerance of the two air
  // masses (1.4996 against 1.5).
  EXPECT_NEAR(am15.sun_rgb.x / am15.sun_rgb.y, 1.0, 2e-3);
  EXPECT_NEAR(am15.sun_rgb.z / am15.sun_rgb.y, 1.0, 2e-3);
  // Its illuminance: G173's direct beam (900 W/m^2 over 280-4000 nm) at ~100 lm/W of its visible
  // part: between 80 and 110 klux.
  EXPECT_GT(am15.sun_illuminance_lux, 80e3);
  EXPECT_LT(am15.sun_illuminance_lux, 110e3);
  const auto low = scene::make_sun_sky(5, 2.5);
  EXPECT_LT(low.sun_illuminance_lux, am15.sun_illuminance_lux / 2);
  EXPECT_GT(low.sun_rgb.x / low.sun_rgb.z, 1.5);  // a low sun is red
  EXPECT_THROW(scene::make_sun_sky(-1, 2.5), DomainError);
  EXPECT_THROW(scene::make_sun_sky(30, 20), DomainError);
}

TEST(SkyModel, PreethamZenithAndShape) {
  const auto s = scene::make_sun_sky(30, 2.5);
  const Vec3 sun = scene::direction_from_angles(180, 30);
  // At the zenith the model returns its zenith values (the Perez normalisation).
  const Vec3 z = scene::sky_radiance(s, sun, {0, 1, 0});
  const Vec3 expect = scene::xyY_to_rgb(s, s.zenith_x, s.zenith_y, s.zenith_Y_kcd * 1000);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(z[k] / expect[k], 1.0, 1e-12);
  // Preetham Fig. 4 / CIE clear skies: the zenith is a few kcd/m^2 and bluish (x, y < 0.3127,
  // 0.3290 of D65), the sky brightest near the sun and at the horizon away from it.
  EXPECT_GT(s.zenith_Y_kcd, 1.0);
  EXPECT_LT(s.zenith_Y_kcd, 10.0);
  EXPECT_LT(s.zenith_x, 0.3127);
  EXPECT_LT(s.zenith_y, 0.3290);
  const auto lum = [](const Vec3& v) { return 0.2126 * v.x + 0.7152 * v.y + 0.0722 * v.z; };
  const double near_sun = lum(scene::sky_radiance(s, sun, scene::direction_from_angles(180, 35)));
  const double opposite = lum(scene::sky_radiance(s, sun, scene::direction_from_angles(0, 60)));
  EXPECT_GT(near_sun, 3 * opposite);
  EXPECT_GT(z.z, z.x);  // blue above
  // Diffuse daylight on a horizontal plane at 30 degrees under a clear sky: 10-20 klux (IES
  // Lighting Handbook's clear-sky curves); the model's 16 x 64 quadrature gives it.
  const double e_sky = lum(s.sky_illuminance_rgb);
  EXPECT_GT(e_sky, 8e3);
  EXPECT_LT(e_sky, 25e3);
  // l_ref: a white Lambertian plane under sun and sky.
  EXPECT_NEAR(s.l_ref, (lum(s.sun_rgb) * 0.5 + e_sky) / kPi<double>, 1e-4 * s.l_ref);  // rounded weights
}

TEST(Compositor, FastAcosAccuracy) {
  double worst = 0;
  for (int i = -100000; i <= 100000; ++i) {
    const float x = float(i) / 100000.0f;
    worst = std::max(worst, std::abs(double(scene::fast_acos(x)) - std::acos(double(x))));
  }
  EXPECT_LT(worst, 1e-6);  // A&S 4.4.46 is 2e-8; float rounding of the polynomial dominates
}

TEST(Compositor, BowSitsAtItsScatteringAngle) {
  // A thin ring in the table at 138 degrees (rows 0.1 degree apart): the rendered bow colour must be
  // non-zero exactly where the independent pixel angle lies within one row of it.
  const BowSlice ring = synthetic_slice(90, 180, 901, [](double t) {
    const double v = std::abs(t - 138.0) < 0.05 ? 1.0 : 0.0;
    return std::array<double, 3>{v, v, v};
  });
  SkySettings s = small();
  const SkyCompositor comp(s, ring, {});
  const Image bow = comp.bow_colour();
  int lit = 0;
  for (int j = 0; j < s.camera.height; ++j)
    for (int i = 0; i < s.camera.width; ++i) {
      const double t = pixel_theta_deg(s, i, j);
      const float v = bow.at(i, j, 0);
      if (std::abs(t - 138.0) > 0.1 + 1e-4) {
        EXPECT_EQ(v, 0.0f) << i << "," << j << " theta " << t;
      }
      if (std::abs(t - 138.0) < 1e-3) {
        EXPECT_GT(v, 0.9f);
      }
      lit += v > 0;
    }
  EXPECT_GT(lit, 100);
}

TEST(Compositor, LookupIsLinearBetweenRowsAndZeroOutside) {
  const BowSlice ramp = synthetic_slice(100, 170, 71, [](double t) {
    return std::array<double, 3>{t, 2 * t, 1.0};
  });
  float o[3];
  ramp.lookup(0, 137.25f, o);
  EXPECT_NEAR(o[0], 137.25f, 1e-4);
  EXPECT_NEAR(o[1], 274.5f, 1e-3);
  ramp.lookup(0, 99.9f, o);
  EXPECT_EQ(o[0] + o[1] + o[2], 0.0f);
  ramp.lookup(0, 170.01f, o);
  EXPECT_EQ(o[0] + o[1] + o[2], 0.0f);
  ramp.lookup(0, 170.0f, o);
  EXPECT_NEAR(o[0], 170.0f, 1e-4);
}

TEST(Compositor, SliceInterpolatesInLogRadius) {
  // A table whose value is ln(r): the slice at any radius between columns is exact.
  const std::vector<double> radii{10, 100, 1000};
  std::vector<float> rgb;
  for (int row = 0; row < 3; ++row)
    for (double r : radii)
      for (int k = 0; k < 3; ++k) rgb.push_back(float(std::log(r)));
  const auto t = scene::bow_table(atmos::LeeTableKind::rainbow, atmos::AngleAxis::angle, radii, {90, 135, 180}, rgb);
  for (double r : {10.0, 31.6, 500.0, 1000.0}) {
    const auto s = scene::slice_at_radius(t, r);
    EXPECT_NEAR(s.rgb[3], std::log(r), 1e-5) << r;
  }
  EXPECT_NEAR(scene::slice_at_radius(t, 5000).rgb[0], std::log(1000.0), 1e-5);  // clamped
  EXPECT_TRUE(scene::slice_at_radius(t, 5000, true).empty());
  // Rows must be uniform on their axis.
  EXPECT_THROW(scene::bow_table(atmos::LeeTableKind::rainbow, atmos::AngleAxis::angle, radii, {90, 100, 180}, rgb),
               Error);
}

TEST(Compositor, RainRateSetsTheBowsBrightness) {
  // Marshall and Palmer (1948): N(D) = 8000 m^-3 mm^-1 exp(-4.1 R^-0.21 D), so the projected area
  // per volume is pi/4 * 2 N0 / Lambda^3: 5.03e-4 m^-1 at 5 mm/h.
  const double lambda = 4.1 * std::pow(5.0, -0.21) * 1e3;  // m^-1 of diameter
  const double expect = kPi<double> / 4 * 2 * 8000e3 / std::pow(lambda, 3);
  EXPECT_NEAR(scene::rain_beta_geo_per_m(5) / expect, 1.0, 1e-6);
  EXPECT_NEAR(expect, 5.03e-4, 0.01e-4);
  // The bow term is E_sun T (1 - exp(-2 tau)) / 2: faint in a shower, bright in a downpour,
  // saturating as the curtain turns opaque.
  SkySettings s = small(64, 36);
  s.blend = scene::Blend::physical;
  const BowSlice flat = synthetic_slice(90, 180, 91, [](double) { return std::array<double, 3>{0.05, 0.05, 0.05}; });
  std::vector<double> bow;
  for (double rate : {0.5, 5.0, 50.0}) {
    s.rain_rate_mmh = rate;
    const SkyCompositor comp(s, flat, {});
    SkySettings dry = s;
    dry.rain_rate_mmh = 0;
    const SkyCompositor none(dry, flat, {});
    const Image wet = comp.render(), bg = none.render();
    const double tau = scene::rain_beta_geo_per_m(rate) * 2000;
    const double trans = std::exp(-2 * tau);
    // The top-centre pixel looks at the sky through the whole curtain.
    const float* w = &wet.pixels[(0 * 64 + 32) * 3];
    const float* b = &bg.pixels[(0 * 64 + 32) * 3];
    const double in_scatter = comp.sun_sky().sun_rgb.y * 0.05 * (1 - trans) / 2;
    EXPECT_NEAR(w[1], b[1] * trans + in_scatter, 1e-4 * (b[1] + in_scatter)) << rate;
    bow.push_back(in_scatter);
  }
  // beta_geo grows as R^0.63: 4.3 times per decade of rain rate while the curtain is thin.
  EXPECT_GT(bow[1], 2 * bow[0]);
  EXPECT_GT(bow[2], bow[1]);
  EXPECT_LT(bow[2], 1.5 * bow[1]);  // saturating: tau = 4.3 at 50 mm/h
}

TEST(Compositor, GroundAndMoistureStopTheBow) {
  SkySettings s = small(96, 54);
  s.camera.elevation_deg = 0;
  const BowSlice flat = synthetic_slice(90, 180, 91, [](double) { return std::array<double, 3>{0.1, 0.1, 0.1}; });
  const SkyCompositor comp(s, flat, {});
  SkySettings dry = s;
  dry.rain_rate_mmh = 0;
  const SkyCompositor none(dry, flat, {});
  Image mask(96, 54, 1);
  for (int j = 0; j < 54; ++j)
    for (int i = 0; i < 96; ++i) mask.at(i, j, 0) = i < 48 ? 0.0f : 1.0f;
  const Image wet = comp.render(), bg = none.render(), masked = comp.render(&mask);
  for (int j = 0; j < 54; ++j)
    for (int i = 0; i < 96; ++i) {
      Vec3 d;
      pixel_theta_deg(s, i, j, &d);
      for (int k = 0; k < 3; ++k) {
        // Below the horizon the ground (1.7 m down) is nearer than the curtain (1000 m) for every
        // ray steeper than 0.1 degree: the ground itself, no rain.
        if (d.y < -0.002) {
          EXPECT_EQ(wet.at(i, j, k), bg.at(i, j, k));
        }
        // No moisture, no rain.
        if (i < 47) {
          EXPECT_EQ(masked.at(i, j, k), bg.at(i, j, k));
        }
        if (i > 48) {
          EXPECT_EQ(masked.at(i, j, k), wet.at(i, j, k));
        }
      }
      if (d.y > 0) {
        EXPECT_NE(wet.at(i, j, 1), bg.at(i, j, 1));
      }
    }
}

TEST(Compositor, BlendsDifferAsDocumented) {
  SkySettings s = small(64, 36);
  const BowSlice flat = synthetic_slice(90, 180, 91, [](double) { return std::array<double, 3>{0.05, 0.05, 0.05}; });
  SkySettings dry = s;
  dry.rain_rate_mmh = 0;
  const Image bg = SkyCompositor(dry, flat, {}).render();
  s.blend = scene::Blend::physical;
  const SkyCompositor phys(s, flat, {});
  s.blend = scene::Blend::whitepaper;
  const SkyCompositor wp(s, flat, {});
  const Image p = phys.render(), w = wp.render();
  const double l_ref = phys.sun_sky().l_ref;
  const double trans = std::exp(-2 * phys.beta_geo_per_m() * 2000);
  const double b = phys.sun_sky().sun_rgb.x * 0.05 * (1 - trans) / 2;
  // Top-left pixel: sky through the whole curtain.
  const double g = bg.at(0, 0, 0);
  EXPECT_NEAR(p.at(0, 0, 0), g * trans + b, 1e-4 * (g + b));
  EXPECT_NEAR(w.at(0, 0, 0), g + b * (1 - std::clamp(g / l_ref, 0.0, 1.0)), 1e-4 * (g + b));
  // The whitepaper's blend never darkens what is behind; the physical one does where the bow is weak.
  for (std::size_t i = 0; i < w.pixels.size(); ++i) EXPECT_GE(w.pixels[i], bg.pixels[i] * (1 - 1e-6f));
  EXPECT_LT(p.at(0, 0, 2), bg.at(0, 0, 2));
}

TEST(Compositor, EnvironmentReplacesSkyAndGround) {
  // A uniform equirectangular environment of 1000 cd/m^2, scaled by 2: with no rain every pixel,
  // sky or ground, is 2000; with rain the physical blend attenuates it and adds the bow.
  Image env(64, 32, 3);
  std::fill(env.pixels.begin(), env.pixels.end(), 1000.0f);
  auto map = std::make_shared<scene::EquirectEnvironment>(env);
  SkySettings s = small(48, 27);
  s.rain_rate_mmh = 0;
  const BowSlice flat = synthetic_slice(90, 180, 91, [](double) { return std::array<double, 3>{0.05, 0.05, 0.05}; });
  const Image dry = SkyCompositor(s, flat, {}, map, 2.0).render();
  for (float v : dry.pixels) EXPECT_NEAR(v, 2000.0f, 0.01f);
  s.rain_rate_mmh = 5;
  const SkyCompositor wet(s, flat, {}, map, 2.0);
  const Image w = wet.render();
  const double trans = std::exp(-2 * wet.beta_geo_per_m() * 2000);
  EXPECT_NEAR(w.at(24, 0, 1), 2000 * trans + wet.sun_sky().sun_rgb.y * 0.05 * (1 - trans) / 2, 0.5);
}

TEST(Compositor, SecondaryWindowAndCorona) {
  const BowSlice flat = synthetic_slice(90, 180, 91, [](double) { return std::array<double, 3>{1, 1, 1}; });
  const BowSlice corona = synthetic_slice(0, 20, 201, [](double) { return std::array<double, 3>{2, 2, 2}; });
  SkySettings s = small(160, 90);
  s.sun_azimuth_deg = 0;  // the sun ahead: both sides in view with a wide lens
  s.sun_elevation_deg = 5;
  s.camera.fov_deg = 170;
  s.secondary = false;
  s.corona = true;
  const Image bow = SkyCompositor(s, flat, corona).bow_colour();
  s.corona = false;
  const Image no_corona = SkyCompositor(s, flat, corona).bow_colour();
  int corona_px = 0;
  for (int j = 0; j < 90; ++j)
    for (int i = 0; i < 160; ++i) {
      const double t = pixel_theta_deg(s, i, j);
      const float v = bow.at(i, j, 0);
      if (t < 19.9) {
        EXPECT_NEAR(v, 2.0f, 1e-5);
        EXPECT_EQ(no_corona.at(i, j, 0), 0.0f);
        ++corona_px;
      } else if (t > 20.1 && t < 131.9) {
        EXPECT_EQ(v, 0.0f) << t;  // no table, or the secondary window
      } else if (t > 136.1) {
        EXPECT_NEAR(v, 1.0f, 1e-5);
      }
    }
  EXPECT_GT(corona_px, 10);
  EXPECT_FLOAT_EQ(scene::secondary_weight(false, 134), 0.5f);
  EXPECT_FLOAT_EQ(scene::secondary_weight(true, 100), 1.0f);
}

TEST(Compositor, SunDiskCarriesTheSunsIlluminance) {
  SkySettings s = small(400, 400);
  s.sun_azimuth_deg = 0;
  s.sun_elevation_deg = 20;
  s.camera.elevation_deg = 20;
  s.camera.fov_deg = 2;  // 0.005 degree pixels
  s.rain_rate_mmh = 0;
  const SkyCompositor comp(s, {}, {});
  const Image im = comp.render();
  const double pix_sr = std::pow(2 * std::tan(1.0 / kRad) / 400, 2);  // near the axis
  double sum = 0;
  for (int j = 0; j < 400; ++j)
    for (int i = 0; i < 400; ++i)
      if (pixel_theta_deg(s, i, j) < scene::kSunAngularRadiusDeg) sum += luminance(&im.pixels[(j * 400 + i) * 3]);
  // Irradiance = radiance x solid angle: the disk's pixels add up to E_v (pixel quantisation of the
  // disk's edge: 1%).
  EXPECT_NEAR(sum * pix_sr / comp.sun_sky().sun_illuminance_lux, 1.0, 0.01);
}

// Seed 002's optimisations against the per-pixel answer on a 500 um bow with supernumeraries. The
// bounds are the measured errors (docs/sky.md) with a margin: a regression in the bake, the cube
// lookup or the dome's interpolation shows.
TEST(Compositor, OptimisationsAgainstPerPixel) {
  SkySettings s = small(640, 360);
  const Image ref = SkyCompositor(s, rainbow_500(), {}).bow_colour();
  s.mode = scene::BowMode::cube_map;
  s.cube_face_size = 512;
  const auto cube512 = scene::bow_error(SkyCompositor(s, rainbow_500(), {}).bow_colour(), ref);
  s.cube_face_size = 128;
  const auto cube128 = scene::bow_error(SkyCompositor(s, rainbow_500(), {}).bow_colour(), ref);
  s.mode = scene::BowMode::half_dome;
  const auto dome = scene::bow_error(SkyCompositor(s, rainbow_500(), {}).bow_colour(), ref);
  s.dome_rings = 20;
  s.dome_segments = 40;
  const auto coarse = scene::bow_error(SkyCompositor(s, rainbow_500(), {}).bow_colour(), ref);
  std::printf("cube 512: max %.4f rms %.5f; cube 128: max %.4f rms %.5f; dome 90x180: max %.4f rms %.5f; dome "
              "20x40: max %.4f rms %.5f\n",
              cube512.max_rel, cube512.rms_rel, cube128.max_rel, cube128.rms_rel, dome.max_rel, dome.rms_rel,
              coarse.max_rel, coarse.rms_rel);
  // Measured on this 640 x 360 view: cube 512 max 0.096, RMS 0.0029; dome 90 x 180 max 0.015,
  // RMS 0.0009 (of the bow's peak luminance).
  EXPECT_LT(cube512.max_rel, 0.15);
  EXPECT_LT(cube512.rms_rel, 0.005);
  EXPECT_GT(cube128.rms_rel, cube512.rms_rel);  // resolution matters
  EXPECT_LT(dome.max_rel, 0.03);
  EXPECT_LT(dome.rms_rel, 0.002);
  EXPECT_GT(coarse.rms_rel, dome.rms_rel);
}

TEST(Compositor, ToneMapAndPsnr) {
  Image a(3, 1, 3);
  const double l_ref = 1000;
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) a.at(i, 0, k) = float(l_ref * (i == 0 ? 0.0 : i == 1 ? 1.0 : 1e6));
  const Image d = scene::tone_map(a, l_ref);
  EXPECT_EQ(d.at(0, 0, 0), 0.0f);
  const double x = 0.6;
  EXPECT_NEAR(d.at(1, 0, 0), x * (1 + x / 36) / (1 + x), 1e-6);
  EXPECT_EQ(d.at(2, 0, 0), 1.0f);
  EXPECT_GT(scene::psnr(d, d), 100);
  Image e = d;
  e.at(1, 0, 1) += 0.1f;
  EXPECT_NEAR(scene::psnr(d, e), 10 * std::log10(9 / 0.01), 1e-3);
}

TEST(Compositor, SettingsAreValidated) {
  SkySettings s = small();
  s.camera.fov_deg = 0;
  EXPECT_THROW(SkyCompositor(s, {}, {}), DomainError);
  s = small();
  s.curtain_near_m = 3000;
  s.curtain_far_m = 1000;
  try {
    SkyCompositor(s, {}, {});
    ADD_FAILURE() << "a curtain whose far edge is nearer than its near one accepted";
  } catch (const Error& e) {  // the declared span's message (its parts out of order), in the library's names
    EXPECT_STREQ(e.what(), "curtain_distance_m 3000:1000: expected NEAR:FAR, each in [0, 1e+06] m, NEAR <= FAR");
  }
  s = small();
  s.camera.width = 0;
  EXPECT_THROW(SkyCompositor(s, {}, {}), Error);
  s = small();
  s.light_color = Vec3(1, -1, 1);
  EXPECT_THROW(SkyCompositor(s, {}, {}), Error);
  s = small();
  s.rain_rate_mmh = -1;
  EXPECT_THROW(SkyCompositor(s, {}, {}), DomainError);
}

}  // namespace
