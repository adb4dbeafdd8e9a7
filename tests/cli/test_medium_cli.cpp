// hydrolux medium end to end (issue 28): a Mitsuba 3 file that an XML parser reads (python3's
// xml.etree, where python3 is installed) with the medium, the spectra and the table the library
// computes; a pbrt-v4 file with its statement; the format from the extension or --format; the same
// bytes twice; and bad input refused in one line with nothing written.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "hydrolux/optics/media.hpp"
#include "hydrolux/scatter/renderer_export.hpp"
#include "support/cli.hpp"

namespace {

namespace fs = std::filesystem;
using hydrolux::testing::run;
using hydrolux::testing::slurp;
using namespace hydrolux;

fs::path dir() {
  static const fs::path d = hydrolux::testing::temp_dir("hydrolux_medium_cli");
  return d;
}

const std::string kFog = "--radius-um 4 --size-distribution gamma:0.2 --number-per-cm3 100 --nodes 16 --values 1025";

// The file is the library's text for the same job, byte for byte; it parses as XML, its root is the
// homogeneous medium, and the table has the values asked for.
TEST(MediumCli, MitsubaFileIsTheLibrarysAndParses) {
  const fs::path out = dir() / "fog.xml";
  const auto r = run("medium -q " + kFog + " --name fog -o " + out.string());
  ASSERT_EQ(r.code, 0) << r.err;
  // -q: no progress; 16 radii are too few for 4 um drops' Mie ripple, which one warning line says, and
  // their average is more than half of --max-error from 32 radii, which a second one says.
  EXPECT_EQ(r.err.rfind("hydrolux medium: warning: 16 radii over size parameters", 0), 0u) << r.err;
  EXPECT_NE(r.err.find("give --nodes "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("\nhydrolux medium: warning: the size average over 16 radii is itself"), std::string::npos)
      << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 2) << r.err;
  EXPECT_TRUE(r.out.empty());
  scatter::MediumJob job;
  job.radius_um = 4;
  job.size_distribution = "gamma:0.2";
  job.medium = optics::find_medium("water");
  job.surrounding = optics::find_medium("air");
  job.numbers.number_per_cm3 = 100;
  job.numbers.nodes = 16;
  job.numbers.values = 1025;
  const std::string want = scatter::mitsuba3_medium_xml(scatter::run_medium_job(job), "fog");
  EXPECT_EQ(slurp(out), want);
  // Well-formed XML with the expected structure (python3 where the machine has it).
  if (std::system("python3 -c 'import xml.etree.ElementTree' >/dev/null 2>&1") == 0) {
    const std::string check =
        "python3 -c \"import sys, xml.etree.ElementTree as E; r = E.parse(sys.argv[1]).getroot(); "
        "assert r.tag == 'medium' and r.get('type') == 'homogeneous' and r.get('id') == 'fog' and "
        "r.get('version') == '3.0.0'; p = r.find('phase'); assert p.get('type') == 'tabphase'; "
        "v = [float(x) for x in p.find('string').get('value').split(',')]; assert len(v) == 1025; "
        "assert {s.get('name') for s in r.findall('spectrum')} == {'sigma_t', 'albedo'}; "
        "assert r.find('float').get('name') == 'scale'\" " +
        out.string();
    EXPECT_EQ(std::system(check.c_str()), 0);
  }
  // The same bytes again.
  const fs::path again = dir() / "fog2.xml";
  ASSERT_EQ(run("medium -q " + kFog + " --name fog -o " + again.string()).code, 0);
  EXPECT_EQ(slurp(again), slurp(out));
}

TEST(MediumCli, PbrtFileAndFormats) {
  const fs::path out = dir() / "fog.pbrt";
  auto r = run("medium " + kFog + " --scene-unit-m 0.01 -o " + out.string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("Henyey-Greenstein g"), std::string::npos) << r.err;  // the summary on stderr
  const std::string text = slurp(out);
  EXPECT_NE(text.find("MakeNamedMedium \"hydrolux_medium\"\n    \"string type\" \"homogeneous\"\n"), std::string::npos);
  EXPECT_NE(text.find("\"float scale\" 0.01\n"), std::string::npos);
  EXPECT_NE(text.find("# error of Henyey-Greenstein against hydrolux's phase"), std::string::npos);
  // --format agreeing with the extension is accepted.
  r = run("medium -q " + kFog + " --format pbrt-v4 -o " + (dir() / "f2.pbrt").string());
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_NE(slurp(dir() / "f2.pbrt").find("\"float scale\" 1\n"), std::string::npos);
}

// Rain takes its count from its rate; fog needs one.
TEST(MediumCli, BadInputIsOneLineAndNothingWritten) {
  const std::string o = " -o " + (dir() / "bad.xml").string();
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"medium -q --radius-um 10 --size-distribution gamma:0.2" + o, "--number-per-cm3"},
      {"medium -q --size-distribution marshall-palmer:5 --number-per-cm3 10" + o, "--number-per-cm3"},
      {"medium -q --size-distribution marshall-palmer:5 --lwc-g-m3 0.1" + o, "--lwc-g-m3"},
      {"medium -q --radius-um 10 --number-per-cm3 10 --lwc-g-m3 0.1" + o, "--number-per-cm3"},
      {"medium -q --size-distribution gamma:0.2 --number-per-cm3 10" + o, "--radius-um"},
      {"medium -q --radius-um 10 --size-distribution gamma:9 --number-per-cm3 10" + o, "--size-distribution"},
      {"medium -q --radius-um 10 --number-per-cm3 10 --phase-wavelength-nm 900" + o, "--phase-wavelength-nm"},
      {"medium -q --radius-um 10 --number-per-cm3 10 --values 2" + o, "--values"},
      {"medium -q --radius-um 10 --number-per-cm3 10 --forward-cut-deg 91" + o, "--forward-cut-deg"},
      {"medium -q --radius-um 10 --number-per-cm3 10 --max-error 0" + o, "--max-error"},
      {"medium -q --radius-um 10 --number-per-cm3 10 --scene-unit-m 0" + o, "--scene-unit-m"},
      {"medium -q --radius-um 10 --number-per-cm3 10 --format blender" + o, "--format"},
      {"medium -q --radius-um 10 --number-per-cm3 10 --format pbrt-v4" + o, "--format"},
      {"medium -q --radius-um 10 --number-per-cm3 10 --name 'a b'" + o, "--name"},
      {"medium -q --radius-um 10 --number-per-cm3 10 --medium pmma" + o, "--medium"},
      {"medium -q --radius-um 10 --number-per-cm3 10 -o " + (dir() / "bad.txt").string(), "-o"},
      {"medium -q --radius-um 10 --number-per-cm3 10 -o " + (dir() / "missing" / "bad.xml").string(), "-o"},
  };
  hydrolux::testing::expect_usage_errors(cases);
  EXPECT_FALSE(fs::exists(dir() / "bad.xml"));
  EXPECT_FALSE(fs::exists(dir() / "bad.txt"));
}

// Issue 37: a flag the rest of the command would ignore is refused in one line naming both flags:
// a radius for Marshall-Palmer rain (its own radii), a count of radii for one radius (mono).
TEST(MediumCli, FlagsThatWouldBeIgnoredAreRefused) {
  const std::string o = " -o " + (dir() / "ignored.xml").string();
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"medium -q --radius-um 500 --size-distribution marshall-palmer:5" + o, "--radius-um 500: "},
      {"medium -q --radius-um 10 --number-per-cm3 10 --nodes 16" + o, "--nodes 16: "},
      {"medium -q --radius-um 10 --number-per-cm3 10 --nodes 64" + o, "--nodes 64: "},  // the default, given
      {"medium -q --radius-um 10 --size-distribution mono --number-per-cm3 10 --nodes 4" + o, "--nodes 4: "},
  };
  hydrolux::testing::expect_usage_errors(cases);
  EXPECT_FALSE(fs::exists(dir() / "ignored.xml"));
  const auto rain = run("medium -q --radius-um 500 --size-distribution marshall-palmer:5" + o);
  EXPECT_NE(rain.err.find("--size-distribution marshall-palmer:5 sets its own radii (50-3000 um); omit --radius-um"),
            std::string::npos)
      << rain.err;
  const auto mono = run("medium -q --radius-um 10 --number-per-cm3 10 --nodes 16" + o);
  EXPECT_NE(mono.err.find("--size-distribution mono is one radius"), std::string::npos) << mono.err;
}

}  // namespace
