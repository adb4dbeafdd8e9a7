// Spectral colour: the CIE 1931 observer table, the light sources, the RGB spaces, Bradford
// adaptation and the gamut mapping, against published numbers and exact identities.
#include <gtest/gtest.h>

#include <cmath>

#include "hydrolux/color/cie.hpp"
#include "hydrolux/core/error.hpp"

namespace {

using namespace hydrolux;
using namespace hydrolux::color;

// CIE 015:2004 Table T.4 (1 nm): y_bar peaks at 555 nm with exactly 1 (it is V(lambda)), and the
// table starts with x_bar(360) = 0.0001299. Between rows the functions are interpolated linearly.
TEST(Cie1931, TableValues) {
  EXPECT_DOUBLE_EQ(cie1931(555).Y, 1.0);
  EXPECT_DOUBLE_EQ(cie1931(360).X, 0.0001299);
  EXPECT_DOUBLE_EQ(cie1931(600).X, 1.0622);  // x_bar(600), CIE 015 Table T.4
  const Xyz a = cie1931(500), b = cie1931(501), mid = cie1931(500.5);
  EXPECT_NEAR(mid.Y, 0.5 * (a.Y + b.Y), 1e-15);
  EXPECT_EQ(cie1931(359.9).Y, 0.0);
  EXPECT_EQ(cie1931(830.1).Y, 0.0);
}

// The CIE chose the colour-matching functions so that the equal-energy stimulus E has X = Y = Z
// (CIE 015:2004 section 7.1: "the tristimulus values of illuminant E are equal"). Over 360-830 nm
// at 1 nm the three sums of the published table are 106.865, 106.857, 106.892 (within 0.03%), so
// E's chromaticity is (1/3, 1/3) to within 1e-4 (the table's own rounding).
TEST(Cie1931, FlatSpectrumIsTheEqualEnergyWhite) {
  const Xyz e = integrate_xyz(Illuminant::equal_energy(), kCmfMinNm, kCmfMaxNm);
  EXPECT_NEAR(e.X, 106.8655, 0.01);
  EXPECT_NEAR(e.Y, 106.8569, 0.01);
  EXPECT_NEAR(e.Z, 106.8923, 0.01);
  const auto xy = chromaticity(e);
  EXPECT_NEAR(xy[0], 1.0 / 3, 1e-4);
  EXPECT_NEAR(xy[1], 1.0 / 3, 1e-4);
}

// The spectral locus: a 550 nm line has chromaticity (0.30160, 0.69231) (CIE 015:2004 Table T.4,
// x(lambda), y(lambda) columns, 5 decimals); 450 nm (0.15664, 0.01771).
TEST(Cie1931, MonochromaticLinesOnTheSpectralLocus) {
  const auto g = chromaticity(cie1931(550));
  EXPECT_NEAR(g[0], 0.30160, 1e-5);
  EXPECT_NEAR(g[1], 0.69231, 1e-5);
  const auto b = chromaticity(cie1931(450));
  EXPECT_NEAR(b[0], 0.15664, 1e-5);
  EXPECT_NEAR(b[1], 0.01771, 1e-5);
}

// XYZ -> linear sRGB from the BT.709 primaries and D65 = (0.3127, 0.3290), as the W3C's CSS Color
// Module Level 4 (section 18, sample code, lin_sRGB matrix to 16 digits) derives it; the 4-decimal
// matrix of IEC 61966-2-1:1999 was computed from a rounded D65 (0.9505, 1, 1.0890) and differs by up
// to 4e-4. BT.709 and BT.2020 give the luminance coefficients.
TEST(RgbSpaces, PublishedMatrices) {
  const Mat3 m = xyz_to_rgb_matrix(RgbSpace::rec709);
  const Mat3 css{{{3.2409699419045226, -1.537383177570094, -0.4986107602930034},
                  {-0.9692436362808796, 1.8759675015077202, 0.04155505740717559},
                  {0.05563007969699366, -0.20397695888897652, 1.0569715142428786}}};
  const Mat3 iec{{{3.2406, -1.5372, -0.4986}, {-0.9689, 1.8758, 0.0415}, {0.0557, -0.2040, 1.0570}}};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      EXPECT_NEAR(m[i][j], css[i][j], 1e-12) << i << j;
      EXPECT_NEAR(m[i][j], iec[i][j], 4e-4) << i << j;
    }
  const Rgb y709 = luminance_weights(RgbSpace::rec709);
  EXPECT_NEAR(y709[0], 0.2126, 1e-4);
  EXPECT_NEAR(y709[1], 0.7152, 1e-4);
  EXPECT_NEAR(y709[2], 0.0722, 1e-4);
  const Rgb y2020 = luminance_weights(RgbSpace::rec2020);  // ITU-R BT.2020-2, non-constant luminance
  EXPECT_NEAR(y2020[0], 0.2627, 1e-4);
  EXPECT_NEAR(y2020[1], 0.6780, 1e-4);
  EXPECT_NEAR(y2020[2], 0.0593, 1e-4);
  // D65 is white in both: RGB (1, 1, 1).
  for (RgbSpace s : {RgbSpace::rec709, RgbSpace::rec2020}) {
    const Rgb w = matmul(xyz_to_rgb_matrix(s), d65_white());
    for (double c : w) EXPECT_NEAR(c, 1.0, 1e-12);
  }
  EXPECT_EQ(parse_rgb_space("srgb"), RgbSpace::rec709);
  EXPECT_THROW(parse_rgb_space("p3"), UnknownNameError);
}

// Bradford D50 -> D65 as tabulated by Lindbloom (brucelindbloom.com, "Chromatic Adaptation",
// 7 decimals, from D50 = (0.96422, 1, 0.82521) and D65 = (0.95047, 1, 1.08883)).
TEST(Bradford, LindbloomD50ToD65) {
  const Mat3 m = bradford_adaptation({0.96422, 1.0, 0.82521}, {0.95047, 1.0, 1.08883});
  const Mat3 ref{{{0.9555766, -0.0230393, 0.0631636}, {-0.0282895, 1.0099416, 0.0210077}, {0.0122982, -0.0204830, 1.3299098}}};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) EXPECT_NEAR(m[i][j], ref[i][j], 2e-7) << i << j;
}

// What the Lee tables rely on: a source's own white, adapted to D65 and taken to RGB, is (1, 1, 1)
// times its luminance, for the sun and for a blackbody far from D65.
TEST(Bradford, SourceWhiteBecomesRgbWhite) {
  for (const Illuminant& s : {Illuminant::astm_g173_direct(), Illuminant::blackbody(3000)}) {
    const Xyz w = integrate_xyz(s, 380, 780);
    const Mat3 m = multiply(xyz_to_rgb_matrix(RgbSpace::rec709), bradford_adaptation(w, d65_white()));
    const Rgb rgb = matmul(m, w);
    for (double c : rgb) EXPECT_NEAR(c / w.Y, 1.0, 1e-12) << s.name();
  }
}

// Wien's displacement law, lambda_max T = 2.897771955e-3 m K (CODATA 2018): the blackbody source
// peaks at 501.5 nm for 5778 K; it is 1 at 560 nm by construction.
TEST(Illuminants, BlackbodyAndSun) {
  const Illuminant bb = Illuminant::parse("blackbody:5778");
  EXPECT_EQ(bb.name(), "blackbody:5778");
  EXPECT_DOUBLE_EQ(bb(560), 1.0);
  double best = 0, at = 0;
  for (double nm = 400; nm <= 600; nm += 0.01)
    if (bb(nm) > best) {
      best = bb(nm);
      at = nm;
    }
  EXPECT_NEAR(at, 2.897771955e6 / 5778, 0.02);
  // ASTM G173-03 direct + circumsolar, rows of the table itself (W m^-2 nm^-1).
  const Illuminant sun = Illuminant::parse("astm-g173-direct");
  EXPECT_DOUBLE_EQ(sun(500), 1.3391);
  EXPECT_DOUBLE_EQ(sun(550), 1.3648);
  EXPECT_THROW(sun(1200), DomainError);
  EXPECT_THROW(Illuminant::parse("blackbody:5"), DomainError);
  EXPECT_THROW(Illuminant::parse("d65"), UnknownNameError);
  EXPECT_THROW(Illuminant::parse("blackbody:"), UnknownNameError);
}

// Desaturation toward the white point at constant luminance (the mapping Lee and Laven use): a
// negative component is lifted to exactly 0, the luminance is kept, the hue line is kept (the
// result lies on the segment from white to the colour), and in-gamut or HDR values pass unchanged.
TEST(GamutMapping, DesaturateAtConstantLuminance) {
  const Rgb w = luminance_weights(RgbSpace::rec709);
  const auto lum = [&](const Rgb& c) { return w[0] * c[0] + w[1] * c[1] + w[2] * c[2]; };
  const Rgb spectral = matmul(xyz_to_rgb_matrix(RgbSpace::rec709), cie1931(500));  // far outside
  ASSERT_LT(std::min({spectral[0], spectral[1], spectral[2]}), 0);
  const Rgb mapped = desaturate_into_gamut(spectral, RgbSpace::rec709);
  EXPECT_NEAR(lum(mapped), lum(spectral), 1e-12);
  EXPECT_NEAR(std::min({mapped[0], mapped[1], mapped[2]}), 0.0, 1e-15);
  const double y = lum(spectral);
  const double s = (mapped[1] - y) / (spectral[1] - y);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(mapped[c], y + s * (spectral[c] - y), 1e-12);
  EXPECT_GT(s, 0);
  EXPECT_LT(s, 1);
  const Rgb inside{0.2, 0.5, 3.0};  // HDR, in gamut
  EXPECT_EQ(desaturate_into_gamut(inside, RgbSpace::rec709), inside);
  const Rgb dark{-1, -1, -1};
  EXPECT_EQ(desaturate_into_gamut(dark, RgbSpace::rec709), (Rgb{0, 0, 0}));
}

}  // namespace
