// Claims of docs/non-spherical.md, docs/sky.md and the gallery's captions about non-spherical
// drops, checked against published values and formulas written out here.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <optional>

#include "hydrolux/atmos/lee.hpp"
#include "hydrolux/optics/media.hpp"
#include "hydrolux/scatter/ellipse_rainbow.hpp"
#include "hydrolux/scatter/spheroid_bow.hpp"
#include "hydrolux/scatter/sphere.hpp"
#include "hydrolux/scatter/theories.hpp"

namespace hydrolux {
namespace {

// Beard & Chuang's (1987) equilibrium axis ratios as fitted by Andsager, Beard & Laird, J. Atmos.
// Sci. 56, 2673 (1999), eq. 2: D the equivalent diameter in mm, valid for D = 1-7 mm.
double beard_chuang_fit(double d_mm) {
  return 1.0048 + 5.7e-4 * d_mm - 2.628e-2 * d_mm * d_mm + 3.682e-3 * d_mm * d_mm * d_mm -
         1.677e-4 * d_mm * d_mm * d_mm * d_mm;
}

// Canting in the library: each orientation of a round drop (spheroid:1) sees the same circle, so a
// canted table equals the upright one when each evaluation's weights sum to 1 (1e-6: each
// orientation's rainbow ray is found by a search, good to ~1e-7 here; LeeShapes.SphereLimitEqualsTheAiryTable).
TEST(ShapeClaims, CantingWeightsOfARoundDropSumToOne) {
  atmos::LeeSpec s = atmos::profile_spec(atmos::LeeTableKind::rainbow, 500, 134, 142, 81);
  s.theory = scatter::parse_theory("airy");
  s.shape = atmos::parse_drop_shape("spheroid:1");
  s.wavelengths = 6;
  const atmos::LeeTable upright = atmos::compute_lee_table(s);
  s.canting_deg = 10;
  const atmos::LeeTable canted = atmos::compute_lee_table(s);
  double peak = 0, worst = 0;
  for (std::size_t i = 0; i < upright.xyz.size(); ++i) peak = std::max(peak, upright.xyz[i]);
  for (std::size_t i = 0; i < upright.xyz.size(); ++i) worst = std::max(worst, std::abs(upright.xyz[i] - canted.xyz[i]));
  EXPECT_GT(peak, 0);
  EXPECT_LT(worst, 1e-6 * peak);
}

// The canted table's sum over orientations, through the library's tables. A one-row table (point sun,
// one wavelength, one radius, Airy theory of the plane section) is one evaluation (n = 0): it holds
// C sum_o I_o(theta) / 9 with C the same for the upright and the canted drop, I_o the section bow of
// the drop of axis o, the nine axes of that evaluation (atmos::evaluation_canting_axes; their
// distribution is CantingRule.AxesAreNormalTilts's). So canted / upright = sum_o I_o / (9 I_0),
// computed here from the public section functions (spheroid_section, section_rainbow, section_airy,
// section_airy_intensity, and spheroid_bow, which moves each profile to the tilted drop's 3-D bow
// angle). Spheroid 0.9, 1 mm, 550 nm, canting 10 degrees, at z = 0.5, 1.5 and 3 of the upright
// bow. Within 1e-9 relative (rounding of sums of nine terms); the same sum with each section's own
// angle instead of the 3-D edge differs by more than 2% (asserted), so the table uses the edge.
TEST(ShapeClaims, CantedTableIsTheSumOverItsOrientationsPlaneSections) {
  constexpr double kPi = 3.14159265358979323846;
  const double sigma_deg = 10, radius_um = 1000, nm = 550, q = 0.9;
  const auto water = optics::find_medium("water");
  const auto air = optics::find_medium("air");
  const scatter::SphereProblem sp = scatter::sphere_problem(radius_um, nm, *water, *air);
  const auto bow_of = [&](const Vec3& axis, bool edge_3d) {
    const auto bow = scatter::section_rainbow(sp.m.real(), 2, scatter::spheroid_section(q, axis, 0, 0));
    if (!bow) return std::optional<scatter::SectionAiry>();
    scatter::SectionAiry a = scatter::section_airy(*bow, sp.x, sp.m.imag());
    if (edge_3d)
      if (const auto edge = scatter::spheroid_bow(sp.m.real(), 2, q, axis, 0, 0, *bow)) a.theta_r = edge->scattering_angle;
    return std::optional<scatter::SectionAiry>(a);
  };
  const auto upright_bow = bow_of(Vec3(0, 1, 0), true);
  ASSERT_TRUE(upright_bow.has_value());
  double section_angle_off = 0;
  for (const double z : {0.5, 1.5, 3.0}) {
    const double theta = upright_bow->theta_r + upright_bow->side * z / upright_bow->scale;
    const double deg = theta * 180 / kPi;
    atmos::LeeSpec spec = atmos::profile_spec(atmos::LeeTableKind::rainbow, radius_um, deg, deg, 1);
    spec.theory = scatter::parse_theory("airy");
    spec.shape = atmos::parse_drop_shape("spheroid:0.9");
    spec.sun_disk_deg = 0;
    spec.wavelength_min_nm = spec.wavelength_max_nm = nm;
    spec.threads = 1;
    const double upright = atmos::compute_lee_table(spec).at(0, 0).Y;
    spec.canting_deg = sigma_deg;
    const double canted = atmos::compute_lee_table(spec).at(0, 0).Y;
    const double i0 = scatter::section_airy_intensity(*upright_bow, theta);
    ASSERT_GT(upright, 0) << z;
    ASSERT_GT(i0, 0) << z;
    double sum = 0, sum_section = 0;
    for (const Vec3& axis : atmos::evaluation_canting_axes(spec, 0)) {
      if (const auto bow = bow_of(axis, true)) sum += scatter::section_airy_intensity(*bow, theta);
      if (const auto bow = bow_of(axis, false)) sum_section += scatter::section_airy_intensity(*bow, theta);
    }
    const double want = sum / (atmos::kCantingAxes * i0);
    EXPECT_NEAR(canted / upright, want, 1e-9 * want) << "z " << z;
    section_angle_off = std::max(section_angle_off, std::abs(sum_section / sum - 1));
  }
  EXPECT_GT(section_angle_off, 0.02);
}

// docs/non-spherical.md l. 125-127: the primary's fold meets the hyperbolic umbilic at width /
// height 1.31, Q = 0.763. Reference: q4 = D / H = 1.31, the published critical aspect ratio for
// the hyperbolic umbilic focal section of water drops (C. E. Dean and P. L. Marston, Appl. Opt.
// 30, 3443, 1991, after Marston & Trinh, Nature 312, 529, 1984); Q = 1 / q4. The method's
// smallest axis ratio (kMinBowAxisRatio) lies just above it (within 0.01).
TEST(ShapeClaims, UmbilicAxisRatioAndTheMethodsLimit) {
  const double q4 = 1.31;
  EXPECT_NEAR(1 / q4, 0.763, 5e-4);
  EXPECT_GT(atmos::kMinBowAxisRatio, 1 / q4);
  EXPECT_LT(atmos::kMinBowAxisRatio - 1 / q4, 0.01);
}

// docs/sky.md l. 227-228 (drops of 0.1 mm are round: Q = 0.999) and the caption of
// bow_real_drops.png (src/gallery/shape_gallery.cpp: axis ratio 0.999 at 0.1 mm to 0.91 at
// 1.1 mm). References: at 1.1 mm (D = 2.2 mm) the Beard-Chuang fit above, 0.914; at 0.1 mm, below
// the fit's range, its D = 1 mm value 0.9826 carried down as a^2 (the deformation of a small drop
// grows with its Bond number rho g a^2 / sigma: Pruppacher & Klett, Microphysics of Clouds and
// Precipitation, 1997, chapter 10), 0.9993. The library's Beard-Chuang axis ratios are held
// to the stated digits (half a unit) and to these references (0.005: the fit's own spread about
// Beard & Chuang's shapes).
TEST(ShapeClaims, AxisRatiosOfSmallAndMediumRainDrops) {
  const atmos::DropShapeSpec bc = atmos::parse_drop_shape("beard-chuang");
  const double at_100 = atmos::drop_axis_ratio(bc, 100), at_1100 = atmos::drop_axis_ratio(bc, 1100);
  const double fit_1100 = beard_chuang_fit(2.2);
  const double scaled_100 = 1 - (1 - beard_chuang_fit(1.0)) * (0.1 / 0.5) * (0.1 / 0.5);
  EXPECT_NEAR(fit_1100, 0.91, 0.005);
  EXPECT_NEAR(scaled_100, 0.999, 5e-4);
  EXPECT_NEAR(at_1100, 0.91, 0.005);
  EXPECT_NEAR(at_1100, fit_1100, 0.005);
  EXPECT_NEAR(at_100, 0.999, 5e-4);
  EXPECT_NEAR(at_100, scaled_100, 1e-4);
}

}  // namespace
}  // namespace hydrolux
