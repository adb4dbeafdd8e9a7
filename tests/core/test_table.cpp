#include <gtest/gtest.h>

#include "hydrolux/core/embedded_data.hpp"
#include "hydrolux/core/error.hpp"
#include "hydrolux/core/table.hpp"

namespace hydrolux {
namespace {

TEST(Table, ParsesMetadataHeaderAndRows) {
  const auto t = parse_table("# source: A. Author (1999)\n# notes: first\n# notes: second\n"
                             "x,y\n1,2.5\n2, 3e-1\n\n3,4E+00\n",
                             "test");
  EXPECT_EQ(t.meta_or_empty("source"), "A. Author (1999)");
  EXPECT_EQ(t.meta_or_empty("notes"), "first second");
  EXPECT_EQ(t.meta_or_empty("absent"), "");
  ASSERT_EQ(t.rows(), 3u);
  EXPECT_DOUBLE_EQ(t.column("y")[1], 0.3);
  EXPECT_DOUBLE_EQ(t.column("y")[2], 4.0);
  EXPECT_THROW((void)t.column("z"), IoError);
}

TEST(Table, RejectsMalformedInput) {
  EXPECT_THROW(parse_table("x,y\n1\n", "t"), IoError);
  EXPECT_THROW(parse_table("x,y\n1,abc\n", "t"), IoError);
  EXPECT_THROW(parse_table("# only a comment\n", "t"), IoError);
  EXPECT_THROW(parse_table("x,y\n", "t"), IoError);
}

TEST(Table, LinearInterpolation) {
  const std::vector<double> x{1, 2, 4}, y{10, 20, 0};
  EXPECT_DOUBLE_EQ(interpolate_linear(x, y, 1.0), 10.0);
  EXPECT_DOUBLE_EQ(interpolate_linear(x, y, 1.5), 15.0);
  EXPECT_DOUBLE_EQ(interpolate_linear(x, y, 3.0), 10.0);
  EXPECT_DOUBLE_EQ(interpolate_linear(x, y, 4.0), 0.0);
}

TEST(EmbeddedData, KnownAndUnknownFiles) {
  EXPECT_FALSE(embedded_file("media/gold_johnson_christy_1972.csv").empty());
  EXPECT_THROW((void)embedded_file("media/nothing.csv"), IoError);
}

}  // namespace
}  // namespace hydrolux
