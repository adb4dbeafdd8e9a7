// End-to-end tests of the hydrolux command line: the contract of issue #2 (flags, JSON fields,
// exit codes, one-line errors) as a user or script sees it.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "hydrolux/optics/fresnel.hpp"
#include "hydrolux/optics/media.hpp"

namespace {

namespace fs = std::filesystem;

struct Result {
  int code = -1;
  std::string out, err;
};

Result run(const std::string& args) {
  const fs::path err_file = fs::temp_directory_path() / ("hydrolux_cli_err_" + std::to_string(::getpid()));
  const std::string cmd = std::string(HYDROLUX_CLI_PATH) + " " + args + " 2>" + err_file.string();
  Result r;
  FILE* pipe = ::popen(cmd.c_str(), "r");
  if (!pipe) return r;
  std::array<char, 4096> buf{};
  std::size_t n;
  while ((n = std::fread(buf.data(), 1, buf.size(), pipe)) > 0) r.out.append(buf.data(), n);
  const int status = ::pclose(pipe);
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  std::ifstream in(err_file);
  std::stringstream ss;
  ss << in.rdbuf();
  r.err = ss.str();
  fs::remove(err_file);
  return r;
}

std::size_t lines(const std::string& s) { return std::size_t(std::count(s.begin(), s.end(), '\n')); }

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
  for (const auto& [args, flag] : cases) {
    const auto r = run(args);
    EXPECT_EQ(r.code, 2) << args;
    EXPECT_EQ(lines(r.err), 1u) << args << "\n" << r.err;
    EXPECT_NE(r.err.find(flag), std::string::npos) << args << "\n" << r.err;
    EXPECT_TRUE(r.out.empty()) << args;
  }
  // The value and the valid range are in the message.
  const auto r = run("ior --medium water --wavelength-nm 100");
  EXPECT_NE(r.err.find("100"), std::string::npos);
  EXPECT_NE(r.err.find("[200, 1100] nm"), std::string::npos) << r.err;
  EXPECT_NE(run("fresnel --theta-deg 100").err.find("[0, 90] deg"), std::string::npos);
}

TEST(Cli, GalleryWritesIndexAndFigures) {
  const fs::path dir = fs::temp_directory_path() / "hydrolux_cli_gallery";
  fs::remove_all(dir);
  const auto r = run("gallery -q -o " + dir.string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(fs::exists(dir / "index.html"));
  EXPECT_TRUE(fs::exists(dir / "fresnel_air_gold.svg"));
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
