// docs/reference.md is current: the tables generated from the CLI's registration and the declared
// parameters (tools/hydrolux/reference.cpp) equal the file in the repository. `make reference`
// (HYDROLUX_WRITE_REFERENCE=1) writes it anew.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>

#include "common.hpp"
#include "hydrolux/core/params.hpp"
#include "hydrolux/io/files.hpp"
#include "params.hpp"
#include "support/cli.hpp"

namespace {

TEST(Reference, DocsReferenceIsCurrent) {
  CLI::App app;
  const auto commands = hydrolux::cli::add_all_commands(app);
  const std::string generated = hydrolux::cli::reference_markdown(commands);
  const auto path = std::filesystem::path(HYDROLUX_SOURCE_DIR) / "docs" / "reference.md";
  if (const char* w = std::getenv("HYDROLUX_WRITE_REFERENCE"); w && std::string(w) == "1") {
    hydrolux::io::write_file(path, generated, "docs/reference.md");  // checked and atomic (files.hpp)
    GTEST_SKIP() << "wrote " << path;
  }
  EXPECT_EQ(hydrolux::testing::slurp(path), generated)
      << path << " is not current: run `make reference` and commit it";
}

// A parameter's deprecated name (Param::deprecated, kept for one release): its old flag still sets it,
// through the same range check, with one warning naming the new flag; it is hidden from --help and
// from the reference, and giving both spellings is refused.
TEST(Reference, DeprecatedFlagWorksWithOneWarningAndIsHidden) {
  static const hydrolux::Param p{"rain_rate_mmh", "--rain-rate-mmh", "rain", hydrolux::ParamKind::real, "mm/h", 0, 500,
                                 "Rain rate", {}, {}, {}, {}, "rate_mmh"};
  const hydrolux::ParamInfo info{&p, 25};
  double got = -1;
  CLI::App app;
  hydrolux::cli::add_param(app, info, [&](const hydrolux::ParamValue& v) { got = v[0]; });
  ::testing::internal::CaptureStderr();
  app.parse("--rate-mmh 7", false);
  const std::string err = ::testing::internal::GetCapturedStderr();
  EXPECT_EQ(got, 7);
  EXPECT_NE(err.find("--rate-mmh is deprecated"), std::string::npos) << err;
  EXPECT_NE(err.find("give --rain-rate-mmh"), std::string::npos) << err;
  EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
  EXPECT_TRUE(hydrolux::cli::given(app, p));
  EXPECT_EQ(app.help().find("--rate-mmh"), std::string::npos) << app.help();

  CLI::App out_of_range;
  hydrolux::cli::add_param(out_of_range, info, [](const hydrolux::ParamValue&) {});
  EXPECT_THROW(out_of_range.parse("--rate-mmh 600", false), CLI::ValidationError);
  // Both spellings: refused, naming both (and no warning for a value that is not taken).
  for (const char* args : {"--rate-mmh 1 --rain-rate-mmh 2", "--rain-rate-mmh 2 --rate-mmh 1"}) {
    CLI::App both;
    hydrolux::cli::add_param(both, info, [](const hydrolux::ParamValue&) {});
    ::testing::internal::CaptureStderr();
    try {
      both.parse(args, false);
      ADD_FAILURE() << args << ": accepted";
    } catch (const CLI::ValidationError& e) {
      EXPECT_STREQ(e.what(), "--rate-mmh: give --rain-rate-mmh or --rate-mmh (its deprecated name), not both");
    }
    EXPECT_EQ(::testing::internal::GetCapturedStderr(), "") << args;
  }
}

}  // namespace
