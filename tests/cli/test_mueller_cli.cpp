// hydrolux mie --mueller and hydrolux phase --mueller: the Mueller matrix elements S11, S12, S33,
// S34 (Bohren & Huffman eq. 4.77, scatter/mueller.hpp) as extra fields and columns, and the
// outputs without the flag as they were (the same fields, columns and header lines).
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "hydrolux/scatter/mueller.hpp"
#include "support/cli.hpp"

namespace {

using hydrolux::testing::run;
namespace fs = std::filesystem;

std::vector<std::string> split_lines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string l; std::getline(in, l);) out.push_back(l);
  return out;
}

std::complex<double> pair_value(const nlohmann::ordered_json& j) { return {j[0].get<double>(), j[1].get<double>()}; }

TEST(CliMueller, MieJsonFields) {
  const std::string args = "mie --m 1.5+0.01i --x 30 --angles-deg 0:180:37 --json";
  const auto plain = run(args);
  ASSERT_EQ(plain.code, 0) << plain.err;
  const auto p = nlohmann::ordered_json::parse(plain.out);  // in the printed order
  std::vector<std::string> keys;
  for (const auto& item : p.items()) keys.push_back(item.key());
  EXPECT_EQ(keys, (std::vector<std::string>{"x", "m", "n_terms", "qext", "qsca", "qabs", "qback", "g", "angles_deg",
                                            "s1", "s2", "compute_s"}));

  const auto r = run(args + " --mueller");
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = nlohmann::ordered_json::parse(r.out);
  EXPECT_EQ(j.at("s1"), p.at("s1"));
  EXPECT_EQ(j.at("s2"), p.at("s2"));
  for (const char* k : {"s11", "s12", "s33", "s34"}) ASSERT_EQ(j.at(k).size(), 37u) << k;
  // The elements of the printed amplitudes (shortest round-trip numbers, so the same doubles),
  // to the rounding of a product.
  for (std::size_t i = 0; i < 37; ++i) {
    const auto e = hydrolux::scatter::mueller_element(pair_value(j["s1"][i]), pair_value(j["s2"][i]));
    const double tol = 1e-15 * e.s11;
    EXPECT_NEAR(j["s11"][i].get<double>(), e.s11, tol) << i;
    EXPECT_NEAR(j["s12"][i].get<double>(), e.s12, tol) << i;
    EXPECT_NEAR(j["s33"][i].get<double>(), e.s33, tol) << i;
    EXPECT_NEAR(j["s34"][i].get<double>(), e.s34, tol) << i;
  }
  // Forward: S1 = S2, so S11 = S33 and S12 = S34 = 0.
  EXPECT_EQ(j["s12"][0].get<double>(), 0.0);
  EXPECT_EQ(j["s34"][0].get<double>(), 0.0);
}

TEST(CliMueller, MieTableAndFiles) {
  const std::string args = "mie -q --m 1.33 --x 10 --angles-deg 0:180:7";
  const auto plain = split_lines(run(args).out);
  const auto with = split_lines(run(args + " --mueller").out);
  ASSERT_EQ(plain.size(), with.size());
  ASSERT_EQ(plain.size(), 2u + 1u + 7u);  // two summary lines, the header, seven angles
  for (std::size_t i = 2; i < plain.size(); ++i) {  // the same columns first, four more after
    EXPECT_EQ(with[i].substr(0, plain[i].size()), plain[i]) << i;
    EXPECT_GT(with[i].size(), plain[i].size() + 4 * 17) << i;
  }
  EXPECT_NE(with[2].find("S34"), std::string::npos);
  EXPECT_EQ(plain[2].find("S11"), std::string::npos);

  const fs::path dir = hydrolux::testing::temp_dir("hydrolux_mueller_out");
  auto r = run(args + " --mueller -o " + (dir / "m.csv").string());
  ASSERT_EQ(r.code, 0) << r.err;
  const auto csv = split_lines(hydrolux::testing::slurp(dir / "m.csv"));
  ASSERT_EQ(csv.size(), 8u);
  EXPECT_EQ(csv[0], "theta_deg,s1_re,s1_im,s2_re,s2_im,s11,s12,s33,s34");
  for (std::size_t i = 1; i < csv.size(); ++i) {
    double v[9];
    ASSERT_EQ(std::sscanf(csv[i].c_str(), "%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf", &v[0], &v[1], &v[2], &v[3], &v[4],
                          &v[5], &v[6], &v[7], &v[8]),
              9);
    // One sphere: a pure Mueller matrix, S11^2 = S12^2 + S33^2 + S34^2 (B&H eq. 4.78), to rounding.
    EXPECT_NEAR(v[5] * v[5], v[6] * v[6] + v[7] * v[7] + v[8] * v[8], 1e-13 * v[5] * v[5]) << i;
  }
  r = run(args + " --mueller -o " + (dir / "m.npy").string());
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string npy = hydrolux::testing::slurp(dir / "m.npy");
  EXPECT_NE(npy.find("'shape': (7, 9)"), std::string::npos);
  r = run(args + " -o " + (dir / "p.npy").string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(hydrolux::testing::slurp(dir / "p.npy").find("'shape': (7, 5)"), std::string::npos);
  fs::remove_all(dir);

  // Without amplitudes there are no elements.
  const auto bad = run("mie --m 1.33 --x 10 --no-angles --mueller");
  EXPECT_EQ(bad.code, 2);
  EXPECT_NE(bad.err.find("--mueller"), std::string::npos);
}

TEST(CliMueller, PhaseColumns) {
  const std::string args =
      "phase -q --radius-um 20 --wavelength-nm 550 --size-distribution gamma:0.1 --nodes 8 --angles-deg 0:180:13";
  const auto plain = split_lines(run(args + " --csv").out);
  const auto with = split_lines(run(args + " --csv --mueller").out);
  ASSERT_EQ(plain.size(), 14u);
  ASSERT_EQ(with.size(), 14u);
  EXPECT_EQ(plain[0], "theta_deg,i1,i2,i");
  EXPECT_EQ(with[0], "theta_deg,i1,i2,i,s11,s12,s33,s34");
  for (std::size_t k = 1; k < plain.size(); ++k) {
    ASSERT_EQ(with[k].substr(0, plain[k].size() + 1), plain[k] + ",") << k;
    double v[8];
    ASSERT_EQ(std::sscanf(with[k].c_str(), "%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf", &v[0], &v[1], &v[2], &v[3], &v[4], &v[5],
                          &v[6], &v[7]),
              8);
    // S11 is the unpolarised i; S12 = (i2 - i1) / 2, to the 11 printed digits; an average over
    // sizes is partly depolarised, S11 >= sqrt(S12^2 + S33^2 + S34^2).
    EXPECT_EQ(v[4], v[3]) << k;
    EXPECT_NEAR(v[5], (v[2] - v[1]) / 2, 1e-10 * v[4]) << k;
    EXPECT_LE(std::sqrt(v[5] * v[5] + v[6] * v[6] + v[7] * v[7]), v[4] * (1 + 1e-9)) << k;
  }
  const auto text = split_lines(run(args + " --mueller").out);
  const auto text_plain = split_lines(run(args).out);
  EXPECT_EQ(text.size(), text_plain.size() + 1);  // one comment line on the elements
  EXPECT_NE(text.back().size(), text_plain.back().size());
}

}  // namespace
