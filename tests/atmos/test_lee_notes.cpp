// What a Lee table cannot resolve is said (atmos::lee_resolution_notes, issue 39): the supernumeraries'
// spacing the notes use against an exact wave computation (the Debye series' order 2 and 3, no Airy
// approximation), and the notes themselves: none for the defaults, each case named with the parameters
// that fix it, and gone once they are given as the note says.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "support/asan.hpp"
#include "hydrolux/atmos/lee.hpp"
#include "hydrolux/core/math.hpp"
#include "hydrolux/scatter/geometric.hpp"
#include "hydrolux/scatter/theories.hpp"

namespace hydrolux::atmos {
namespace {

// The angles (deg) of the local maxima of the Debye order-p intensity inside the bow (on its lit
// side), nearest the bow first: a fine scan (1e-3 deg) of (|S1|^2 + |S2|^2) / 2.
std::vector<double> debye_maxima_deg(double n, double x, int p, int count) {
  const double bow = rad_to_deg(scatter::rainbow_angle(n, p));
  // The lit side: towards the antisolar point (larger scattering angles) for the primary, away for the secondary.
  const double dir = p == 2 ? 1 : -1;
  std::vector<double> theta;
  for (double d = -0.3; d < 6; d += 1e-3) theta.push_back(deg_to_rad(bow + dir * d));
  std::vector<scatter::Complex> s1(theta.size()), s2(theta.size());
  scatter::amplitudes(scatter::Theory{scatter::TheoryKind::Debye, p}, {n, 0}, x, theta, s1, s2, 1);
  std::vector<double> i(theta.size());
  for (std::size_t k = 0; k < i.size(); ++k) i[k] = (std::norm(s1[k]) + std::norm(s2[k])) / 2;
  std::vector<double> out;
  for (std::size_t k = 1; k + 1 < i.size() && int(out.size()) < count; ++k)
    if (i[k] > i[k - 1] && i[k] >= i[k + 1]) out.push_back(rad_to_deg(theta[k]));
  return out;
}

// Airy's spacing of the first two supernumeraries against the Debye series' own maxima, for the
// primary and the secondary at x = 2000 and 10^4: within 3% (Airy theory places the first
// supernumerary within a few percent of Mie at x >= 1000: docs/rainbow-theories.md, "Validity";
// measured here 1.3% and 0.4% for the primary at x = 2000 and 10^4, 1.6% and 0.5% for the secondary).
TEST(LeeNotes, SupernumerarySpacingIsTheWaveSolutions) {
  const double n = 1.3335;
  for (const int p : {2, 3})
    for (const double x : {2000.0, 1e4}) {
      SCOPED_TRACE(testing::Message() << "p " << p << ", x " << x);
      const auto maxima = debye_maxima_deg(n, x, p, 3);
      ASSERT_EQ(maxima.size(), 3u);
      const double debye = std::abs(maxima[2] - maxima[1]);
      EXPECT_NEAR(supernumerary_spacing_deg(n, x, p) / debye, 1, 0.03) << debye;
    }
}

bool mentions(const std::vector<std::string>& notes, const std::string& text) {
  return std::any_of(notes.begin(), notes.end(), [&](const std::string& s) { return s.find(text) != std::string::npos; });
}

TEST(LeeNotes, TheDefaultsResolveTheirFringes) {
  for (const auto kind : {LeeTableKind::rainbow, LeeTableKind::corona, LeeTableKind::glory})
    EXPECT_TRUE(lee_resolution_notes(default_lee_spec(kind)).empty()) << table_kind_name(kind);
}

// A point sun leaves the 800 um drops' fringes (0.27 deg apart at 380 nm), which 1024 rows over
// 90 degrees (0.088 deg) alias; the rows the note asks for resolve them.
TEST(LeeNotes, RowsWiderThanTheFringesAreNamed) {
  LeeSpec s = default_lee_spec(LeeTableKind::rainbow);
  s.sun_disk_deg = 0;
  const auto notes = lee_resolution_notes(s);
  ASSERT_EQ(notes.size(), 1u);
  EXPECT_TRUE(mentions(notes, "primary bow")) << notes[0];
  EXPECT_TRUE(mentions(notes, "{size}") && mentions(notes, "{angle_deg}")) << notes[0];
  const auto at = notes[0].find("at least ");
  ASSERT_NE(at, std::string::npos);
  s.rows = std::stoi(notes[0].substr(at + 9));
  EXPECT_GT(s.rows, 1024);
  EXPECT_TRUE(lee_resolution_notes(s).empty());
  // A narrower range at the default rows does it too.
  s.rows = 1024;
  s.angle_min_deg = 130, s.angle_max_deg = 150;
  EXPECT_TRUE(lee_resolution_notes(s).empty());
}

TEST(LeeNotes, AiryBelowItsDomainAndCoarseMonodisperseColumnsAreNamed) {
  LeeSpec s = default_lee_spec(LeeTableKind::rainbow);
  s.theory = scatter::Theory{scatter::TheoryKind::Airy, 2};
  EXPECT_TRUE(mentions(lee_resolution_notes(s), "{radius_um} from 125, or {theory} mie"));
  s.radius_min_um = 125;
  EXPECT_FALSE(mentions(lee_resolution_notes(s), "Airy theory"));

  LeeSpec mono = default_lee_spec(LeeTableKind::rainbow);
  mono.size_spread = 0;
  mono.columns = 8;  // 5-800 um: 107% apart
  EXPECT_TRUE(mentions(lee_resolution_notes(mono), "{size_spread}"));
  mono.columns = 512;  // 1% apart
  EXPECT_FALSE(mentions(lee_resolution_notes(mono), "{size_spread}"));
}

// A table whose estimated error (LeeTable::error) is above kLeeErrorTolerance says so after the work,
// naming the sampling that would meet it from the rule that the error falls as 1 / sampling; at that
// sampling the table's own estimate is within the tolerance (an independent run: other wavelengths,
// radius grids and cell points), and no note is left. A small rainbow table at a quarter of the
// sampling (10 wavelengths) starts above it.
TEST(LeeNotes, ATableAboveItsErrorToleranceNamesTheSampling) {
  if (HYDROLUX_TEST_ASAN) GTEST_SKIP() << "three tables up to sampling 2: Release builds only";
  LeeSpec s = default_lee_spec(LeeTableKind::rainbow);
  s.columns = 2, s.rows = 16, s.angle_min_deg = 135, s.angle_max_deg = 143, s.radius_min_um = 50;
  s.radius_max_um = 200, s.sampling = 0.25;
  const LeeTable coarse = compute_lee_table(s);
  ASSERT_TRUE(coarse.error.luminance_rms);
  ASSERT_GT(*coarse.error.luminance_rms, kLeeErrorTolerance);
  const auto& notes = coarse.notes;
  ASSERT_TRUE(mentions(notes, "estimated error")) << (notes.empty() ? "" : notes.back());
  const auto at = notes.back().find("{sampling} ");
  ASSERT_NE(at, std::string::npos) << notes.back();
  s.sampling = std::stod(notes.back().substr(at + 11));
  EXPECT_GT(s.sampling, 0.25);
  const LeeTable fine = compute_lee_table(s);
  ASSERT_TRUE(fine.error.luminance_rms);
  std::printf("sampling 0.25: %.3g%%; sampling %g: %.3g%%\n", 100 * *coarse.error.luminance_rms, s.sampling,
              100 * *fine.error.luminance_rms);
  EXPECT_LT(*fine.error.luminance_rms, 1.5 * kLeeErrorTolerance);
  EXPECT_EQ(mentions(fine.notes, "estimated error"), *fine.error.luminance_rms > kLeeErrorTolerance);
  // One wavelength has no halves to compare: no estimate, no note.
  s.wavelength_min_nm = s.wavelength_max_nm = 550;
  EXPECT_FALSE(compute_lee_table(s).error.luminance_rms);
}

}  // namespace
}  // namespace hydrolux::atmos
