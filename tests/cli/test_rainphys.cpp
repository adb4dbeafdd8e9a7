// hydrolux rainphys end to end: the JSON contract (keys, order, values against the library), the
// text form, the null Gunn & Kinzer velocity outside their measurements, and bad input.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "hydrolux/drop/physics.hpp"
#include "hydrolux/scatter/drop_shape.hpp"
#include "hydrolux/scatter/size_distribution.hpp"
#include "support/cli.hpp"

namespace {

using hydrolux::testing::expect_usage_errors;
using hydrolux::testing::run;

// Defaults (a = 1 mm, h = 30 mm/h): the five keys of the issue first and in order, then the rest;
// every value as the library computes it. The paper's numbers: v = 200 sqrt(1e-3) = 6.3246 m/s;
// N(a) = 8e6 exp(-8200 30^-0.21 1e-3) = 1.444e5 m^-4; n = N0 / Lambda = 1993 m^-3, spacing 7.95 cm.
TEST(Rainphys, JsonContract) {
  const auto r = run("rainphys --json");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(r.err.empty()) << r.err;
  const auto j = nlohmann::ordered_json::parse(r.out);
  const std::vector<std::string> first = {"terminal_velocity_mps", "terminal_velocity_gunn_kinzer_mps",
                                          "density_per_m4", "shape_coefficients", "axis_ratio"};
  std::vector<std::string> keys;
  for (const auto& [k, v] : j.items()) keys.push_back(k);
  ASSERT_GE(keys.size(), first.size());
  EXPECT_EQ(std::vector<std::string>(keys.begin(), keys.begin() + 5), first);
  for (const char* k : {"c0", "radius_mm", "rain_rate_mmh", "number_density_per_m3", "mean_spacing_m", "notes"})
    EXPECT_TRUE(j.contains(k)) << k;

  using namespace hydrolux;
  const double a = 1e-3;
  EXPECT_NEAR(j.at("terminal_velocity_mps").get<double>(), 6.3246, 1e-4);
  EXPECT_DOUBLE_EQ(j.at("terminal_velocity_mps").get<double>(), 200 * std::sqrt(a));
  EXPECT_DOUBLE_EQ(j.at("terminal_velocity_gunn_kinzer_mps").get<double>(), 6.49);
  const double density = 8e6 * std::exp(-8200 * std::pow(30.0, -0.21) * a);
  EXPECT_NEAR(j.at("density_per_m4").get<double>(), density, 1e-12 * density);
  EXPECT_NEAR(density, 1.4443e5, 1e1);
  const auto mp = scatter::SizeDistribution::marshall_palmer(30);
  EXPECT_DOUBLE_EQ(j.at("density_per_m4").get<double>(), mp.number_density(a));
  const auto shape = scatter::drop_shape(a);
  ASSERT_EQ(j.at("shape_coefficients").size(), 10u);
  for (int n = 1; n <= 10; ++n) EXPECT_EQ(j.at("shape_coefficients")[n - 1].get<double>(), shape.c[n]) << n;
  EXPECT_EQ(j.at("shape_coefficients")[1].get<double>(), -0.0385);  // c2 at a = 1 mm, paper convention
  EXPECT_EQ(j.at("shape_coefficients")[0].get<double>(), -0.0118);  // c1: odd, negative with theta = 0 down
  EXPECT_EQ(j.at("c0").get<double>(), -0.0134);
  EXPECT_DOUBLE_EQ(j.at("axis_ratio").get<double>(), scatter::axis_ratio(shape));
  EXPECT_NEAR(j.at("axis_ratio").get<double>(), 0.9259, 1e-4);
  EXPECT_EQ(j.at("radius_mm").get<double>(), 1.0);
  EXPECT_EQ(j.at("rain_rate_mmh").get<double>(), 30.0);
  const double n = 8e6 / (8200 * std::pow(30.0, -0.21));
  EXPECT_NEAR(j.at("number_density_per_m3").get<double>(), n, 1e-12 * n);
  EXPECT_DOUBLE_EQ(j.at("number_density_per_m3").get<double>(), mp.moment(0));
  EXPECT_NEAR(j.at("mean_spacing_m").get<double>(), std::cbrt(1 / n), 1e-15);
  EXPECT_NEAR(j.at("mean_spacing_m").get<double>(), 0.0795, 1e-4);
  EXPECT_TRUE(j.at("notes").is_array());
  EXPECT_TRUE(j.at("notes").empty());
}

// Gunn & Kinzer measured radii up to 2.9 mm: there the value, beyond it null with a note, and a
// note where the fit no longer holds (above 2.5 mm). Other flags pass through.
TEST(Rainphys, GunnKinzerRangeAndNotes) {
  const auto edge = nlohmann::json::parse(run("rainphys --radius-mm 2.9 --json").out);
  EXPECT_DOUBLE_EQ(edge.at("terminal_velocity_gunn_kinzer_mps").get<double>(), 9.17);
  const auto r = run("rainphys --radius-mm 3.5 --rain-rate-mmh 5 --json");
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_TRUE(j.at("terminal_velocity_gunn_kinzer_mps").is_null());
  EXPECT_DOUBLE_EQ(j.at("terminal_velocity_mps").get<double>(), 200 * std::sqrt(3.5e-3));
  bool gk_note = false, fit_note = false;
  for (const auto& note : j.at("notes")) {
    const auto s = note.get<std::string>();
    gk_note |= s.find("terminal_velocity_gunn_kinzer_mps") == 0 && s.find("2.9 mm") != std::string::npos;
    fit_note |= s.find("terminal_velocity_mps") == 0;
  }
  EXPECT_TRUE(gk_note) << j.at("notes");
  EXPECT_TRUE(fit_note) << j.at("notes");
  EXPECT_EQ(j.at("rain_rate_mmh").get<double>(), 5.0);
  EXPECT_DOUBLE_EQ(j.at("density_per_m4").get<double>(),
                   hydrolux::scatter::SizeDistribution::marshall_palmer(5).number_density(3.5e-3));
  EXPECT_DOUBLE_EQ(j.at("axis_ratio").get<double>(), hydrolux::scatter::axis_ratio(hydrolux::scatter::drop_shape(3.5e-3)));
  // The table's ends are accepted.
  EXPECT_EQ(run("rainphys --radius-mm 0.5 --json").code, 0);
  // The rain rate's one upper limit, the rain's and the sky's (kMaxRainRateMmh).
  EXPECT_EQ(run("rainphys --radius-mm 4.5 --rain-rate-mmh 500 --json").code, 0);
}

// The text form: the same numbers with units; the help states the density convention.
TEST(Rainphys, TextAndHelp) {
  const auto r = run("rainphys");
  ASSERT_EQ(r.code, 0) << r.err;
  for (const char* s : {"6.3246 m/s", "6.4900 m/s", "m^-4", "m^-3", "0.9259", "mm/h"})
    EXPECT_NE(r.out.find(s), std::string::npos) << s << "\n" << r.out;
  const auto far = run("rainphys --radius-mm 4");
  EXPECT_EQ(far.code, 0);
  EXPECT_NE(far.out.find("outside their measurements"), std::string::npos) << far.out;
  const auto h = run("rainphys --help");
  EXPECT_EQ(h.code, 0);
  EXPECT_NE(h.out.find("DIAMETER"), std::string::npos);
  EXPECT_NE(h.out.find("twice"), std::string::npos);
  EXPECT_NE(h.out.find("mm/h"), std::string::npos);
}

TEST(Rainphys, BadInputIsOneLineAndExitCodeTwo) {
  const std::pair<const char*, const char*> cases[] = {
      {"rainphys --radius-mm 0", "--radius-mm"},
      {"rainphys --radius-mm 5", "--radius-mm"},
      {"rainphys --radius-mm -1", "--radius-mm"},
      {"rainphys --radius-mm abc", "--radius-mm"},
      {"rainphys --radius-mm nan", "--radius-mm"},
      {"rainphys --radius-mm 0.49", "--radius-mm"},
      {"rainphys --rain-rate-mmh 0", "--rain-rate-mmh"},
      {"rainphys --rain-rate-mmh -3", "--rain-rate-mmh"},
      {"rainphys --rain-rate-mmh 501", "--rain-rate-mmh"},
      {"rainphys --rain-rate-mmh x", "--rain-rate-mmh"},
      {"rainphys --bogus 1", "--bogus"},
  };
  expect_usage_errors(cases);
  // The value and the valid range are in the message.
  const auto r = run("rainphys --radius-mm 5");
  EXPECT_NE(r.err.find("[0.5, 4.5] mm"), std::string::npos) << r.err;
  EXPECT_NE(run("rainphys --rain-rate-mmh 0").err.find("[0.01, 500] mm/h"), std::string::npos);
}

}  // namespace
