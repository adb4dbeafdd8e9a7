// hydrolux sky and hydrolux export end to end: the exported folder (tables in four forms that
// agree, sky.json equal to the library's model, the shaders, the manifest), a scene rendered from
// the exported tables equal to the library's compositor on the same tables, the PNG's tone
// mapping, the same bytes for the same inputs, and a rain rate that changes the bow.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "hydrolux/io/image_io.hpp"
#include "hydrolux/io/lee_files.hpp"
#include "hydrolux/scene/compositor.hpp"
#include "hydrolux/scene/sky_model.hpp"
#include "support/cli.hpp"

namespace {

namespace fs = std::filesystem;
using hydrolux::testing::run;
using hydrolux::testing::slurp;
using namespace hydrolux;

// A small export, computed once: 24 radii x 128 angles, half the sampling.
const fs::path& assets() {
  static const fs::path dir = [] {
    const fs::path d = hydrolux::testing::temp_dir("hydrolux_export_cli") / "assets";
    const auto r = run("export --size 24x128 --sampling 0.5 -q --dir " + d.string());
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_TRUE(r.err.empty()) << r.err;
    return d;
  }();
  return dir;
}

TEST(ExportCli, WritesTablesSkyShadersAndManifest) {
  const fs::path& d = assets();
  for (const char* f : {"README.md", "manifest.json", "sky.json", "rainbow.exr", "rainbow.png", "rainbow.json",
                        "rainbow.f32", "corona.exr", "corona.png", "corona.json", "corona.f32",
                        "glsl/example.frag", "glsl/hydrolux_rainbow.glsl", "hlsl/example.hlsl"})
    EXPECT_TRUE(fs::is_regular_file(d / f)) << f;
  // No staging folder left behind.
  for (const auto& e : fs::directory_iterator(d.parent_path())) EXPECT_EQ(e.path().filename(), "assets");

  const auto manifest = nlohmann::json::parse(slurp(d / "manifest.json"));
  EXPECT_EQ(manifest.at("format"), "hydrolux-rainbow-assets");
  EXPECT_EQ(manifest.at("tables").at("rainbow").at("columns"), 24);
  EXPECT_EQ(manifest.at("tables").at("corona").at("rows"), 256);  // twice the rainbow's, over 0-90 degrees
  EXPECT_EQ(manifest.at("tables").at("corona").at("angle_deg")[1], 90.0);
  for (const auto& s : manifest.at("shaders")) EXPECT_TRUE(fs::is_regular_file(d / s.get<std::string>())) << s;

  // The raw float32 table is the EXR's R, G, B.
  for (const char* name : {"rainbow", "corona"}) {
    const auto exr = io::decode_image(slurp(d / (std::string(name) + ".exr")), name);
    const std::string raw = slurp(d / (std::string(name) + ".f32"));
    ASSERT_EQ(raw.size(), std::size_t(exr.image.width) * exr.image.height * 3 * 4) << name;
    std::vector<float> f(raw.size() / 4);
    std::memcpy(f.data(), raw.data(), raw.size());
    for (std::size_t p = 0; p < std::size_t(exr.image.width) * exr.image.height; ++p)
      for (int c = 0; c < 3; ++c) ASSERT_EQ(f[p * 3 + c], exr.image.pixels[p * exr.image.channels + c]) << name << p;
    const auto side = nlohmann::json::parse(slurp(d / (std::string(name) + ".json")));
    EXPECT_EQ(side.at("files").at("f32"), std::string(name) + ".f32");
    EXPECT_EQ(side.at("table"), name);

    // The Stokes Q for shaders (<name>_q.f32, the polariser) is the EXR's Q.X, Q.Y, Q.Z through the
    // sidecar's matrix, as hydrolux sky --lut reads it (io::lee_bow_table), to float rounding.
    const std::string qname = std::string(name) + "_q.f32";
    EXPECT_EQ(side.at("files").at("f32_q"), qname);
    EXPECT_EQ(manifest.at("tables").at(name).at("stokes_q"), qname);
    const std::string qraw = slurp(d / qname);
    ASSERT_EQ(qraw.size(), raw.size()) << name;
    std::vector<float> q(qraw.size() / 4);
    std::memcpy(q.data(), qraw.data(), qraw.size());
    const scene::BowTable read = io::lee_bow_table(io::parse_lee_sidecar(slurp(d / (std::string(name) + ".json"))),
                                                      io::decode_image(slurp(d / (std::string(name) + ".exr")), name));
    ASSERT_TRUE(read.has_q()) << name;
    float peak = 0, qmax = 0;
    for (float v : read.rgb) peak = std::max(peak, v);
    for (std::size_t i = 0; i < q.size(); ++i) {
      ASSERT_NEAR(q[i], read.q[i], 1e-5f * std::abs(read.q[i]) + 1e-9f * peak) << name << " " << i;
      qmax = std::max(qmax, std::abs(q[i]));
    }
    EXPECT_GT(qmax, 1e-5f * peak) << name;  // polarised light, not zeros (the corona's, 6e-5 of its forward peak)
  }
  // The sky's polarisation model for the shaders' polariser.
  EXPECT_EQ(nlohmann::json::parse(slurp(d / "sky.json")).at("polarization").at("sky_max_dolp").get<double>(),
            scene::kSkyMaxDolpDefault);

  // sky.json holds the library's model at every whole degree.
  const auto sky = nlohmann::json::parse(slurp(d / "sky.json"));
  ASSERT_EQ(sky.at("elevations_deg").size(), 91u);
  for (int e : {0, 25, 90}) {
    const auto s = scene::make_sun_sky(e, 2.5);
    EXPECT_DOUBLE_EQ(sky.at("sun_illuminance_lux")[std::size_t(e)].get<double>(), s.sun_illuminance_lux);
    EXPECT_DOUBLE_EQ(sky.at("l_ref")[std::size_t(e)].get<double>(), s.l_ref);
    EXPECT_DOUBLE_EQ(sky.at("perez_Y")[std::size_t(e)][3].get<double>(), s.perez[0].D);
  }
  // The rain law: coefficient x R^exponent equals the library at 7 mm/h.
  const double beta = sky.at("rain").at("coefficient").get<double>() *
                      std::pow(7.0, sky.at("rain").at("exponent").get<double>());
  EXPECT_NEAR(beta / scene::rain_beta_geo_per_m(7), 1.0, 1e-9);
}

// hydrolux sky with the exported tables: the EXR is the library's compositor on the same tables.
TEST(SkyCli, RendersFromExportedTablesAsTheLibraryDoes) {
  const fs::path& d = assets();
  const fs::path out = hydrolux::testing::temp_dir("hydrolux_sky_cli");
  const std::string args = " --size 96x54 --radius-um 300 --rain-rate-mmh 8 --sun-elevation-deg 30 --lut " +
                           (d / "rainbow.exr").string() + " --lut " + (d / "corona.exr").string() + " -q";
  auto r = run("sky" + args + " -o " + (out / "a.exr").string());
  ASSERT_EQ(r.code, 0) << r.err;
  r = run("sky" + args + " -o " + (out / "a.png").string());
  ASSERT_EQ(r.code, 0) << r.err;
  r = run("sky" + args + " -o " + (out / "b.png").string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(slurp(out / "a.png"), slurp(out / "b.png"));  // the same bytes

  // The library on the same tables (read from the EXR and its sidecar).
  const auto side = nlohmann::json::parse(slurp(d / "rainbow.json"));
  const auto exr = io::decode_image(slurp(d / "rainbow.exr"), "rainbow.exr").image;
  std::vector<float> rgb;
  for (std::size_t p = 0; p < std::size_t(exr.width) * exr.height; ++p)
    for (int c = 0; c < 3; ++c) rgb.push_back(exr.pixels[p * exr.channels + c]);
  const auto table = scene::bow_table(atmos::LeeTableKind::rainbow, atmos::AngleAxis::angle,
                                      side.at("radius_um").get<std::vector<double>>(),
                                      side.at("angle_deg").get<std::vector<double>>(), rgb);
  scene::SkySettings s;
  s.camera.width = 96;
  s.camera.height = 54;
  s.radius_um = 300;
  s.rain_rate_mmh = 8;
  s.sun_elevation_deg = 30;
  const scene::SkyCompositor comp(s, scene::slice_at_radius(table, 300), {});
  const Image lib = comp.render();
  const auto cli = io::decode_image(slurp(out / "a.exr"), "a.exr").image;
  ASSERT_EQ(cli.width, 96);
  ASSERT_EQ(cli.channels, 3);
  double worst = 0, peak = 0;
  for (std::size_t i = 0; i < lib.pixels.size(); ++i) {
    worst = std::max(worst, double(std::abs(cli.pixels[i] - lib.pixels[i])));
    peak = std::max(peak, double(lib.pixels[i]));
  }
  EXPECT_LE(worst, 1e-6 * peak);  // EXR float, bit for bit up to the encoder's float32
  // The PNG is the documented tone mapping of the EXR.
  const auto png = io::decode_image(slurp(out / "a.png"), "a.png").image;
  const Image tm = scene::tone_map(lib, comp.sun_sky().l_ref);
  double psnr = scene::psnr(png, tm);
  EXPECT_GT(psnr, 45) << "8-bit quantisation only";
}

TEST(SkyCli, RainRateAndBlendChangeTheFrame) {
  const fs::path& d = assets();
  const fs::path out = hydrolux::testing::temp_dir("hydrolux_sky_cli_rain");
  const std::string base = " --size 64x36 -q --lut " + (d / "rainbow.exr").string();
  for (const char* v : {"0.5", "50"}) {
    const auto r = run("sky" + base + " --rain-rate-mmh " + v + " -o " + (out / (std::string(v) + ".exr")).string());
    ASSERT_EQ(r.code, 0) << r.err;
  }
  auto r = run("sky" + base + " --rain-rate-mmh 0 -o " + (out / "dry.exr").string());
  ASSERT_EQ(r.code, 0) << r.err;
  r = run("sky" + base + " --blend whitepaper -o " + (out / "wp.exr").string());
  ASSERT_EQ(r.code, 0) << r.err;
  const auto light = io::decode_image(slurp(out / "0.5.exr"), "").image;
  const auto heavy = io::decode_image(slurp(out / "50.exr"), "").image;
  const auto dry = io::decode_image(slurp(out / "dry.exr"), "").image;
  const auto wp = io::decode_image(slurp(out / "wp.exr"), "").image;
  // The sky behind the rain: darker in a downpour (attenuation), and never darker with the
  // whitepaper's blend.
  EXPECT_LT(heavy.at(0, 0, 2), light.at(0, 0, 2));
  EXPECT_LT(light.at(0, 0, 2), dry.at(0, 0, 2));
  for (std::size_t i = 0; i < wp.pixels.size(); ++i) ASSERT_GE(wp.pixels[i], dry.pixels[i] * (1 - 1e-6f));
}

// The summary says how the profiles' sampling came about: chosen without --sampling (fogbow droplets'
// profiles state under 1% at 1, so no second pass), as given with it.
TEST(SkyCli, SummaryStatesTheProfilesSampling) {
  const fs::path out = hydrolux::testing::temp_dir("hydrolux_sky_sampling");
  auto r = run("sky --size 8x8 --radius-um 10 -o " + (out / "chosen.png").string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("RMS in luminance (sampling 1, chosen);"), std::string::npos) << r.err;
  r = run("sky --size 8x8 --radius-um 10 --sampling 0.25 -o " + (out / "given.png").string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("RMS in luminance (sampling 0.25);"), std::string::npos) << r.err;
}

TEST(SkyCli, TablesAreCheckedAgainstTheScene) {
  const fs::path& d = assets();
  const fs::path out = hydrolux::testing::temp_dir("hydrolux_sky_cli_bad");
  // A radius outside the table, a corona table alone, a table without its sidecar.
  auto r = run("sky --size 8x8 -q --radius-um 900 --lut " + (d / "rainbow.exr").string() + " -o " +
               (out / "x.png").string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--radius-um"), std::string::npos) << r.err;
  r = run("sky --size 8x8 -q --radius-um 10 --lut " + (d / "corona.exr").string() + " -o " + (out / "x.png").string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--lut"), std::string::npos) << r.err;
  fs::copy_file(d / "rainbow.exr", out / "lonely.exr");
  r = run("sky --size 8x8 -q --lut " + (out / "lonely.exr").string() + " -o " + (out / "x.png").string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--lut"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out / "x.png"));
}

}  // namespace
