// Lee tables of non-spherical drops (docs/non-spherical.md): the sphere limit against the existing
// Airy and Mie tables, a twinned bow from two drop populations, and Marshall-Palmer rain of
// Beard-Chuang drops whose supernumeraries survive at the top of the bow and not at its sides.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "hydrolux/atmos/lee.hpp"
#include "hydrolux/core/error.hpp"
#include "hydrolux/scatter/ellipse_rainbow.hpp"
#include "hydrolux/scatter/geometric.hpp"

namespace {

using namespace hydrolux;
using atmos::LeeSpec;
using atmos::LeeTable;

constexpr double kDeg = 3.14159265358979323846 / 180;

// One radius (no spread) over [a0, a1] degrees, Airy theory of the primary, the given shape.
LeeSpec airy_profile(double radius_um, double a0, double a1, int rows, const std::string& shape, double position_deg,
                     double sun_elevation_deg = 0) {
  LeeSpec s = atmos::profile_spec(atmos::LeeTableKind::rainbow, radius_um, a0, a1, rows);
  s.theory = scatter::parse_theory("airy");
  s.shape = atmos::parse_drop_shape(shape);
  s.position_deg = position_deg;
  s.sun_elevation_deg = sun_elevation_deg;
  return s;
}

std::vector<double> luminance(const LeeTable& t, int column = 0) {
  std::vector<double> y(std::size_t(t.rows()));
  for (int r = 0; r < t.rows(); ++r) y[std::size_t(r)] = t.at(r, column).Y;
  return y;
}

// The angle of the largest value, refined by a parabola through it and its neighbours.
double peak_deg(const std::vector<double>& angle, const std::vector<double>& y) {
  const std::size_t i = std::size_t(std::max_element(y.begin(), y.end()) - y.begin());
  if (i == 0 || i + 1 == y.size()) return angle[i];
  const double d = y[i - 1] - 2 * y[i] + y[i + 1];
  return angle[i] + (d != 0 ? 0.5 * (y[i - 1] - y[i + 1]) / d : 0.0) * (angle[i + 1] - angle[i]);
}

// The sphere limit. With axis ratio 1 the section is the unit circle and the new path must give the
// existing Airy table: the only differences are the rainbow ray found by a search instead of
// Descartes' formula and its curvature by a second difference (both ~1e-8 relative, test_ellipse_
// rainbow), so 1e-6 of the peak. A whole table (24 columns with a size spread, 301 rows) so the
// population integration and the sun's disk go through the same code.
TEST(LeeShapes, SphereLimitEqualsTheAiryTable) {
  LeeSpec s = atmos::default_lee_spec(atmos::LeeTableKind::rainbow);
  s.theory = scatter::parse_theory("airy");
  s.radius_min_um = 100;
  s.radius_max_um = 1000;
  s.columns = 24;
  s.angle_min_deg = 130;
  s.angle_max_deg = 145;
  s.rows = 301;
  s.wavelengths = 12;
  const LeeTable sphere = atmos::compute_lee_table(s);
  s.shape = atmos::parse_drop_shape("spheroid:1");
  s.position_deg = 37;
  s.sun_elevation_deg = 20;
  const LeeTable limit = atmos::compute_lee_table(s);
  double peak = 0, worst = 0;
  for (std::size_t i = 0; i < sphere.xyz.size(); ++i) peak = std::max(peak, sphere.xyz[i]);
  for (std::size_t i = 0; i < sphere.xyz.size(); ++i) worst = std::max(worst, std::abs(sphere.xyz[i] - limit.xyz[i]));
  EXPECT_LT(worst / peak, 1e-6);
}

// And so against Mie as Airy theory is (tests/atmos/test_lee.cpp, LeeTheories.AiryAgainstMie: Wang
// & van de Hulst, Appl. Opt. 30, 106, 1991): near the primary of 1000 um drops the luminance RMS
// over 136-141 degrees is within 5% of the Mie peak.
TEST(LeeShapes, SphereLimitAgainstMie) {
  const LeeTable a = atmos::compute_lee_table(airy_profile(1000, 130, 145, 301, "spheroid:1", 0));
  LeeSpec ms = atmos::profile_spec(atmos::LeeTableKind::rainbow, 1000, 130, 145, 301);
  const LeeTable m = atmos::compute_lee_table(ms);
  double num = 0, peak = 0;
  int n = 0;
  for (int i = 0; i < a.rows(); ++i) {
    if (a.angle_deg[std::size_t(i)] < 136 || a.angle_deg[std::size_t(i)] > 141) continue;
    const double d = a.at(i, 0).Y - m.at(i, 0).Y;
    num += d * d;
    ++n;
    peak = std::max(peak, m.at(i, 0).Y);
  }
  EXPECT_LT(std::sqrt(num / n) / peak, 0.05);
}

// Luminance profile of a mixture of the columns of a table, each weighted (weights per unit of the
// drops' projected area: the table is already per projected area).
std::vector<double> mixture(const LeeTable& t, const std::vector<double>& weight) {
  std::vector<double> y(std::size_t(t.rows()), 0.0);
  double total = 0;
  for (double w : weight) total += w;
  for (int c = 0; c < t.columns(); ++c)
    for (int r = 0; r < t.rows(); ++r) y[std::size_t(r)] += weight[std::size_t(c)] / total * t.at(r, c).Y;
  return y;
}

// The local maxima of y over [a0, a1] with their prominence: min over both sides of (peak - the
// lowest value before a higher one), relative to the peak.
struct Maximum {
  double angle_deg, prominence;
};
std::vector<Maximum> maxima(const std::vector<double>& angle, const std::vector<double>& y, double a0, double a1) {
  std::vector<Maximum> out;
  for (std::size_t i = 1; i + 1 < y.size(); ++i) {
    if (angle[i] < a0 || angle[i] > a1 || !(y[i] >= y[i - 1] && y[i] > y[i + 1])) continue;
    double left = y[i], right = y[i];
    for (std::size_t k = i; k-- > 0 && y[k] <= y[i];) left = std::min(left, y[k]);
    for (std::size_t k = i + 1; k < y.size() && y[k] <= y[i]; ++k) right = std::min(right, y[k]);
    out.push_back({angle[i], (y[i] - std::max(left, right)) / y[i]});
  }
  return out;
}

// The Moebius shift of the primary's rainbow ray at the top of the bow (sun on the horizon) for a
// Beard-Chuang drop of radius r: the section's rainbow angle minus Descartes'.
double top_shift_deg(double radius_um, double n) {
  const double q = atmos::drop_axis_ratio(atmos::parse_drop_shape("beard-chuang"), radius_um);
  const auto top = scatter::section_rainbow(n, 2, scatter::spheroid_section(q, Vec3(0, 1, 0), 0, 0));
  return top->scattering_angle / kDeg - scatter::rainbow_angle(n, 2) / kDeg;
}

// A twinned bow (Haussmann, Appl. Opt. 54(4), B117, 2015; the observations there and on
// atoptics.co.uk: two bows that share their feet and split towards the top, the extra one inside).
// Two narrow populations of Beard-Chuang drops, 200 um (axis ratio 0.997) and 600 um (0.974), the
// sun on the horizon. At the feet (position 90) the sections are the equatorial circles: the bows
// differ only by Airy theory's size-dependent offset (-0.32 degrees) and the sum shows one maximum.
// At the top the difference grows by the Moebius shifts' difference, 2.45 degrees from the sections'
// rainbow rays at the two radii (test_ellipse_rainbow checks those against an exact 2-D trace); the
// populations' 5% spread moves their mean shifts (which grow about as a^2) by up to ~0.1 degree
// (measured 0.11 here), hence 0.15. The sum shows two maxima of comparable prominence.
TEST(LeeShapes, TwinnedBowFromTwoPopulations) {
  const auto table = [](double psi) {
    LeeSpec s = airy_profile(200, 134, 146, 601, "beard-chuang", psi, 0);
    s.columns = 2;
    s.radius_max_um = 600;
    s.size_spread = 0.05;
    return atmos::compute_lee_table(s);
  };
  const LeeTable top = table(0), feet = table(90);
  const auto separation = [](const LeeTable& t) {
    return peak_deg(t.angle_deg, luminance(t, 1)) - peak_deg(t.angle_deg, luminance(t, 0));
  };
  const double n = 1.3335;  // water near 560 nm, the middle of the luminance weighting
  const double moebius = top_shift_deg(600, n) - top_shift_deg(200, n);
  EXPECT_NEAR(moebius, 2.45, 0.05);
  EXPECT_NEAR(separation(top) - separation(feet), moebius, 0.15);
  EXPECT_LT(std::abs(separation(feet)), 0.4);
  const auto strong = [](const std::vector<Maximum>& m) {
    std::vector<double> a;
    for (const auto& x : m)
      if (x.prominence > 0.3) a.push_back(x.angle_deg);
    return a;
  };
  const auto at_top = strong(maxima(top.angle_deg, mixture(top, {1, 1}), 134, 146));
  ASSERT_EQ(at_top.size(), 2u);
  EXPECT_GT(at_top[1] - at_top[0], 2.0);
  const auto at_feet = strong(maxima(feet.angle_deg, mixture(feet, {1, 1}), 134, 146));
  ASSERT_GE(at_feet.size(), 1u);
  for (std::size_t k = 1; k < at_feet.size(); ++k) EXPECT_GT(at_feet[k] - at_feet[0], 1.0);  // supernumeraries only
}

// Marshall-Palmer rain (5 mm/h: n(a) ~ exp(-8200 h^-0.21 a), Marshall & Palmer, J. Meteor. 5, 165,
// 1948) of Beard-Chuang drops, 100-1100 um, the sun 2 degrees up: the bow's supernumeraries are
// visible at the top and washed out at the side, as in natural rainbows (Koennen's explanation,
// reviewed by Haussmann 2015: at the top the Moebius shift, growing with size, offsets Airy's
// offset, shrinking with size, for drops of ~0.2 mm, which then pile up their fringes; at the side
// every size has its own fringe spacing). Measured: at the top a first supernumerary of prominence
// 0.14 1.0 degree inside the main maximum; at the side no maximum besides the main one. Bounds: a
// supernumerary of prominence above 0.07 at the top, none above 0.02 at the side.
TEST(LeeShapes, MarshallPalmerSupernumerariesOnlyAtTheTop) {
  const auto profile = [](double psi) {
    LeeSpec s = airy_profile(100, 134, 146, 601, "beard-chuang", psi, 2);
    s.columns = 120;
    s.radius_max_um = 1100;
    const LeeTable t = atmos::compute_lee_table(s);
    std::vector<double> w;  // per log-spaced column: n(a) a (per ln a) x a^2 (projected area)
    for (double r : t.radius_um) w.push_back(r * r * r * std::exp(-8200 * std::pow(5.0, -0.21) * r * 1e-6));
    return maxima(t.angle_deg, mixture(t, w), 134, 146);
  };
  const auto second = [](const std::vector<Maximum>& m) {
    double best = 0;
    for (std::size_t k = 1; k < m.size(); ++k)
      if (m[k].angle_deg > m[0].angle_deg) best = std::max(best, m[k].prominence);
    return best;
  };
  const auto top = profile(0), side = profile(90);
  ASSERT_FALSE(top.empty());
  ASSERT_FALSE(side.empty());
  EXPECT_GT(second(top), 0.07);
  EXPECT_LT(second(side), 0.02);
}

// The sidecar's axis ratios: Beard-Chuang's shape for each radius (scatter/drop_shape.hpp), 1 for spheres,
// the given one for spheroids; below the shape table's 0.5 mm the departure shrinks as a^2.
TEST(LeeShapes, AxisRatios) {
  const auto bc = atmos::parse_drop_shape("beard-chuang");
  EXPECT_EQ(atmos::drop_axis_ratio(atmos::parse_drop_shape("sphere"), 800), 1.0);
  EXPECT_EQ(atmos::drop_axis_ratio(atmos::parse_drop_shape("spheroid:0.9"), 800), 0.9);
  const double q500 = atmos::drop_axis_ratio(bc, 500);
  EXPECT_NEAR(q500, 0.984, 0.002);  // scatter/drop_shape.hpp: axis ratio 0.984 at 0.5 mm
  EXPECT_NEAR(1 - atmos::drop_axis_ratio(bc, 250), (1 - q500) / 4, 1e-12);
  EXPECT_LT(atmos::drop_axis_ratio(bc, 1000), q500);
  EXPECT_EQ(atmos::drop_shape_name(bc), "beard-chuang");
  EXPECT_EQ(atmos::drop_shape_name(atmos::parse_drop_shape("spheroid:0.95")), "spheroid:0.95");
}

// Bad shapes and options: one error each, naming the option.
TEST(LeeShapes, Validation) {
  EXPECT_THROW(atmos::parse_drop_shape("egg"), UnknownNameError);
  EXPECT_THROW(atmos::parse_drop_shape("spheroid:x"), UnknownNameError);
  EXPECT_THROW(atmos::parse_drop_shape("spheroid:0.3"), DomainError);
  EXPECT_THROW(atmos::parse_drop_shape("spheroid:1.01"), DomainError);
  EXPECT_THROW(atmos::parse_drop_shape("spheroid:0.5"), DomainError);  // outside the method's domain
  LeeSpec mie = atmos::profile_spec(atmos::LeeTableKind::rainbow, 500, 130, 145, 11);
  mie.shape = atmos::parse_drop_shape("beard-chuang");
  EXPECT_THROW(atmos::validate(mie), Error);
  LeeSpec far = airy_profile(500, 130, 145, 11, "spheroid:0.95", 181);
  EXPECT_THROW(atmos::validate(far), DomainError);
  LeeSpec big = airy_profile(4000, 130, 145, 11, "beard-chuang", 0);
  try {
    atmos::validate(big);
    ADD_FAILURE() << "a 4 mm Beard-Chuang drop (axis ratio 0.51) was accepted";
  } catch (const DomainError& e) {
    EXPECT_EQ(e.quantity(), "radius_um");
  }
}

// Issue 37: axis ratios 0.70-0.76 were computed with exit 0 although the one-fold Airy profile fails
// there (the hyperbolic umbilic at width / height 1.31, Q = 0.763: Marston and Trinh, Nature 312, 529,
// 1984): at the top of the bow with the sun on the horizon the primary collapsed onto 180 degrees with
// a 1/sin term ~1500 times a sphere's peak (Q = 0.709) and the secondary was an all-zero table
// (Q <= 0.72). The limit is now 0.77 in every door, with one range in every message. At the limit the
// bow is still a bow: at the top (the worst place: the section there is the drop's own flattened
// meridian) and at the side, the primary for the sun on the horizon and at 30 degrees, the secondary
// for the sun on the horizon,
// each table's peak is finite, lies away from 180 degrees (the collapse) and within 5 times the
// sphere's and above 1/20 of it (measured: the primary 3.4 times at the top, sun on the horizon; the
// secondary there 0.14 times).
TEST(LeeShapes, AxisRatiosBelowTheUmbilicAreRefusedAndTheLimitKeepsABow) {
  for (const char* bad : {"spheroid:0.769", "spheroid:0.709", "spheroid:0.3", "spheroid:1.01"}) {
    SCOPED_TRACE(bad);
    try {
      (void)atmos::parse_drop_shape(bad);
      ADD_FAILURE() << "accepted";
    } catch (const DomainError& e) {
      EXPECT_EQ(e.quantity(), "axis_ratio");
      EXPECT_EQ(e.lo(), 0.77);
      EXPECT_NE(std::string(e.what()).find("outside [0.77, 1]"), std::string::npos) << e.what();
    }
  }
  try {
    (void)atmos::parse_drop_shape("spheroid:x");
    ADD_FAILURE();
  } catch (const UnknownNameError& e) {
    EXPECT_NE(std::string(e.what()).find("[0.77, 1]"), std::string::npos) << e.what();
  }
  const auto sphere_peak = [](double a0, double a1, const char* theory) {
    LeeSpec s = airy_profile(500, a0, a1, 901, "sphere", 0);
    s.theory = scatter::parse_theory(theory);
    const auto y = luminance(atmos::compute_lee_table(s));
    return *std::max_element(y.begin(), y.end());
  };
  const double primary = sphere_peak(120, 180, "airy"), secondary = sphere_peak(90, 180, "airy:3");
  for (const char* theory : {"airy", "airy:3"})
    for (double position : {0.0, 90.0})
      for (double sun : {0.0, 30.0}) {
        // The secondary of flattened drops with the sun up fades at some positions for Q = 0.8 as for
        // 0.77 (a separate question, left to the 3-D tracer's check, issue 39): the horizon sun only.
        if (std::string(theory) == "airy:3" && sun > 0) continue;
        SCOPED_TRACE(std::string(theory) + " position " + std::to_string(position) + " sun " + std::to_string(sun));
        LeeSpec s = airy_profile(500, 90, 180, 901, "spheroid:0.77", position, sun);
        s.theory = scatter::parse_theory(theory);
        const LeeTable t = atmos::compute_lee_table(s);
        const auto y = luminance(t);
        const double top = *std::max_element(y.begin(), y.end());
        const double ref = std::string(theory) == "airy" ? primary : secondary;
        EXPECT_TRUE(std::isfinite(top));
        EXPECT_GT(top, 0.05 * ref);  // the secondary at the top, sun on the horizon: 0.14 of a sphere's
        EXPECT_LT(top, 5 * ref);
        std::vector<double> angle(y.size());
        for (std::size_t r = 0; r < y.size(); ++r) angle[r] = 90 + 90.0 * double(r) / double(y.size() - 1);
        EXPECT_LT(peak_deg(angle, y), 176.0);
      }
}

}  // namespace
