// hydrolux lee end to end: the three files and their contract (EXR channels, PNG, the sidecar's
// axes and units), the table equal to the library's, the one-radius JSON profile, the same bytes
// for the same inputs, and bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "hydrolux/atmos/lee.hpp"
#include "hydrolux/io/image_io.hpp"
#include "support/cli.hpp"

namespace {

namespace fs = std::filesystem;
using hydrolux::testing::expect_usage_errors;
using hydrolux::testing::run;

using hydrolux::testing::slurp;

constexpr const char* kSmall = "--size 6x9 --radius-um 20:400 --angle-deg 130:145 --wavelengths-nm 400:700:24 -q";

TEST(LeeCli, WritesExrPngAndSidecar) {
  const fs::path dir = hydrolux::testing::temp_dir("hydrolux_lee_cli");
  const auto r = run(std::string("lee ") + kSmall + " -o " + (dir / "t.exr").string());
  ASSERT_EQ(r.code, 0) << r.err;
  // -q: no progress or summary; only the warning that 9 rows over 15 degrees alias the supernumeraries.
  EXPECT_EQ(r.err.find("hydrolux lee: warning: the rows are 1.88 deg apart at the primary bow"), 0u) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  ASSERT_TRUE(fs::exists(dir / "t.exr"));
  ASSERT_TRUE(fs::exists(dir / "t.png"));
  ASSERT_TRUE(fs::exists(dir / "t.json"));
  // Nothing else (no temporary file left).
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 3);

  const auto exr = hydrolux::io::decode_image(slurp(dir / "t.exr"), "t.exr");
  EXPECT_EQ(exr.image.width, 6);
  EXPECT_EQ(exr.image.height, 9);
  EXPECT_EQ(exr.image.channels, 6);  // R, G, B, XYZ.X, XYZ.Y, XYZ.Z
  const auto png = hydrolux::io::decode_image(slurp(dir / "t.png"), "t.png");
  EXPECT_EQ(png.image.width, 6);
  EXPECT_EQ(png.image.channels, 3);
  for (const char* name : {"R", "G", "B", "XYZ.X", "XYZ.Y", "XYZ.Z"})
    EXPECT_NE(slurp(dir / "t.exr").find(name), std::string::npos) << name;

  const auto j = nlohmann::json::parse(slurp(dir / "t.json"));
  EXPECT_EQ(j.at("units"), "sr^-1");
  EXPECT_EQ(j.at("table"), "rainbow");
  EXPECT_EQ(j.at("theory"), "mie");
  EXPECT_EQ(j.at("width"), 6);
  EXPECT_EQ(j.at("height"), 9);
  EXPECT_EQ(j.at("files").at("png"), "t.png");
  for (const char* k : {"quantity", "layout", "color_space", "spectrum", "sun_disk", "size_distribution", "medium",
                        "sampling", "hydrolux_version", "png", "channels"})
    EXPECT_TRUE(j.contains(k)) << k;
  const auto radius = j.at("radius_um").get<std::vector<double>>();
  const auto angle = j.at("angle_deg").get<std::vector<double>>();
  ASSERT_EQ(radius.size(), 6u);
  ASSERT_EQ(angle.size(), 9u);
  EXPECT_DOUBLE_EQ(radius.front(), 20);
  EXPECT_DOUBLE_EQ(radius.back(), 400);
  EXPECT_DOUBLE_EQ(angle.front(), 130);
  EXPECT_DOUBLE_EQ(angle.back(), 145);
  EXPECT_EQ(j.at("spectrum").at("wavelengths_nm").size(), 24u);
  EXPECT_EQ(j.at("sun_disk").at("diameter_deg"), 0.53);
  EXPECT_EQ(j.at("size_distribution").at("relative_width"), 0.1);

  // The EXR holds the library's table: the same spec, the same numbers (float).
  hydrolux::atmos::LeeSpec s;
  s.columns = 6;
  s.rows = 9;
  s.radius_min_um = 20;
  s.radius_max_um = 400;
  s.angle_min_deg = 130;
  s.angle_max_deg = 145;
  s.wavelength_min_nm = 400;
  s.wavelength_max_nm = 700;
  s.wavelengths = 24;
  const auto t = hydrolux::atmos::compute_lee_table(s);
  for (int y = 0; y < 9; ++y)
    for (int x = 0; x < 6; ++x) {
      const auto rgb = t.rgb(y, x);
      for (int c = 0; c < 3; ++c) EXPECT_FLOAT_EQ(exr.image.at(x, y, c), float(rgb[std::size_t(c)])) << x << "," << y;
      EXPECT_FLOAT_EQ(exr.image.at(x, y, 4), float(t.at(y, x).Y));
    }

  // Same inputs, same bytes: all three files.
  const auto again = run(std::string("lee ") + kSmall + " -o " + (dir / "u.exr").string());
  ASSERT_EQ(again.code, 0) << again.err;
  EXPECT_EQ(slurp(dir / "t.exr"), slurp(dir / "u.exr"));
  EXPECT_EQ(slurp(dir / "t.png"), slurp(dir / "u.png"));
  EXPECT_EQ(slurp(dir / "t.json").substr(slurp(dir / "t.json").find("\"hydrolux_version\"")),
            slurp(dir / "u.json").substr(slurp(dir / "u.json").find("\"hydrolux_version\"")));
  fs::remove_all(dir);
}

// The cosine axis: the sidecar carries cos_angle (increasing downward) instead of angle_deg; the
// corona and glory tables take their own defaults.
TEST(LeeCli, CosineAxisCoronaAndGlory) {
  const fs::path dir = hydrolux::testing::temp_dir("hydrolux_lee_cli_cos");
  ASSERT_EQ(run("lee -q --size 3x5 --radius-um 5:50 --axis cos --wavelengths-nm 450:650:3 -o " + (dir / "c.exr").string()).code, 0);
  const auto j = nlohmann::json::parse(slurp(dir / "c.json"));
  EXPECT_FALSE(j.contains("angle_deg"));
  const auto c = j.at("cos_angle").get<std::vector<double>>();
  ASSERT_EQ(c.size(), 5u);
  EXPECT_NEAR(c.front(), -1.0, 1e-15);
  EXPECT_NEAR(c.back(), 0.0, 1e-15);
  EXPECT_LT(c[1], c[2]);
  for (const char* table : {"corona", "glory"}) {
    const auto r = run(std::string("lee -q --table ") + table + " --size 3x5 --wavelengths-nm 450:650:3 -o " +
                       (dir / (std::string(table) + ".exr")).string());
    ASSERT_EQ(r.code, 0) << r.err;
    const auto k = nlohmann::json::parse(slurp(dir / (std::string(table) + ".json")));
    EXPECT_EQ(k.at("table"), table);
    const auto a = k.at("angle_deg").get<std::vector<double>>();
    EXPECT_DOUBLE_EQ(a.front(), std::string(table) == "corona" ? 0.0 : 160.0);
    EXPECT_DOUBLE_EQ(a.back(), std::string(table) == "corona" ? 20.0 : 180.0);
    EXPECT_DOUBLE_EQ(k.at("radius_um").back().get<double>(), 50.0);
  }
  fs::remove_all(dir);
}

// One radius as JSON: angle, RGB, luminance per sample; the primary's peak of a 500 um drop in
// 138-139 degrees (as the library test checks in detail).
TEST(LeeCli, OneRadiusProfile) {
  const auto r = run("lee --radius-um 500 --angle-deg 130:145 --size 1x151 --size-spread 0 --json");
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j.at("radius_um"), 500.0);
  const auto angle = j.at("angle_deg").get<std::vector<double>>();
  const auto lum = j.at("luminance").get<std::vector<double>>();
  ASSERT_EQ(angle.size(), 151u);
  ASSERT_EQ(lum.size(), 151u);
  ASSERT_EQ(j.at("rgb").size(), 151u);
  ASSERT_EQ(j.at("rgb")[0].size(), 3u);
  const auto peak = std::max_element(lum.begin(), lum.end()) - lum.begin();
  EXPECT_GE(angle[std::size_t(peak)], 138.0);
  EXPECT_LE(angle[std::size_t(peak)], 139.0);
}

TEST(LeeCli, BadInput) {
  const std::string out = " -o " + (fs::temp_directory_path() / "hydrolux_lee_never.exr").string();
  expect_usage_errors(std::vector<std::pair<std::string, std::string>>{
      {"lee --radius-um 800:5" + out, "--radius-um"},
      {"lee --radius-um 0.01:5" + out, "--radius-um"},
      {"lee --radius-um 4000:5000" + out, "--radius-um"},  // x beyond the Mie solver at 380 nm
      {"lee --angle-deg 90:190" + out, "--angle-deg"},
      {"lee --size 0x10" + out, "--size"},
      {"lee --size 512" + out, "--size"},
      {"lee --radius-um 500 --size 4x10" + out, "--size"},
      {"lee --sun-disk-deg 9" + out, "--sun-disk-deg"},
      {"lee --size-spread 0.9" + out, "--size-spread"},
      {"lee --wavelengths-nm 300:700" + out, "--wavelengths-nm"},
      {"lee --wavelengths-nm 700:400" + out, "--wavelengths-nm"},
      {"lee --theory airy --table corona" + out, "Airy"},
      {"lee --theory nope" + out, "--theory"},
      {"lee --medium gold" + out, "--medium"},
      {"lee --sun blackbody:1" + out, "--sun"},
      {"lee --temperature-c 150" + out, "--temperature-c"},
      {"lee -o lee.png", "-o"},
      {"lee", "-o"},
      {"lee --json" + out, "--json"},
  });
  EXPECT_FALSE(fs::exists(fs::temp_directory_path() / "hydrolux_lee_never.exr"));
}

// Issue 37: the flags of non-spherical drops (--sun-elevation-deg, --position-deg, --canting-deg)
// given for spheres would be ignored: refused, as export refuses --sun-elevation-deg without
// --shape, in export's words; with a shape they are taken.
TEST(LeeCli, ShapeFlagsForSpheresAreRefused) {
  const fs::path never = fs::temp_directory_path() / "hydrolux_lee_never_shape.nc";
  const std::string out = std::string(" ") + kSmall + " -o " + never.string();
  expect_usage_errors(std::vector<std::pair<std::string, std::string>>{
      {"lee --sun-elevation-deg 20" + out, "--sun-elevation-deg 20: "},
      {"lee --position-deg 30" + out, "--position-deg 30: "},
      {"lee --canting-deg 5" + out, "--canting-deg 5: "},
      {"lee --shape sphere --canting-deg 0" + out, "--canting-deg 0: "},  // given, even at its default
      {"lee --radius-um 500 --size 1x9 --json --sun-elevation-deg 10", "--sun-elevation-deg 10: "},
  });
  EXPECT_FALSE(fs::exists(never));
  // export's sentence, word for word after the flag and its value.
  const auto lee = run("lee --sun-elevation-deg 20" + out);
  const auto exp = run("export -q --sun-elevation-deg 20 --dir " + (fs::temp_directory_path() / "hydrolux_never_export").string());
  ASSERT_EQ(exp.code, 2) << exp.err;
  const auto sentence = [](const std::string& err) { return err.substr(err.find("--sun-elevation-deg 20: ")); };
  EXPECT_EQ(sentence(lee.err), sentence(exp.err));
  EXPECT_FALSE(fs::exists(fs::temp_directory_path() / "hydrolux_never_export"));
  for (const char* flag : {"--position-deg 30", "--canting-deg 5"}) {
    const auto r = run(std::string("lee ") + flag + out);
    EXPECT_NE(r.err.find("of the non-spherical drops' table (--shape); the spheres' tables do not depend on it (omit "
                         "it or give --shape)"),
              std::string::npos)
        << r.err;
  }
  // With a shape: taken.
  const auto shaped = run("lee -q --theory airy --shape spheroid:0.95 --radius-um 500 --size 1x9 --angle-deg 130:145 "
                          "--wavelengths-nm 400:700:4 --sun-elevation-deg 20 --position-deg 30 --canting-deg 5 --json");
  EXPECT_EQ(shaped.code, 0) << shaped.err;
}

}  // namespace
