// End-to-end tests of the hydrolux command line: the contract of issue #2 (flags, JSON fields,
// exit codes, one-line errors) as a user or script sees it.
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>

#include "hydrolux/optics/fresnel.hpp"
#include "support/asan.hpp"
#include "support/cli.hpp"
#include "hydrolux/optics/media.hpp"
#include "hydrolux/scatter/mie.hpp"
#include "hydrolux/scatter/sphere.hpp"

namespace {

using hydrolux::testing::expect_usage_errors;
using hydrolux::testing::lines;
using hydrolux::testing::run;
namespace fs = std::filesystem;

TEST(Cli, VersionAndHelp) {
  const auto v = run("--version");
  EXPECT_EQ(v.code, 0);
  EXPECT_EQ(v.out.rfind("hydrolux ", 0), 0u);
  for (const char* cmd : {"", "fresnel ", "ior ", "gallery "}) {
    const auto h = run(std::string(cmd) + "--help");
    EXPECT_EQ(h.code, 0) << cmd;
    EXPECT_NE(h.out.find("Usage"), std::string::npos) << cmd;
  }
  EXPECT_NE(run("fresnel --help").out.find("deg"), std::string::npos);       // units in help
  EXPECT_NE(run("ior --help").out.find("nm"), std::string::npos);
}

TEST(Cli, FresnelJsonContract) {
  const auto r = run("fresnel --n1 1 --n2 1.333 --theta-deg 45 --json");
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  const auto f = hydrolux::optics::fresnel_dielectric(std::cos(45 * std::acos(-1.0) / 180), 1.0, 1.333);
  EXPECT_NEAR(j.at("rs").get<double>(), f.R_s, 1e-15);
  EXPECT_NEAR(j.at("rp").get<double>(), f.R_p, 1e-15);
  EXPECT_NEAR(j.at("r").get<double>(), f.R, 1e-15);
  EXPECT_NEAR(j.at("t").get<double>(), 1 - f.R, 1e-14);
  EXPECT_NEAR(j.at("theta_t_deg").get<double>(), 32.0367, 1e-4);
  EXPECT_EQ(j.at("tir").get<bool>(), false);
  EXPECT_EQ(j.size(), 6u);
  // Field order as documented.
  EXPECT_LT(r.out.find("theta_t_deg"), r.out.find("\"rs\""));
  EXPECT_LT(r.out.find("\"rs\""), r.out.find("\"tir\""));
}

TEST(Cli, FresnelConductorAndTir) {
  const auto c = nlohmann::json::parse(run("fresnel --n1 1 --n2 0.43 --k2 2.455 --theta-deg 0 --json").out);
  EXPECT_TRUE(c.at("t").is_null());
  EXPECT_TRUE(c.at("theta_t_deg").is_null());
  EXPECT_NEAR(c.at("r").get<double>(), 0.7869, 5e-5);  // gold at 548.6 nm, Johnson & Christy
  const auto t = nlohmann::json::parse(run("fresnel --n1 1.333 --n2 1 --theta-deg 50 --json").out);
  EXPECT_TRUE(t.at("tir").get<bool>());
  EXPECT_EQ(t.at("r").get<double>(), 1.0);
  EXPECT_EQ(t.at("t").get<double>(), 0.0);
  const auto text = run("fresnel --n2 1.5 --theta-deg 45");
  EXPECT_EQ(text.code, 0);
  EXPECT_NE(text.out.find("0.092013"), std::string::npos);
}

TEST(Cli, IorJsonContract) {
  const auto r = run("ior --medium water --wavelength-nm 589.3 --temperature-c 25 --json");
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j.at("medium"), "water");
  EXPECT_EQ(j.at("wavelength_nm").get<double>(), 589.3);
  EXPECT_DOUBLE_EQ(j.at("n").get<double>(), hydrolux::optics::find_medium("water")->n(589.3, 25.0));
  EXPECT_GT(j.at("k").get<double>(), 0.0);
  const auto g = nlohmann::json::parse(run("ior --medium gold --wavelength-nm 548.6 --json").out);
  EXPECT_DOUBLE_EQ(g.at("n").get<double>(), 0.43);
  EXPECT_DOUBLE_EQ(g.at("k").get<double>(), 2.455);
  const auto list = run("ior --list");
  EXPECT_EQ(list.code, 0);
  EXPECT_NE(list.out.find("aluminium"), std::string::npos);
  EXPECT_EQ(nlohmann::json::parse(run("ior --list --json").out).size(),
            hydrolux::optics::medium_names().size());
}

// Bad input: exit code 2, exactly one line on stderr that names the flag and the value, nothing on
// stdout.
TEST(Cli, BadInputIsOneLineAndExitCodeTwo) {
  const std::pair<const char*, const char*> cases[] = {
      {"fresnel --n1 1 --n2 1.333 --theta-deg 100", "--theta-deg"},
      {"fresnel --n1 1 --n2 1.333 --theta-deg -1", "--theta-deg"},
      {"fresnel --n1 1 --n2 1.333 --theta-deg nan", "--theta-deg"},
      {"fresnel --n1 1 --n2 1.333 --theta-deg abc", "--theta-deg"},
      {"fresnel --n1 0 --n2 1.333 --theta-deg 10", "--n1"},
      {"fresnel --n2 1.333 --k2 -1 --theta-deg 10", "--k2"},
      {"fresnel --n2 1.333", "--theta-deg"},
      {"ior --medium milk --wavelength-nm 500", "--medium"},
      {"ior --medium water --wavelength-nm -5", "--wavelength-nm"},
      {"ior --medium water --wavelength-nm abc", "--wavelength-nm"},
      {"ior --medium water --wavelength-nm 100", "--wavelength-nm"},
      {"ior --medium water --wavelength-nm 1200", "--wavelength-nm"},
      {"ior --medium water --wavelength-nm inf", "--wavelength-nm"},
      {"ior --medium water --wavelength-nm 500 --temperature-c 150", "--temperature-c"},
      {"ior --medium ice --wavelength-nm 500 --temperature-c 0", "--temperature-c"},
      {"ior --wavelength-nm 500", "--medium"},
      {"ior --medium water", "--wavelength-nm"},
      {"fresnel --theta-deg 10 --bogus 3", "--bogus"},
  };
  expect_usage_errors(cases);
  // The value and the valid range are in the message.
  const auto r = run("ior --medium water --wavelength-nm 100");
  EXPECT_NE(r.err.find("100"), std::string::npos);
  EXPECT_NE(r.err.find("[200, 1100] nm"), std::string::npos) << r.err;
  EXPECT_NE(run("fresnel --theta-deg 100").err.find("[0, 90] deg"), std::string::npos);
}

TEST(Cli, MieJsonContract) {
  const auto r = run("mie --m 1.333+1e-8i --x 1000 --angles-deg 0,10,90 --json");
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  for (const char* key : {"x", "m", "n_terms", "qext", "qsca", "qabs", "qback", "g", "angles_deg", "s1", "s2",
                          "compute_s"})
    EXPECT_TRUE(j.contains(key)) << key;
  const auto c = hydrolux::scatter::mie_coefficients({1.333, 1e-8}, 1000.0);
  const auto q = hydrolux::scatter::mie_efficiencies(c);
  EXPECT_EQ(j.at("n_terms").get<int>(), c.terms());
  EXPECT_DOUBLE_EQ(j.at("qext").get<double>(), q.qext);
  EXPECT_DOUBLE_EQ(j.at("g").get<double>(), q.g);
  EXPECT_EQ(j.at("m"), nlohmann::json::array({1.333, 1e-8}));
  EXPECT_EQ(j.at("angles_deg").size(), 3u);
  EXPECT_EQ(j.at("s1").size(), 3u);
  EXPECT_EQ(j.at("s2")[0].size(), 2u);  // [re, im]
  // Optical theorem through the CLI: Qext = 4/x^2 Re S(0). The amplitude path and the efficiency
  // sum add ~1000 terms in different orders: 1e-11 relative covers their rounding.
  EXPECT_NEAR(4.0 / 1e6 * j.at("s1")[0][0].get<double>(), q.qext, 1e-11 * q.qext);
  EXPECT_GE(j.at("compute_s").get<double>(), 0.0);
  // Angle ranges A:B:N, inclusive.
  const auto g = nlohmann::json::parse(run("mie --m 1.5 --x 3 --angles-deg 0:180:1801 --json").out);
  EXPECT_EQ(g.at("angles_deg").size(), 1801u);
  EXPECT_DOUBLE_EQ(g.at("angles_deg")[1800].get<double>(), 180.0);
  EXPECT_DOUBLE_EQ(g.at("angles_deg")[10].get<double>(), 1.0);
}

// The physical form computes m and x from the media: water in air at 650 nm.
TEST(Cli, MiePhysicalForm) {
  const auto r = run("mie --radius-um 500 --wavelength-nm 650 --medium water --angles-deg 0 --json");
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  const auto p = hydrolux::scatter::sphere_problem(500, 650, *hydrolux::optics::find_medium("water"),
                                                   *hydrolux::optics::find_medium("air"));
  EXPECT_DOUBLE_EQ(j.at("x").get<double>(), p.x);
  EXPECT_DOUBLE_EQ(j.at("m")[0].get<double>(), p.m.real());
  EXPECT_NEAR(p.x, 2 * std::acos(-1.0) * 500e3 * 1.00027 / 650, 0.5);
  const auto vac = nlohmann::json::parse(
      run("mie --radius-um 500 --wavelength-nm 650 --surrounding const:1 --angles-deg 0 --json").out);
  EXPECT_NEAR(vac.at("x").get<double>(), 2 * std::acos(-1.0) * 500e3 / 650, 1e-9);
}

TEST(Cli, MieBadInput) {
  const std::pair<const char*, const char*> cases[] = {
      {"mie --m 1.333 --x 0", "--x"},
      {"mie --m 1.333 --x 2e6", "--x"},
      {"mie --m 1.333 --x 5e-7", "--x"},
      {"mie --m 1.333-1i --x 10", "--m"},
      {"mie --m abc --x 10", "--m"},
      {"mie --m 2000 --x 10", "--m"},
      {"mie --m 1+2000i --x 10", "--m"},
      {"mie --m 0 --x 10", "--m"},
      {"mie --m 1.333 --x 10 -o /tmp/hydrolux_mie_never.txt", "-o"},
      {"mie --m 1.333 --x 10 -o /nonexistent-folder/s.npy", "-o"},
      {"mie --m 1.333 --x 10 --no-angles -o /tmp/hydrolux_mie_never.npy", "-o"},
      {"mie --m 1.333 --x 10 --angles-deg 0:200:5", "--angles-deg"},
      {"mie --m 1.333 --x 10 --angles-deg 0:180:0", "--angles-deg"},
      {"mie --m 1.333 --x 10 --angles-deg 10,abc", "--angles-deg"},
      {"mie --radius-um 500 --wavelength-nm 100", "--wavelength-nm"},
      {"mie --radius-um -5 --wavelength-nm 500", "--radius-um"},
      {"mie --m 1.333", "--x"},
      {"mie --m 1.333 --x 10 --radius-um 3", "--radius-um"},
      {"mie --m 1.333 --x 10 --threads -1", "--threads"},
      // Issue 37: "0:180:1" was 0 alone; repeated or unsorted angles made a table (and a .nc
      // coordinate) that is not monotonic.
      {"mie --m 1.333 --x 10 --angles-deg 0:180:1", "N must be >= 2, or A == B"},
      {"mie --m 1.333 --x 10 --angles-deg 10,10,20", "--angles-deg"},
      {"mie --m 1.333 --x 10 --angles-deg 0,90,45", "--angles-deg"},
      {"mie --m 1.333 --x 10 --angles-deg 0:1e-322:1000", "--angles-deg"},  // too narrow for 1000 doubles
      {"mie --m 1.333 --x 10 --angles-deg 10,10,20 -o /tmp/hydrolux_mie_never.nc", "--angles-deg"},
      {"mie --m 1.333 --x 10 --angles-deg 10,10,20 -o /tmp/hydrolux_mie_never.csv", "--angles-deg"},
  };
  expect_usage_errors(cases);
  EXPECT_FALSE(fs::exists("/tmp/hydrolux_mie_never.nc"));
  EXPECT_FALSE(fs::exists("/tmp/hydrolux_mie_never.csv"));
  for (const char* text : {"0:180:1", "10,10,20", "0,90,45"}) {
    const auto r = run(std::string("mie --m 1.333 --x 10 --angles-deg ") + text);
    EXPECT_NE(r.err.find("--angles-deg '" + std::string(text) + "': "), std::string::npos) << r.err;
  }
  // What stays accepted: one angle as A:A:1, a decreasing range or list.
  for (const auto& [text, count] : {std::pair{"5:5:1", 1u}, std::pair{"180:0:3", 3u}, std::pair{"90,45,0", 3u}}) {
    const auto r = run(std::string("mie --m 1.333 --x 10 --json --angles-deg ") + text);
    ASSERT_EQ(r.code, 0) << text << r.err;
    EXPECT_EQ(nlohmann::json::parse(r.out).at("angles_deg").size(), count) << text;
  }
  // A negative imaginary part is refused with the reason, the sign convention; never conjugated.
  const auto r = run("mie --m 1.5-0.1i --x 10");
  EXPECT_NE(r.err.find("n + ik"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists("/tmp/hydrolux_mie_never.txt"));
  EXPECT_FALSE(fs::exists("/tmp/hydrolux_mie_never.npy"));
}

// Du 2004 / MIEV0 case 19 through the CLI, efficiencies only: m = 10 + 10i, x = 1e4.
TEST(Cli, MieNoAnglesAndStrongAbsorption) {
  const auto r = run("mie --m 10+10i --x 1e4 --no-angles --json");
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_FALSE(j.contains("angles_deg"));
  EXPECT_FALSE(j.contains("s1"));
  const auto q = hydrolux::scatter::mie_efficiencies({10, 10}, 1e4);
  EXPECT_EQ(j.at("qext").get<double>(), q.qext);
  EXPECT_EQ(j.at("n_terms").get<int>(), hydrolux::scatter::mie_terms(1e4));
  EXPECT_NEAR(j.at("qsca").get<double>(), 1.795393, 1e-6 * 1.795393);  // MVTstNew.f, 7 digits
}

// -o writes S1, S2 as .npy (NumPy format 1.0, float64, shape (angles, 5)), .csv or .json, each
// the same numbers as --json (shortest round-trip text, so equal to the last bit), whole, while
// stdout keeps the efficiencies.
TEST(Cli, MieOutputFiles) {
  const fs::path dir = hydrolux::testing::temp_dir("hydrolux_mie_out");
  const std::string args = "mie --m 1.5+0.01i --x 30 --angles-deg 0:180:91";
  const auto ref = nlohmann::json::parse(run(args + " --json").out);
  const auto& angles = ref.at("angles_deg");
  ASSERT_EQ(angles.size(), 91u);
  const auto expect_row = [&](std::size_t i, const double* v) {
    EXPECT_EQ(v[0], angles[i].get<double>()) << i;
    EXPECT_EQ(v[1], ref.at("s1")[i][0].get<double>()) << i;
    EXPECT_EQ(v[2], ref.at("s1")[i][1].get<double>()) << i;
    EXPECT_EQ(v[3], ref.at("s2")[i][0].get<double>()) << i;
    EXPECT_EQ(v[4], ref.at("s2")[i][1].get<double>()) << i;
  };

  auto r = run(args + " -o " + (dir / "s.npy").string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("Qext"), std::string::npos);
  EXPECT_EQ(r.out.find("Re S1"), std::string::npos);  // the table went to the file
  const std::string npy = hydrolux::testing::slurp(dir / "s.npy");
  ASSERT_GE(npy.size(), 10u);
  EXPECT_EQ(npy.substr(0, 8), std::string("\x93NUMPY\x01\x00", 8));
  const std::size_t header = 10 + (std::uint8_t(npy[8]) | (std::uint8_t(npy[9]) << 8));
  EXPECT_EQ(header % 64, 0u);
  EXPECT_NE(npy.find("'descr': '<f8', 'fortran_order': False, 'shape': (91, 5)"), std::string::npos);
  ASSERT_EQ(npy.size(), header + 91 * 5 * 8);
  for (std::size_t i = 0; i < 91; ++i) {
    double v[5];
    std::memcpy(v, npy.data() + header + i * 40, 40);  // little-endian float64 (x86-64, aarch64)
    expect_row(i, v);
  }

  r = run(args + " -o " + (dir / "s.csv").string());
  ASSERT_EQ(r.code, 0) << r.err;
  std::istringstream csv(hydrolux::testing::slurp(dir / "s.csv"));
  std::string line;
  std::getline(csv, line);
  EXPECT_EQ(line, "theta_deg,s1_re,s1_im,s2_re,s2_im");
  std::size_t rows = 0;
  while (std::getline(csv, line)) {
    double v[5];
    ASSERT_EQ(std::sscanf(line.c_str(), "%lf,%lf,%lf,%lf,%lf", &v[0], &v[1], &v[2], &v[3], &v[4]), 5);
    expect_row(rows++, v);
  }
  EXPECT_EQ(rows, 91u);

  r = run(args + " --json -o " + (dir / "s.json").string());
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = nlohmann::json::parse(hydrolux::testing::slurp(dir / "s.json"));
  EXPECT_EQ(j.at("angles_deg"), angles);
  EXPECT_EQ(j.at("s1"), ref.at("s1"));
  EXPECT_EQ(j.at("s2"), ref.at("s2"));
  const auto out = nlohmann::json::parse(r.out);
  EXPECT_EQ(out.at("output").get<std::string>(), (dir / "s.json").string());
  EXPECT_FALSE(out.contains("s1"));
  fs::remove_all(dir);
}

// --json streams: a million angles (99 MB of JSON) fit in a 256 MiB address space, where the
// document built in memory (440 MB, as before) could not. Without AddressSanitizer, whose shadow
// memory needs far more address space.
TEST(Cli, MieJsonStreamsAMillionAngles) {
#if !HYDROLUX_TEST_ASAN
  const auto r = hydrolux::testing::run_argv({"mie", "--m", "1.333", "--x", "10", "--angles-deg", "0:180:1000000", "--json"}, [] {
    const rlimit lim{std::uint64_t(256) << 20, std::uint64_t(256) << 20};
    ::setrlimit(RLIMIT_AS, &lim);
  });
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_GT(r.out.size(), 90'000'000u);
  EXPECT_EQ(r.out.rfind("{\"x\":10.0,\"m\":[1.333,0.0],\"n_terms\":27,", 0), 0u) << r.out.substr(0, 200);
  EXPECT_NE(r.out.find("\"s2\":[["), std::string::npos);
  EXPECT_EQ(r.out.substr(r.out.size() - 2), "}\n");
#endif
}

// The CLI does not load Highway's shared library, whose static initialiser calibrates a timer
// (3.5 ms of every start): hydrolux chooses the SIMD target itself. The dynamic loader lists what
// it would load (LD_TRACE_LOADED_OBJECTS, as ldd does). Release builds only: the sanitizer build
// links it for Highway's assertion handler.
TEST(CliStartup, DoesNotLoadHighwaysLibrary) {
#if !HYDROLUX_TEST_ASAN && defined(NDEBUG)
  const auto r = hydrolux::testing::run_argv({"fresnel", "--theta-deg", "30"},
                                             [] { ::setenv("LD_TRACE_LOADED_OBJECTS", "1", 1); });
  EXPECT_NE(r.out.find("libc.so"), std::string::npos) << r.out;  // the listing is there
  EXPECT_EQ(r.out.find("libhwy"), std::string::npos) << r.out;
#endif
}

// Nor, in a Release build with the fast start (HYDROLUX_FAST_START; BENCHMARKS.md "CLI start-up"),
// the shared libstdc++, fmt or oneTBB: the executable carries the first two and loads oneTBB on its
// first parallel loop. A shared library listed here costs every start its loading and relocation.
TEST(CliStartup, LoadsNoCxxLibraryAtStart) {
#if !HYDROLUX_TEST_ASAN && defined(NDEBUG) && HYDROLUX_TEST_FAST_START
  const auto r = hydrolux::testing::run_argv({"fresnel", "--theta-deg", "30"},
                                             [] { ::setenv("LD_TRACE_LOADED_OBJECTS", "1", 1); });
  ASSERT_NE(r.out.find("libc.so"), std::string::npos) << r.out;
  for (const char* lib : {"libstdc++", "libfmt", "libtbb"}) EXPECT_EQ(r.out.find(lib), std::string::npos) << lib << "\n" << r.out;
#endif
}

// phase: the same intensities as the library, as text or CSV, for every theory.
TEST(Cli, PhaseTheoriesAndCsv) {
  const auto r = run("phase --theory mie --radius-um 100 --wavelength-nm 650 --angles-deg 0:180:19 --csv");
  ASSERT_EQ(r.code, 0) << r.err;
  std::istringstream in(r.out);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "theta_deg,i1,i2,i");
  int rows = 0;
  double i1 = 0, i2 = 0, i = 0;
  while (std::getline(in, line)) {
    ++rows;
    if (rows == 1) std::sscanf(line.c_str(), "%*[^,],%lf,%lf,%lf", &i1, &i2, &i);
  }
  EXPECT_EQ(rows, 19);
  // Forward: i1 = i2 = |S(0)|^2, and the average is their mean.
  EXPECT_NEAR(i1 / i2, 1.0, 1e-9);
  EXPECT_NEAR(i, (i1 + i2) / 2, 1e-9 * i);
  for (const char* theory : {"debye:2", "airy", "geometric", "geometric:5", "debye:0"}) {
    const auto t = run(std::string("phase --theory ") + theory + " --radius-um 200 --wavelength-nm 550 --angles-deg 137:140:4");
    EXPECT_EQ(t.code, 0) << theory << t.err;
    std::size_t data = 0;  // a header and four angles, after '#' comment lines
    std::istringstream text(t.out);
    for (std::string l; std::getline(text, l);) data += !l.empty() && l[0] != '#';
    EXPECT_EQ(data, 1u + 4u) << theory;
  }
  const auto avg = run("phase --radius-um 50 --wavelength-nm 650 --size-distribution gamma:0.05 --nodes 16 "
                       "--angles-deg 140 --csv -q");
  EXPECT_EQ(avg.code, 0) << avg.err;
  EXPECT_EQ(lines(avg.out), 2u);
}

TEST(Cli, PhaseBadInput) {
  const std::pair<const char*, const char*> cases[] = {
      {"phase --theory foo --radius-um 10 --wavelength-nm 500", "--theory"},
      {"phase --theory debye:-1 --radius-um 10 --wavelength-nm 500", "--theory"},
      {"phase --theory mie --wavelength-nm 500", "--radius-um"},
      {"phase --theory mie --radius-um 10", "--wavelength-nm"},
      {"phase --radius-um 10 --wavelength-nm 500 --size-distribution gamma:2", "--size-distribution"},
      {"phase --radius-um 10 --wavelength-nm 500 --size-distribution cauchy:1", "--size-distribution"},
      {"phase --radius-um 10 --wavelength-nm 500 --nodes 0", "--nodes"},
      {"phase --radius-um 10 --wavelength-nm 2000", "--wavelength-nm"},
      {"phase --radius-um 10 --wavelength-nm 500 --angles-deg 190", "--angles-deg"},
      {"phase --radius-um 10 --wavelength-nm 500 --angles-deg 0:180:1", "N must be >= 2, or A == B"},
      {"phase --radius-um 10 --wavelength-nm 500 --angles-deg 10,10,20", "--angles-deg"},
      {"phase --radius-um 10 --wavelength-nm 500 --angles-deg 0,90,45", "--angles-deg"},
  };
  expect_usage_errors(cases);
}

// Issue 37: flags that the rest of the command would ignore are refused, in one line naming both:
// Marshall-Palmer rain sets its own radii (50-3000 um); one radius (mono) has no radii to count.
TEST(Cli, PhaseRefusesFlagsItWouldIgnore) {
  const std::pair<const char*, const char*> cases[] = {
      {"phase -q --radius-um 500 --wavelength-nm 650 --size-distribution marshall-palmer:5", "--radius-um 500: "},
      {"phase -q --radius-um 10 --wavelength-nm 500 --nodes 16", "--nodes 16: "},
      {"phase -q --radius-um 10 --wavelength-nm 500 --nodes 64", "--nodes 64: "},  // the default, given
      {"phase -q --radius-um 10 --wavelength-nm 500 --size-distribution mono --nodes 8", "--nodes 8: "},
  };
  expect_usage_errors(cases);
  const auto rain = run("phase -q --radius-um 500 --wavelength-nm 650 --size-distribution marshall-palmer:5");
  EXPECT_NE(rain.err.find("--size-distribution marshall-palmer:5 sets its own radii (50-3000 um); omit --radius-um"),
            std::string::npos)
      << rain.err;
  // The rain rate's one range (issue 38): 600 mm/h is refused, the range in the message.
  const auto heavy = run("phase -q --wavelength-nm 650 --size-distribution marshall-palmer:600 --angles-deg 140");
  EXPECT_EQ(heavy.code, 2);
  EXPECT_NE(heavy.err.find("--size-distribution"), std::string::npos) << heavy.err;
  EXPECT_NE(heavy.err.find("H = 600 is outside [0.01, 500] mm/h"), std::string::npos) << heavy.err;
  EXPECT_EQ(run("phase -q --wavelength-nm 650 --size-distribution marshall-palmer:500 --nodes 3 --angles-deg 140").code,
            0);
  const auto mono = run("phase -q --radius-um 10 --wavelength-nm 500 --nodes 16");
  EXPECT_NE(mono.err.find("--size-distribution mono is one radius"), std::string::npos) << mono.err;
  // Each alone is still fine.
  EXPECT_EQ(run("phase -q --wavelength-nm 650 --size-distribution marshall-palmer:5 --nodes 3 --angles-deg 140").code, 0);
  EXPECT_EQ(run("phase -q --radius-um 10 --wavelength-nm 500 --size-distribution gamma:0.1 --nodes 4 --angles-deg 140")
                .code,
            0);
}

// Issue 37: a table printed to a full disk is one line saying standard output could not be written,
// exit 1 (a system failure, as every other failed write), never "internal error": large tables
// fail in fmt's writes midway, small ones at the final flush.
TEST(Cli, StandardOutputThatCannotBeWrittenIsOneLine) {
  if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  for (const char* args : {"phase -q --radius-um 10 --wavelength-nm 500",
                           "phase -q --radius-um 10 --wavelength-nm 500 --csv --mueller",
                           "phase -q --radius-um 10 --wavelength-nm 500 --angles-deg 140",
                           "mie -q --m 1.333 --x 10",
                           "mie -q --m 1.333 --x 10 --json",
                           "mie -q --m 1.333 --x 10 --angles-deg 0:180:100000",
                           "lee -q --theory airy --radius-um 500 --size-spread 0 --size 1x400 --angle-deg 130:145 --wavelengths-nm "
                           "400:700:40 --json",  // 40 wavelengths: no warning of the table's error (below 1%)
                           "fresnel --theta-deg 30 --json",
                           "ior --list"}) {
    const auto r = run(std::string(args) + " >/dev/full");
    EXPECT_EQ(r.code, 1) << args << "\n" << r.err;
    EXPECT_EQ(lines(r.err), 1u) << args << "\n" << r.err;
    EXPECT_NE(r.err.find("cannot write to standard output"), std::string::npos) << args << "\n" << r.err;
    EXPECT_EQ(r.err.find("internal error"), std::string::npos) << args << "\n" << r.err;
  }
}

// Issue 37: output extensions are matched whatever their case, by every command (io::lower_extension,
// as image outputs always were): -o P.CSV, -o H.NC, -o T.EXR are written, in their formats.
TEST(Cli, OutputExtensionsAreCaseInsensitive) {
  const fs::path dir = hydrolux::testing::temp_dir("hydrolux_cli_ext");
  auto r = run("mie -q --m 1.333 --x 10 --angles-deg 0:180:3 -o " + (dir / "p.CSV").string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(hydrolux::testing::slurp(dir / "p.CSV").rfind("theta_deg,", 0), 0u);
  r = run("mie -q --m 1.333 --x 10 --angles-deg 0:180:3 -o " + (dir / "p.Nc").string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(hydrolux::testing::slurp(dir / "p.Nc").substr(1, 3), "HDF");  // NetCDF-4: an HDF5 file
  const std::string lee = "lee -q --size 2x3 --radius-um 20:400 --angle-deg 130:145 --wavelengths-nm 400:700:4 -o ";
  r = run(lee + (dir / "h.NC").string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(hydrolux::testing::slurp(dir / "h.NC").substr(1, 3), "HDF");
  r = run(lee + (dir / "t.EXR").string());
  ASSERT_EQ(r.code, 0) << r.err;
  for (const char* f : {"t.EXR", "t.png", "t.json"}) EXPECT_TRUE(fs::exists(dir / f)) << f;
  r = run("medium -q --radius-um 4 --number-per-cm3 100 --values 65 -o " + (dir / "m.XML").string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(fs::exists(dir / "m.XML"));
}

// Issue 37: the same inputs make the same bytes, also as NetCDF: no time in `history` (unless
// SOURCE_DATE_EPOCH gives one), and none from HDF5 (tests/io/test_netcdf.cpp encodes across a second).
TEST(Cli, NetcdfFilesAreTheSameBytesForTheSameInputs) {
  const fs::path dir = hydrolux::testing::temp_dir("hydrolux_cli_nc");
  const std::string args = "mie -q --radius-um 2 --wavelength-nm 550 --angles-deg 0:180:7 --mueller -o " +
                           (dir / "p.nc").string();
  ASSERT_EQ(run(args).code, 0);
  const std::string first = hydrolux::testing::slurp(dir / "p.nc");
  ::usleep(1100000);  // into another second: a clock in the file would show
  ASSERT_EQ(run(args).code, 0);
  EXPECT_EQ(hydrolux::testing::slurp(dir / "p.nc"), first);
  // history: the version and the command line, no time (the attribute's text is in the file as is).
  const std::regex stamp("[0-9]{4}-[0-9]{2}-[0-9]{2}T[0-9]{2}:[0-9]{2}:[0-9]{2}Z hydrolux");
  EXPECT_FALSE(std::regex_search(first, stamp));
  EXPECT_NE(first.find(": hydrolux mie -q --radius-um 2 --wavelength-nm 550 --angles-deg 0:180:7 --mueller -o "),
            std::string::npos);
  // A time only from SOURCE_DATE_EPOCH (reproducible builds), the same at every run.
  ::setenv("SOURCE_DATE_EPOCH", "86400", 1);
  const auto dated = run(args);
  ::unsetenv("SOURCE_DATE_EPOCH");
  ASSERT_EQ(dated.code, 0) << dated.err;
  EXPECT_NE(hydrolux::testing::slurp(dir / "p.nc").find("1970-01-02T00:00:00Z hydrolux "), std::string::npos);
}

// Issue 37: an output folder (or file) that is a dangling symbolic link is named with its flag as
// one, found before any work (it said "File exists" when the folder was created); the link is kept.
TEST(Cli, DanglingSymbolicLinkOutputsAreNamed) {
  const fs::path dir = hydrolux::testing::temp_dir("hydrolux_cli_dangling");
  const fs::path in = dir / "in", out = dir / "out";
  fs::create_directories(in);
  hydrolux::testing::builtin_frame(in / "f.png", "16x16");
  fs::create_directory_symlink(dir / "nowhere", out);
  fs::create_symlink(dir / "nowhere.nc", dir / "p.nc");
  const std::string folder = " --input-dir " + in.string() + " --output-dir " + out.string();
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"fog -q --visibility-m 300" + folder, "--output-dir " + out.string() + ": is a dangling symbolic link"},
      {"rain -q --rain-rate-mmh 5" + folder, "--output-dir " + out.string() + ": is a dangling symbolic link"},
      {"fog -q --visibility-m 300 --input-dir " + in.string() + " --output-dir " + (dir / "o2").string() +
           " --mask-dir " + out.string(),
       "--mask-dir " + out.string() + ": is a dangling symbolic link"},
      {"gallery -q -o " + out.string(), "-o " + out.string() + ": is a dangling symbolic link"},
      {"mie -q --m 1.333 --x 10 -o " + (dir / "p.nc").string(), "is a dangling symbolic link"},
  };
  expect_usage_errors(cases);
  for (const auto& [args, text] : cases) EXPECT_EQ(run(args).err.find("File exists"), std::string::npos) << args;
  EXPECT_TRUE(fs::is_symlink(out));
  EXPECT_FALSE(fs::exists(dir / "nowhere"));
  EXPECT_FALSE(fs::exists(dir / "nowhere.nc"));
  EXPECT_FALSE(fs::exists(dir / "o2"));
}

// drop profile: Garg & Nayar's Figure 4 as JSON.
TEST(Cli, DropProfileJsonContract) {
  const auto r = run("drop profile --mu 1.333 --samples 11 --json");
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  for (const char* key : {"rho", "refraction", "reflection", "internal1", "internal2"}) {
    ASSERT_TRUE(j.contains(key)) << key;
    EXPECT_EQ(j.at(key).size(), 11u) << key;
  }
  EXPECT_NEAR(j.at("fov_deg").get<double>(), 165.6, 0.1);  // the paper: about 165 degrees
  EXPECT_EQ(j.at("rho")[10].get<double>(), 1.0);
  const std::pair<const char*, const char*> bad[] = {{"drop profile --mu 0.5", "--mu"},
                                                     {"drop profile --samples 1", "--samples"},
                                                     {"drop profile --mu abc", "--mu"}};
  expect_usage_errors(bad);
}

// The whole gallery through the CLI is rendered once in the suite, by tests/gallery/test_gallery.cpp
// (which checks every figure); here, what the CLI refuses.
TEST(Cli, GalleryRefusesAFileAsItsDirectory) {
  const fs::path dir = fs::temp_directory_path() / "hydrolux_cli_gallery";
  fs::remove_all(dir);
  // An output path that is a file: exit 2, one line, the file untouched.
  const fs::path file = fs::temp_directory_path() / "hydrolux_cli_gallery_file";
  std::ofstream(file) << "keep";
  const auto bad = run("gallery -q -o " + file.string());
  EXPECT_EQ(bad.code, 2);
  EXPECT_EQ(lines(bad.err), 1u) << bad.err;
  std::ifstream in(file);
  std::string s;
  in >> s;
  EXPECT_EQ(s, "keep");
  fs::remove(file);
  fs::remove_all(dir);
}

}  // namespace
