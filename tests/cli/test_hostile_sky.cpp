// Issue #23, the sky / lee / export part: the holes a hostile probe found. A display PNG renamed
// .exr, or a sidecar with a reversed axis, negative values or a radius of 1e308, taken as a table
// of sr^-1; flags accepted and ignored; a frame too large for the memory refused only by running
// out of it; messages that named neither the flag nor the file, or a range the check disagreed with.
// Each case is bad input: exit 2, one line naming the flag, nothing written.
#include <gtest/gtest.h>
#include <sys/resource.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "hydrolux/atmos/lee.hpp"
#include "hydrolux/core/error.hpp"
#include "hydrolux/io/image_io.hpp"
#include "hydrolux/scene/compositor.hpp"
#include "support/asan.hpp"
#include "support/cli.hpp"

namespace {

namespace fs = std::filesystem;
using hydrolux::testing::lines;
using hydrolux::testing::run_argv;
using hydrolux::testing::slurp;
using namespace hydrolux;

void spit(const fs::path& p, const std::string& text) { std::ofstream(p, std::ios::binary) << text; }

// A small rainbow table written by hydrolux lee (its .exr, .png and .json), made once.
const fs::path& table_dir() {
  static const fs::path dir = [] {
    const fs::path d = hydrolux::testing::temp_dir("hydrolux_hostile_sky");
    const auto r = run_argv({"lee", "-q", "--size", "3x16", "--radius-um", "400:600", "--angle-deg", "130:145",
                             "--wavelengths-nm", "500:600:2", "-o", (d / "t.exr").string()});
    EXPECT_EQ(r.code, 0) << r.err;
    return d;
  }();
  return dir;
}
fs::path table() { return table_dir() / "t.exr"; }

// A sky run on a table: small and fast (no table computed).
std::vector<std::string> sky_args(const fs::path& lut, const fs::path& out, std::vector<std::string> more = {}) {
  std::vector<std::string> a = {"sky", "-q", "--radius-um", "500", "--size", "16x9", "--lut", lut.string(),
                                "-o", out.string()};
  a.insert(a.end(), more.begin(), more.end());
  return a;
}

// Exit 2, one line naming `flag` and containing `what`, nothing on stdout, no output written.
void expect_refused(const std::vector<std::string>& args, const std::string& flag, const std::string& what,
                    const fs::path& out = {}, const std::function<void()>& hook = {}) {
  std::string cmd;
  for (const auto& a : args) cmd += " " + a;
  const auto r = run_argv(args, hook);
  EXPECT_EQ(r.code, 2) << cmd << "\n" << r.err;
  EXPECT_EQ(lines(r.err), 1u) << cmd << "\n" << r.err;
  EXPECT_NE(r.err.find(flag), std::string::npos) << cmd << "\n" << r.err;
  EXPECT_NE(r.err.find(what), std::string::npos) << cmd << "\n" << r.err;
  EXPECT_TRUE(r.out.empty()) << cmd;
  if (!out.empty()) {
    EXPECT_FALSE(fs::exists(out)) << cmd;
  }
}

// A copy of the table under `name` with its sidecar changed by `edit` (and its EXR replaced by
// `exr_bytes` when given).
fs::path forged(const std::string& name, const std::function<void(nlohmann::json&)>& edit,
                const std::string& exr_bytes = {}) {
  const fs::path d = table_dir();
  auto side = nlohmann::json::parse(slurp(d / "t.json"));
  edit(side);
  spit(d / (name + ".json"), side.dump());
  spit(d / (name + ".exr"), exr_bytes.empty() ? slurp(d / "t.exr") : exr_bytes);
  return d / (name + ".exr");
}

TEST(HostileSky, TheUntouchedTableIsAccepted) {  // the control: the cases below fail for their one change
  const fs::path out = table_dir() / "control.png";
  const auto r = run_argv(sky_args(table(), out));
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(fs::is_regular_file(out));
}

// 1. The content decides: a display PNG renamed .exr is not a table of sr^-1.
TEST(HostileSky, RenamedPngIsNotATable) {
  const fs::path lut = forged("renamed", [](nlohmann::json&) {}, slurp(table_dir() / "t.png"));
  const fs::path out = table_dir() / "renamed_out.png";
  expect_refused(sky_args(lut, out), "--lut", "PNG", out);
  expect_refused(sky_args(lut, out), "--lut", lut.string(), out);
}

// 1. The sidecar's axes and the values are checked, each with what is wrong.
TEST(HostileSky, ForgedSidecarsAreRefused) {
  const fs::path out = table_dir() / "forged_out.png";
  struct Forgery {
    std::string name, what;
    std::function<void(nlohmann::json&)> edit;
  };
  const std::vector<Forgery> forgeries = {
      {"reversed", "increase", [](nlohmann::json& j) {
         auto a = j.at("angle_deg").get<std::vector<double>>();
         std::reverse(a.begin(), a.end());
         j["angle_deg"] = a;
       }},
      {"huge_radius", "1e+308", [](nlohmann::json& j) { j["radius_um"] = {400.0, 500.0, 1e308}; }},
      {"radius_not_log", "not uniform", [](nlohmann::json& j) { j["radius_um"] = {400.0, 401.0, 600.0}; }},
      {"radius_not_linear", "not uniform", [](nlohmann::json& j) {
         j["radius_scale"] = "linear";
         j["radius_um"] = {400.0, 489.0, 600.0};
       }},
      {"radius_down", "increase", [](nlohmann::json& j) { j["radius_um"] = {600.0, 500.0, 400.0}; }},
      {"no_scale", "radius_scale", [](nlohmann::json& j) { j.erase("radius_scale"); }},
      {"angle_out", "outside", [](nlohmann::json& j) {
         auto a = j.at("angle_deg").get<std::vector<double>>();
         for (auto& v : a) v += 100;
         j["angle_deg"] = a;
       }},
  };
  for (const auto& f : forgeries) {
    SCOPED_TRACE(f.name);
    const fs::path lut = forged(f.name, f.edit);
    expect_refused(sky_args(lut, out), "--lut", f.what, out);
  }
  // A table of all -1: negative radiance out.
  Image minus(3, 16, 3);
  for (auto& v : minus.pixels) v = -1;
  const fs::path lut = forged("negative", [](nlohmann::json&) {}, io::encode_image(minus, io::ImageFormat::exr));
  expect_refused(sky_args(lut, out), "--lut", "non-negative", out);
}

// 2. A flag given where it has no effect is refused, saying why; given where it is used, or not
// given at all (its default), it is not.
TEST(HostileSky, FlagsThatWouldBeIgnoredAreRefused) {
  const fs::path d = table_dir(), out = d / "ignored_out.png";
  expect_refused(sky_args(table(), out, {"--sampling", "2"}), "--sampling", "--lut", out);
  expect_refused(sky_args(table(), out, {"--environment-scale", "2"}), "--environment-scale", "--environment", out);
  expect_refused(sky_args(table(), out, {"--cube-face-size", "64"}), "--cube-face-size", "cube-map", out);
  expect_refused(sky_args(table(), out, {"--dome-rings", "10"}), "--dome-rings", "half-dome", out);
  expect_refused(sky_args(table(), out, {"--dome-segments", "10"}), "--dome-segments", "half-dome", out);
  expect_refused(sky_args(table(), out, {"--mode", "cube-map", "--dome-rings", "10"}), "--dome-rings", "half-dome", out);
  expect_refused(sky_args(table(), out, {"--mode", "half-dome", "--cube-face-size", "64"}), "--cube-face-size",
                 "cube-map", out);
  // --corona where no corona can be drawn: rain drops (no table is computed above 50 um), or tables
  // without a corona table.
  expect_refused({"sky", "-q", "--corona", "--radius-um", "500", "--size", "16x9", "-o", out.string()}, "--corona",
                 "1-50 um", out);
  expect_refused(sky_args(table(), out, {"--corona"}), "--corona", "no corona table", out);
  // Where they are used:
  for (const auto& more : std::vector<std::vector<std::string>>{
           {"--mode", "cube-map", "--cube-face-size", "16"},
           {"--mode", "half-dome", "--dome-rings", "8", "--dome-segments", "16"},
           {"--mode", "cube-map"}}) {
    const auto r = run_argv(sky_args(table(), out, more));
    EXPECT_EQ(r.code, 0) << more[1] << ": " << r.err;
  }
  // lee: limb darkening of a point sun; the spacing of one column.
  expect_refused({"lee", "-q", "--limb-darkening", "--sun-disk-deg", "0", "--radius-um", "10", "--json"},
                 "--limb-darkening", "point");
  expect_refused({"lee", "-q", "--radius-scale", "linear", "--radius-um", "10", "--json"}, "--radius-scale",
                 "one column");
}

// 3. A frame that cannot fit in the memory left is refused before the work, naming the flag and
// what would fit; the address-space limit makes "the memory left" small on any machine. Without
// AddressSanitizer, whose shadow memory needs far more address space than the limits allow.
TEST(HostileSky, OversizedFramesAreRefusedUpFront) {
#if HYDROLUX_TEST_ASAN
  GTEST_SKIP() << "RLIMIT_AS and AddressSanitizer's shadow memory do not mix";
#endif
  const fs::path out = table_dir() / "huge.png";
  const auto limit = [] {
    const rlimit lim{rlim_t(3) << 30, rlim_t(3) << 30};  // 3 GiB of address space
    ::setrlimit(RLIMIT_AS, &lim);
  };
  std::vector<std::string> args = sky_args(table(), out);
  args[5] = "16384x16384";
  expect_refused(args, "--size", "fit (--size", out, limit);
  expect_refused(args, "--size", "megapixels", out, limit);
  args[5] = "64x36";
  auto cube = args;
  cube.insert(cube.end(), {"--mode", "cube-map", "--cube-face-size", "4096"});  // 1.2 GB of cube map
  const auto limit1 = [] {
    const rlimit lim{rlim_t(1) << 30, rlim_t(1) << 30};
    ::setrlimit(RLIMIT_AS, &lim);
  };
  expect_refused(cube, "--cube-face-size", "texels fit", out, limit1);
  // Under the same 3 GiB, a frame that fits is rendered.
  const auto r = run_argv(args, limit);
  EXPECT_EQ(r.code, 0) << r.err;
  // lee and export: the table's arrays, likewise.
  expect_refused({"lee", "-q", "--size", "8192x8192", "--radius-um", "1:2", "--size-spread", "0", "-o",
                  (table_dir() / "big.exr").string()},
                 "--size", "would fit", table_dir() / "big.exr", limit);
  expect_refused({"export", "-q", "--size", "4096x8192", "--dir", (table_dir() / "big").string()}, "--size",
                 "would fit", table_dir() / "big", limit);
  // The estimate holds the measurement it documents: 16384x16384 peaked at 7.2 GB resident.
  scene::SkySettings s;
  s.camera.width = s.camera.height = 16384;
  EXPECT_GT(scene::estimated_bytes(s), 7.2e9);
}

// 4. Messages name the flag, the file and the range the check applies.
TEST(HostileSky, MessagesNameTheFlagTheFileAndTheRealRange) {
  const fs::path d = table_dir(), out = d / "msg_out.png";
  // An environment map that is not 2:1.
  spit(d / "env.exr", io::encode_image(Image(30, 10, 3), io::ImageFormat::exr));
  expect_refused(sky_args(table(), out, {"--environment", (d / "env.exr").string()}), "--environment",
                 (d / "env.exr").string(), out);
  // --radius-um: the help's range is the library's, and the check agrees with it.
  atmos::LeeSpec spec = atmos::default_lee_spec(atmos::LeeTableKind::rainbow);
  const double rmax = atmos::max_radius_um(spec);
  EXPECT_GT(rmax, 1000);
  EXPECT_LT(rmax, atmos::kMaxRadiusUm);
  spec.radius_min_um = spec.radius_max_um = rmax;
  spec.columns = 1;
  EXPECT_NO_THROW(atmos::validate(spec));
  spec.radius_min_um = spec.radius_max_um = rmax + 1;
  EXPECT_THROW(atmos::validate(spec), DomainError);
  const std::string range = fmt::format("[0.1, {:g}] um", rmax);
  for (const char* cmd : {"sky", "export"}) {
    SCOPED_TRACE(cmd);
    const auto help = run_argv({cmd, "--help"});
    EXPECT_NE(help.out.find(fmt::format("at most {:g}", rmax)), std::string::npos) << help.out;
  }
  // sky computes its tables with Mie theory only: 5000 um only with tables given (--lut).
  EXPECT_NE(run_argv({"sky", "--help"}).out.find("with --lut up to 5000"), std::string::npos);
  expect_refused({"sky", "-q", "--radius-um", "5000", "-o", out.string()}, "--radius-um", range, out);
  expect_refused({"export", "-q", "--radius-um", "5000", "--dir", (d / "assets").string()}, "--radius-um", range);
  // export --size: the corona table has twice the rows; the message names what the user gave.
  expect_refused({"export", "-q", "--size", "16x16384", "--dir", (d / "assets").string()}, "--size 16x16384",
                 "at most 8192");
  EXPECT_FALSE(fs::exists(d / "assets"));
  // lee: a radius that is not a number is refused with the range.
  expect_refused({"lee", "-q", "--radius-um", "nan", "-o", (d / "l.exr").string()}, "--radius-um", "[0.1, 5000]");
  expect_refused({"lee", "-q", "--radius-um", "3000", "-o", (d / "l.exr").string()}, "--radius-um",
                 fmt::format("[0.1, {:g}] um", rmax));
}

}  // namespace
