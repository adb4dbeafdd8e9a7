// Issue 39: an integral the user does not see is converged at the default or states its error.
// Lee tables of non-spherical drops average the bow over the drops' axis tilts (canting): the tilt
// components (tx, tz) independent normals of standard deviation sigma, the axis normalize(tan tx, 1,
// tan tz). The library (src/atmos/lee.cpp, drop_orientations) draws nine orientations for each
// evaluation, its own, so that the orientations are sampled with the wavelengths and radii and the
// table's error estimate covers them. Here the library's canted table is measured against a much
// finer rule over per-orientation tables: the equal-probability product rule of M x M points
// (midpoints in the normal distribution's cumulative probability, M = 32 to 128), whose convergence
// is checked by halving M. (Gauss-Hermite rules of 3 x 3 (the library's until issue 39) to 21 x 21,
// nodes computed here, do not converge: the bow moves at first order in the tilt, by more than its
// width, so the integrand is not a low-degree polynomial in the tilts; BowMovesAtFirstOrderInTheTilt,
// ThreeByThreeRuleAgainstAConvergedReference and the survey, DISABLED_Survey, whose numbers
// docs/non-spherical.md quotes.)
//
// One orientation's table from the library. A spheroid is symmetric about its axis, so what a drop
// of axis A sees at sun elevation e and position angle psi depends only on the angle between A and
// the light and on where A's projection on the sky lies relative to the bow's point: an upright
// drop (the library's table without canting) at the elevation e' and position psi' of the same
// geometry sees the same (upright_frame below; checked orientation by orientation through
// scatter::spheroid_section and scatter::spheroid_bow). The canted table of any rule is then the
// weighted sum of upright tables at the rule's mapped frames, each an independent table of the
// library with its own sampling.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "hydrolux/atmos/lee.hpp"
#include "hydrolux/core/vec.hpp"
#include "hydrolux/optics/media.hpp"
#include "hydrolux/scatter/ellipse_rainbow.hpp"
#include "hydrolux/scatter/sphere.hpp"
#include "hydrolux/scatter/spheroid_bow.hpp"
#include "hydrolux/scatter/theories.hpp"
#include "support/asan.hpp"

namespace hydrolux {
namespace {

constexpr double kPi = 3.14159265358979323846;
double rad(double deg) { return deg * kPi / 180; }
double deg(double r) { return r * 180 / kPi; }

// E[f(t)] for t ~ N(0, 1) as sum_i weight[i] f(node[i]): Gauss-Hermite of n points. The roots of
// the orthonormal Hermite polynomial h_n (recurrence h_j = x sqrt(2/j) h_{j-1} - sqrt((j-1)/j)
// h_{j-2}, h_0 = pi^(-1/4)) are bracketed by a scan and polished by Newton's method
// (h_n' = sqrt(2n) h_{n-1}); the weights are 2 / h_n'(x)^2 for exp(-x^2), then t = sqrt(2) x and
// the weights / sqrt(pi) for the normal density.
struct Rule {
  std::vector<double> node, weight;
};
Rule gauss_hermite(int n) {
  const auto h = [n](double x, double& hn1) {
    double a = 0, b = std::pow(kPi, -0.25);  // h_{j-2}, h_{j-1}
    for (int j = 1; j <= n; ++j) {
      const double c = x * std::sqrt(2.0 / j) * b - std::sqrt(double(j - 1) / j) * a;
      a = b;
      b = c;
    }
    hn1 = a;
    return b;
  };
  Rule r;
  const double L = std::sqrt(2.0 * n + 1) + 1, step = 1e-3;
  double hn1 = 0, prev = h(-L, hn1);
  for (double x = -L + step; x <= L; x += step) {
    const double cur = h(x, hn1);
    if ((prev < 0) != (cur < 0)) {
      double t = x - step / 2;
      for (int it = 0; it < 50; ++it) {
        const double v = h(t, hn1);
        const double dt = v / (std::sqrt(2.0 * n) * hn1);
        t -= dt;
        if (std::abs(dt) < 1e-15) break;
      }
      h(t, hn1);
      const double d = std::sqrt(2.0 * n) * hn1;
      r.node.push_back(std::sqrt(2.0) * t);
      r.weight.push_back(2 / (d * d) / std::sqrt(kPi));
    }
    prev = cur;
  }
  return r;
}

// The equal-probability (midpoint) rule of m points: node i at the normal quantile of (i + 1/2) / m,
// weight 1 / m. Converges for any bounded integrand (it is the midpoint rule in the cumulative
// probability), without the Gauss-Hermite rule's need for a smooth one; its points are densest where
// the weight is.
Rule equal_probability(int m) {
  Rule r;
  for (int i = 0; i < m; ++i) {
    const double u = (i + 0.5) / m;
    double lo = -12, hi = 12;
    for (int it = 0; it < 200 && hi - lo > 1e-14; ++it) {
      const double mid = (lo + hi) / 2;
      (0.5 * std::erfc(-mid / std::sqrt(2.0)) < u ? lo : hi) = mid;
    }
    r.node.push_back((lo + hi) / 2);
    r.weight.push_back(1.0 / m);
  }
  return r;
}

// The library's tilt parametrisation (lee.cpp, drop_orientations).
Vec3 tilted_axis(double tx, double tz) { return glm::normalize(Vec3(std::tan(tx), 1, std::tan(tz))); }

// The elevation and position angle (radians) at which an upright drop sees what the drop of axis
// `axis` sees at (e, psi), in spheroid_section's frame: the light along L = (0, -sin e, cos e), the
// top of the bow U = (0, cos e, sin e), its right R = U x L = (1, 0, 0), the bow's point at
// cos(psi) U + sin(psi) R. For the upright drop (axis Y) the same quantities are: sin e = -Y.L, U
// the direction of Y's projection normal to L, R = U x L. The tilted drop's frame is built the same
// way from its axis (taken with the sign that makes e' >= 0: the axis is a line), and psi' is the
// bow point's angle in it; an upright drop is symmetric in R -> -R, so |psi'|. e' is held to the
// library's range (<= 89 degrees; clamped counts the weight of the nodes beyond, reported).
struct Frame {
  double elevation, position;
  bool clamped = false;
};
Frame upright_frame(Vec3 axis, double e, double psi) {
  const Vec3 L(0, -std::sin(e), std::cos(e)), U(0, std::cos(e), std::sin(e)), R(1, 0, 0);
  const Vec3 point = std::cos(psi) * U + std::sin(psi) * R;
  axis = glm::normalize(axis);
  if (glm::dot(axis, L) > 0) axis = -axis;
  Frame f{std::asin(std::min(1.0, -glm::dot(axis, L))), 0};
  const Vec3 along_sky = axis - glm::dot(axis, L) * L;
  if (glm::length(along_sky) > 1e-12) {
    const Vec3 u = glm::normalize(along_sky), r = glm::cross(u, L);
    f.position = std::abs(std::atan2(glm::dot(point, r), glm::dot(point, u)));
  }
  const double kMaxElevation = rad(89);
  if (f.elevation > kMaxElevation) {
    f.elevation = kMaxElevation;
    f.clamped = true;
  }
  return f;
}

struct Case {
  std::string shape;
  double canting_deg, elevation_deg, position_deg;
};

// The table of a case: one radius (1 mm), Airy theory of the plane section, primary bow, rows over
// 120-160 degrees (the upright bows of these cases lie at 136.8-152.3 degrees). Mode: mono, a point sun at 550 nm; spectrum, a point sun and the default spectrum
// (41 wavelengths over 380-780 nm); disk, the spectrum and the sun's disk (the defaults).
enum class Mode { mono, spectrum, disk };
atmos::LeeSpec case_spec(const Case& c, Mode mode, int rows) {
  atmos::LeeSpec s = atmos::profile_spec(atmos::LeeTableKind::rainbow, 1000, 120, 160, rows);
  s.theory = scatter::parse_theory("airy");
  s.shape = atmos::parse_drop_shape(c.shape);
  s.sun_elevation_deg = c.elevation_deg;
  s.position_deg = c.position_deg;
  s.threads = 1;
  if (mode != Mode::disk) s.sun_disk_deg = 0;
  if (mode == Mode::mono) s.wavelength_min_nm = s.wavelength_max_nm = 550;
  return s;
}

std::vector<double> luminance(const atmos::LeeTable& t) {
  std::vector<double> y(std::size_t(t.rows()));
  for (int r = 0; r < t.rows(); ++r) y[std::size_t(r)] = t.at(r, 0).Y;
  return y;
}

// The canted table's luminance per row by the product rule `rule` (for t ~ N(0, 1); scaled by the
// case's sigma), as the weighted sum of upright tables at the mapped frames. Nodes of weight below
// 1e-14 are left out (their sum is below 1e-12). clamped_weight: the weight of nodes whose e' was
// held at 89 degrees.
std::vector<double> rule_table(const Case& c, Mode mode, int rows, const Rule& rule,
                               double* clamped_weight = nullptr) {
  const double sigma = rad(c.canting_deg);
  std::vector<double> sum(std::size_t(rows), 0.0);
  double clamped = 0;
  for (std::size_t a = 0; a < rule.node.size(); ++a)
    for (std::size_t b = 0; b < rule.node.size(); ++b) {
      const double w = rule.weight[a] * rule.weight[b];
      if (w < 1e-14) continue;
      const Frame f =
          upright_frame(tilted_axis(sigma * rule.node[a], sigma * rule.node[b]), rad(c.elevation_deg), rad(c.position_deg));
      if (f.clamped) clamped += w;
      Case up = c;
      up.elevation_deg = deg(f.elevation);
      up.position_deg = std::min(180.0, deg(f.position));
      const std::vector<double> y = luminance(atmos::compute_lee_table(case_spec(up, mode, rows)));
      for (std::size_t i = 0; i < sum.size(); ++i) sum[i] += w * y[i];
    }
  if (clamped_weight) *clamped_weight = clamped;
  return sum;
}

struct Difference {
  double rms = 0, worst = 0;  // relative to the reference's RMS and peak
};
Difference difference(const std::vector<double>& a, const std::vector<double>& ref) {
  double d2 = 0, r2 = 0, worst = 0, peak = 0;
  for (std::size_t i = 0; i < ref.size(); ++i) {
    d2 += (a[i] - ref[i]) * (a[i] - ref[i]);
    r2 += ref[i] * ref[i];
    worst = std::max(worst, std::abs(a[i] - ref[i]));
    peak = std::max(peak, std::abs(ref[i]));
  }
  return {std::sqrt(d2 / r2), worst / peak};
}

TEST(CantingRule, GaussHermiteNodesAndWeights) {
  // n = 3 is the library's rule: 0, +-sqrt(3), weights 2/3, 1/6.
  const Rule r3 = gauss_hermite(3);
  ASSERT_EQ(r3.node.size(), 3u);
  EXPECT_NEAR(r3.node[0], -std::sqrt(3.0), 1e-13);
  EXPECT_NEAR(r3.node[1], 0, 1e-13);
  EXPECT_NEAR(r3.weight[0], 1.0 / 6, 1e-13);
  EXPECT_NEAR(r3.weight[1], 2.0 / 3, 1e-13);
  // n points integrate the normal moments E[t^k] = (k - 1)!! exactly up to k = 2n - 1.
  for (const int n : {9, 15, 21, 25}) {
    const Rule r = gauss_hermite(n);
    ASSERT_EQ(int(r.node.size()), n);
    for (int k = 0; k < 2 * n; k += 2) {
      double sum = 0, exact = 1;
      for (std::size_t i = 0; i < r.node.size(); ++i) sum += r.weight[i] * std::pow(r.node[i], k);
      for (int j = k - 1; j > 0; j -= 2) exact *= j;
      EXPECT_NEAR(sum / exact, 1, 1e-10) << "n " << n << " k " << k;
    }
  }
}

// The library's sampler of canted axes (atmos::canting_axes, each evaluation's nine) against the
// distribution it draws from: tilt components tx = atan(x / y), tz = atan(z / y) of the axis,
// independent normals of standard deviation sigma. With shifts uniform on the unit square each axis is
// an exact draw: one axis per random shift (the i-th shift's axis i mod 9, so that every one of the
// nine is drawn and the draws are independent), 180,000 shifts, sigma 10 and 30 degrees. Chi-square
// of each component in 20 bins of equal probability under the normal (written out through erfc), and
// of the pair in 6 x 6 such bins (independence), below the 1e-6 upper quantile (Wilson-Hilferty: 64.4
// for 19 degrees of freedom, 90.5 for 35); a sampler with tilts of 0.97 sigma moves the component's
// statistic to 310 (measured). The clamp at 89 degrees (2.97 sigma at 30) lies inside the outermost bins.
TEST(CantingRule, AxesAreNormalTilts) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> uniform(0, 1);
  const auto bin = [](double t_over_sigma, int bins) {
    const double p = 0.5 * std::erfc(-t_over_sigma / std::sqrt(2.0));
    return std::clamp(int(p * bins), 0, bins - 1);
  };
  for (const double sigma_deg : {10.0, 30.0}) {
    constexpr int kBins = 20, kJoint = 6, kShifts = 180000;
    std::vector<double> nx(kBins), nz(kBins), nj(kJoint * kJoint);
    double count = 0;
    for (int i = 0; i < kShifts; ++i) {
      const double su = uniform(rng), sv = uniform(rng);
      {
        const Vec3 a = atmos::canting_axes(sigma_deg, su, sv)[std::size_t(i % atmos::kCantingAxes)];
        ASSERT_GT(a.y, 0);
        const double tx = deg(std::atan(a.x / a.y)) / sigma_deg, tz = deg(std::atan(a.z / a.y)) / sigma_deg;
        nx[std::size_t(bin(tx, kBins))] += 1;
        nz[std::size_t(bin(tz, kBins))] += 1;
        nj[std::size_t(bin(tx, kJoint) * kJoint + bin(tz, kJoint))] += 1;
        count += 1;
      }
    }
    const auto chi2 = [&](const std::vector<double>& n) {
      const double expected = count / double(n.size());
      double c = 0;
      for (const double v : n) c += (v - expected) * (v - expected) / expected;
      return c;
    };
    const double cx = chi2(nx), cz = chi2(nz), cj = chi2(nj);
    RecordProperty("chi2_sigma_" + std::to_string(int(sigma_deg)),
                   std::to_string(cx) + " " + std::to_string(cz) + " " + std::to_string(cj));
    EXPECT_LT(cx, 64.4) << sigma_deg;
    EXPECT_LT(cz, 64.4) << sigma_deg;
    EXPECT_LT(cj, 90.5) << sigma_deg;
  }
}

// The construction of one orientation's table (upright_frame): the drop of axis A at (e, psi) and
// the upright drop at (e', psi') have the same plane section (semi-axes, and the tilt of the
// ellipse in the plane up to a half turn) and the same bow: the section's rainbow ray and the 3-D
// edge (scatter::spheroid_bow). Tilts up to 80 degrees per component (the largest node of the
// equal-probability rule of 128 points is 2.66 sigma, 80 degrees at sigma = 30). Tolerances: the
// section is the same ellipse to rounding (1e-12); the edges are found by Newton searches in
// different frames, measured to agree to 4e-14 rad (tolerance 1e-10).
TEST(CantingRule, OneOrientationIsAnUprightDropInAnotherFrame) {
  double max_edge = 0;
  const auto water = optics::find_medium("water");
  const auto air = optics::find_medium("air");
  const double n = scatter::sphere_problem(1000, 550, *water, *air).m.real();
  for (const double q : {0.95, 0.9, 0.8})
    for (const double e : {0.0, 20.0, 40.0})
      for (const double psi : {0.0, 45.0, 90.0, 135.0})
        for (const auto& [tx, tz] : std::vector<std::pair<double, double>>{
                 {0, 0}, {10, 0}, {-10, 0}, {0, 10}, {0, -10}, {30, -25}, {-45, 20}, {17, 38}, {80, 80},
                 {-70, 60}, {5, -80}}) {
          const Vec3 axis = tilted_axis(rad(tx), rad(tz));
          const Frame f = upright_frame(axis, rad(e), rad(psi));
          ASSERT_FALSE(f.clamped);
          const std::string what = "q " + std::to_string(q) + " e " + std::to_string(e) + " psi " +
                                   std::to_string(psi) + " tilt " + std::to_string(tx) + "," + std::to_string(tz);
          const scatter::EllipseSection a = scatter::spheroid_section(q, axis, rad(e), rad(psi));
          const scatter::EllipseSection b = scatter::spheroid_section(q, Vec3(0, 1, 0), f.elevation, f.position);
          EXPECT_NEAR(a.semi_u, b.semi_u, 1e-12) << what;
          EXPECT_NEAR(a.semi_v, b.semi_v, 1e-12) << what;
          EXPECT_NEAR(std::cos(2 * (a.tilt - b.tilt)), 1, 1e-12) << what;
          const auto ra = scatter::section_rainbow(n, 2, a), rb = scatter::section_rainbow(n, 2, b);
          ASSERT_EQ(ra.has_value(), rb.has_value()) << what;
          if (!ra) continue;
          EXPECT_NEAR(ra->scattering_angle, rb->scattering_angle, 1e-10) << what;
          const auto ea = scatter::spheroid_bow(n, 2, q, axis, rad(e), rad(psi), *ra);
          const auto eb = scatter::spheroid_bow(n, 2, q, Vec3(0, 1, 0), f.elevation, f.position, *rb);
          ASSERT_EQ(ea.has_value(), eb.has_value()) << what;
          if (ea) {
            EXPECT_NEAR(ea->scattering_angle, eb->scattering_angle, 1e-10) << what;
            max_edge = std::max(max_edge, std::abs(ea->scattering_angle - eb->scattering_angle));
          }
        }
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2e", max_edge);
  RecordProperty("max_edge", buf);
}

// The library's canted table against the converged reference (the equal-probability rule of
// 64 x 64 orientations over upright tables at the mapped frames; against 32 x 32 it moves by 1.0% RMS
// here, asserted 2%). The library draws nine orientations of its own for each evaluation (one radius
// at one wavelength; lee.cpp, drop_orientations), so the orientations' sampling is part of the
// table's noise, which its error estimate (even- against odd-numbered wavelengths) measures. Case:
// spheroid:0.9 at 1 mm, canting 10 degrees, sun 20 degrees up, the side of the bow (the bow moves at
// first order in one tilt component there), a point sun and the default spectrum (41 wavelengths).
// Measured: 8.6% RMS from the reference with an estimate of 8.7%; at sampling 4, 3.9% with an
// estimate of 4.0% (about as 1 / sqrt(sampling): random orientations, not a rule). The fixed 3 x 3
// Gauss-Hermite rule the library had was 21% off in this case with the sun's disk
// (ThreeByThreeRuleAgainstAConvergedReference). Asserted: the estimate within a factor of 3 of the
// error at sampling 1 and 4 (issue 39), and the error at sampling 4 below two thirds of that at 1.
TEST(CantingRule, LibraryTableIsWithinItsStatedErrorOfAConvergedReference) {
  if (HYDROLUX_TEST_ASAN) GTEST_SKIP() << "5000 tables: slow under AddressSanitizer";
  const Case c{"spheroid:0.9", 10, 20, 90};
  const int rows = 161;
  const std::vector<double> ref = rule_table(c, Mode::spectrum, rows, equal_probability(64));
  const Difference convergence = difference(rule_table(c, Mode::spectrum, rows, equal_probability(32)), ref);
  RecordProperty("reference_convergence_rms", std::to_string(convergence.rms));
  EXPECT_LT(convergence.rms, 0.02);
  double error_at_1 = 0;
  for (const double sampling : {1.0, 4.0}) {
    atmos::LeeSpec spec = case_spec(c, Mode::spectrum, rows);
    spec.canting_deg = c.canting_deg;
    spec.sampling = sampling;
    const atmos::LeeTable lib = atmos::compute_lee_table(spec);
    ASSERT_TRUE(lib.error.luminance_rms.has_value());
    const double error = difference(luminance(lib), ref).rms, estimate = *lib.error.luminance_rms;
    RecordProperty("error_at_sampling_" + std::to_string(int(sampling)), std::to_string(error));
    RecordProperty("estimate_at_sampling_" + std::to_string(int(sampling)), std::to_string(estimate));
    EXPECT_GT(estimate, error / 3) << "sampling " << sampling;
    EXPECT_LT(estimate, error * 3) << "sampling " << sampling;
    if (sampling == 1)
      error_at_1 = error;
    else
      EXPECT_LT(error, error_at_1 * 2 / 3);
  }
}

// Why a 3-point rule cannot average canting: the bow moves at FIRST order in the tilt wherever the
// scattering plane is not normal to the tilt's axis of rotation (lee.cpp assumes the shift "smooth,
// near quadratic"). At the top of the bow with the sun on the horizon (e = 0, psi = 0) a tilt tz
// towards the light turns the drop within the scattering plane, a plane of symmetry, where the
// section is exact: its long axis then makes the angle h = -tz with the light, and Moebius's
// first-order shift Delta rho = K (1 - Q) cos 2(h - rho / 2) (K = -131.75 degrees for the primary:
// derived and checked in tests/scatter/test_claims_section_3d.cpp, MoebiusFirstOrder) gives
// d theta / d tz = 2 K (1 - Q) sin(rho) (degrees per radian), rho = 180 - theta_D the Descartes
// bow's radius. At Q = 0.99 the library's edge (central difference over +-0.5 degrees) agrees
// within 3% (the second order in 1 - Q is ~1.5% here). At Q = 0.9 the slope is -0.35 degrees of bow per
// degree of tilt (asserted beyond -0.25; the first-order value is -0.31): a canting of
// sigma = 10 degrees spreads the bow over ~3.5 degrees (1 sigma), against the primary's width of
// ~0.5 degree at 1 mm, and the rule's nodes at +-sqrt(3) sigma put three images of the bow 6
// degrees apart.
TEST(CantingRule, BowMovesAtFirstOrderInTheTilt) {
  const auto water = optics::find_medium("water");
  const auto air = optics::find_medium("air");
  const double n = scatter::sphere_problem(1000, 550, *water, *air).m.real();
  const auto bow_angle = [&](double q, double tz_deg) {
    const Vec3 axis = tilted_axis(0, rad(tz_deg));
    const auto sec = scatter::section_rainbow(n, 2, scatter::spheroid_section(q, axis, 0, 0));
    EXPECT_TRUE(sec.has_value());
    const auto edge = scatter::spheroid_bow(n, 2, q, axis, 0, 0, *sec);
    EXPECT_TRUE(edge.has_value());
    return deg(edge ? edge->scattering_angle : 0.0);
  };
  // Descartes' primary: sin i = sqrt((4 - n^2) / 3), theta_D = 180 + 2 i - 4 r (degrees).
  const double i = std::asin(std::sqrt((4 - n * n) / 3)), r = std::asin(std::sin(i) / n);
  const double rho = kPi - (kPi + 2 * i - 4 * r);
  const double K = -131.75;
  const double q = 0.99;
  const double slope = (bow_angle(q, 0.5) - bow_angle(q, -0.5)) / 1.0;  // degrees per degree
  const double theory = 2 * K * (1 - q) * std::sin(rho) * kPi / 180;
  const double slope_09 = (bow_angle(0.9, 0.5) - bow_angle(0.9, -0.5)) / 1.0;
  RecordProperty("slope_q099", std::to_string(slope));
  RecordProperty("first_order_q099", std::to_string(theory));
  RecordProperty("slope_q09", std::to_string(slope_09));
  EXPECT_NEAR(slope, theory, 0.03 * std::abs(theory));
  EXPECT_LT(slope_09, -0.25);
}

// Why the library no longer uses a fixed rule: the 3 x 3 Gauss-Hermite product rule (nodes 0,
// +-sqrt(3) sigma per tilt component, weights 2/3, 1/6, 1/6; the library's rule until issue 39)
// against the converged reference, with a point sun at 550 nm (the cheapest table, 0.15 ms),
// spheroid:0.95 at 1 mm, sun on the horizon, the side of the bow (psi = 90), canting 5 degrees: the
// most favourable case of the survey (the bow's shift is quadratic in both tilts there). The
// reference, the equal-probability rule of 64 x 64 points, agrees with 32 x 32 to 1.0% RMS here
// (asserted 2%; 128 x 128 against 64 x 64: 0.3%). The 3 x 3 rule differs from it by 18% RMS of the
// table (worst row 10% of the peak), asserted above 10% (docs/non-spherical.md, "Canting").
TEST(CantingRule, ThreeByThreeRuleAgainstAConvergedReference) {
  if (HYDROLUX_TEST_ASAN) GTEST_SKIP() << "5000 tables: slow under AddressSanitizer";
  const Case c{"spheroid:0.95", 5, 0, 90};
  const int rows = 161;
  const std::vector<double> fixed = rule_table(c, Mode::mono, rows, gauss_hermite(3));
  const std::vector<double> ref = rule_table(c, Mode::mono, rows, equal_probability(64));
  const std::vector<double> coarse = rule_table(c, Mode::mono, rows, equal_probability(32));
  const Difference convergence = difference(coarse, ref), rule = difference(fixed, ref);
  RecordProperty("reference_convergence_rms", std::to_string(convergence.rms));
  RecordProperty("rule_error_rms", std::to_string(rule.rms));
  RecordProperty("rule_error_worst", std::to_string(rule.worst));
  EXPECT_LT(convergence.rms, 0.02);
  EXPECT_GT(rule.rms, 0.10);
}

// The survey behind docs/non-spherical.md's paragraph on canting: every case, the library's canted
// table (at CANTING_SAMPLING, default 1) and with CANTING_OTHER_RULES fixed rules against the equal-probability rule of M x M points, and M / 2 against M
// (the reference's convergence). Slow (minutes): run with --gtest_also_run_disabled_tests
// --gtest_filter='*Survey*'; CANTING_MODE = mono | spectrum | disk, CANTING_M (default 128),
// CANTING_SHAPE, CANTING_CANTING, CANTING_CORNERS (positions 0 and 90 only) to restrict the cases;
// CANTING_OTHER_RULES also measures other rules.
TEST(CantingRule, DISABLED_Survey) {
  const char* mode_env = std::getenv("CANTING_MODE");
  const std::string mode_name = mode_env ? mode_env : "mono";
  const Mode mode = mode_name == "disk" ? Mode::disk : mode_name == "spectrum" ? Mode::spectrum : Mode::mono;
  const int m = std::getenv("CANTING_M") ? std::atoi(std::getenv("CANTING_M")) : 128;
  const char* shape_env = std::getenv("CANTING_SHAPE");
  const char* canting_env = std::getenv("CANTING_CANTING");
  const Rule r3 = gauss_hermite(3), fine = equal_probability(m), half = equal_probability(m / 2);
  for (const std::string shape : {"spheroid:0.95", "spheroid:0.9", "beard-chuang"})
    for (const double canting : {5.0, 10.0, 20.0, 30.0})
      for (const double elevation : {0.0, 20.0})
        for (const double position : {0.0, 45.0, 90.0}) {
          if (shape_env && shape != shape_env) continue;
          if (canting_env && canting != std::atof(canting_env)) continue;
          if (std::getenv("CANTING_CORNERS") && position == 45) continue;
          const Case c{shape, canting, elevation, position};
          const int rows = 161;
          atmos::LeeSpec spec = case_spec(c, mode, rows);
          spec.canting_deg = canting;
          if (std::getenv("CANTING_SAMPLING")) spec.sampling = std::atof(std::getenv("CANTING_SAMPLING"));
          const atmos::LeeTable lib = atmos::compute_lee_table(spec);
          const std::vector<double> y_lib = luminance(lib);
          double clamped = 0;
          const std::vector<double> ref = rule_table(c, mode, rows, fine, &clamped);
          const std::vector<double> ref_half = rule_table(c, mode, rows, half);
          const Difference rule = difference(y_lib, ref), conv = difference(ref_half, ref);
          std::printf("%-8s %-13s cant %4.0f e %3.0f psi %3.0f | library rms %.4f worst %.4f | M/2 vs M=%d rms %.4f worst %.4f | "
                      "clamped %.1e | table err %s\n",
                      mode_name.c_str(), shape.c_str(), canting, elevation, position, rule.rms, rule.worst, m, conv.rms,
                      conv.worst, clamped,
                      lib.error.luminance_rms ? std::to_string(*lib.error.luminance_rms).c_str() : "-");
          if (std::getenv("CANTING_OTHER_RULES")) {
            // Fixed rules: Gauss-Hermite 3 x 3 (the library's until issue 39), 5 x 5, 9 x 9 and
            // equal-probability 16 x 16, 32 x 32 against the reference.
            std::printf("    other rules rms:");
            for (const auto& [name, r] : std::vector<std::pair<std::string, Rule>>{
                     {"GH3", r3}, {"GH5", gauss_hermite(5)}, {"GH9", gauss_hermite(9)}, {"EP16", equal_probability(16)},
                     {"EP32", equal_probability(32)}})
              std::printf(" %s %.4f", name.c_str(), difference(rule_table(c, mode, rows, r), ref).rms);
            std::printf("\n");
          }
          std::fflush(stdout);
        }
}

}  // namespace
}  // namespace hydrolux
