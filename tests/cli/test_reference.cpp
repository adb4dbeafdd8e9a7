// docs/reference.md is current: the tables generated from the CLI's registration and the declared
// parameters (tools/hydrolux/reference.cpp) equal the file in the repository. `make reference`
// (HYDROLUX_WRITE_REFERENCE=1) writes it anew.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>

#include "common.hpp"
#include "hydrolux/io/files.hpp"
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

}  // namespace
