// docs/fog.md l. 46-52: the fog's phase function from 64 radii (Gauss-Legendre in ln r) leaves
// the Mie ripple at single angles but not in what the glow uses (the apparent phase's cumulative
// and g). The reference is a size average by a different rule, written in this file: the modified
// gamma density of Shettle & Fenn, n(r) ~ r^alpha exp(-alpha r / r_mode), written out (not the
// library's distribution), summed by the midpoint rule on radii evenly spaced in the size
// parameter (steps of 0.25, which resolve the beat of the rays through the drop, period
// pi / (p m) ~ 0.6 in x for p = 4 chords), from 0 to 8 mode radii (the tail beyond holds ~1e-6
// of the scattered light). The integrand, one radius's |S1|^2 + |S2|^2 and Q_sca g, is the
// library's Mie (checked against mpmath and MIEV0 in tests/scatter/test_mie.cpp); the quadrature is
// what is under test. The table and the apparent transform are the library's PhaseTable (checked in
// Fog.ApparentPhaseFunction against Henyey-Greenstein in closed form).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <numbers>
#include <vector>

#include "hydrolux/rain/fog.hpp"
#include "hydrolux/scatter/amplitudes.hpp"
#include "hydrolux/scatter/mie.hpp"
#include "support/asan.hpp"

namespace hydrolux::rain {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kWater = 1.333;  // the fog's index (fog.cpp), real: the albedo is 1

struct Reference {
  std::vector<double> p;  // sum of n(r) dr (|S1|^2 + |S2|^2) at u_i = i / (angles - 1)
  double g = 0;
};

Reference midpoint_reference(double mode_um, double alpha, double wavelength_nm, int angles, double dx) {
  const double k = 2 * kPi / (wavelength_nm * 1e-3);  // per um
  const double x_max = 8 * mode_um * k;
  std::vector<double> mu(static_cast<std::size_t>(angles));
  for (int i = 0; i < angles; ++i) {
    const double u = double(i) / (angles - 1);
    mu[static_cast<std::size_t>(i)] = 1 - 2 * u * u;
  }
  std::vector<scatter::Complex> s1(mu.size()), s2(mu.size());
  Reference ref;
  ref.p.assign(mu.size(), 0.0);
  double csca = 0, cg = 0;
  scatter::MieCoefficients c;
  for (double x = dx / 2; x < x_max; x += dx) {
    const double r = x / k;
    const double w = std::pow(r / mode_um, alpha) * std::exp(-alpha * (r / mode_um - 1));
    scatter::mie_coefficients({kWater, 0.0}, x, c);
    const scatter::MieEfficiencies e = scatter::mie_efficiencies(c);
    csca += w * e.qsca * r * r;
    cg += w * e.qsca * r * r * e.g;
    scatter::mie_amplitudes(c, mu, s1, s2, 1);
    for (std::size_t i = 0; i < mu.size(); ++i) ref.p[i] += w * (std::norm(s1[i]) + std::norm(s2[i]));
  }
  ref.g = cg / csca;
  return ref;
}

// The library's 64-radius table (fog_optics' default) against the reference on the same 1025
// values of u. Measured: the apparent cumulative within 0.17% (mode 4 um) and 0.42% (10 um) of the
// total, g 0.26% and 0.32% high, the phase itself up to 44% and 48% off (u = 0.91 and 0.05).
// Asserted: the cumulative within 0.45% and g within 0.35% (the page's figures; the reference's own
// g moves by 2e-4 between steps of 0.5, 0.25, 0.1 and 0.05 in x, its cumulative by 1e-5, since
// resonances narrower than the step are sampled as if at random), and the worst single value
// 40-55% off for 10 um (the page's "up to 48%": the ripple is really left at single angles).
TEST(ClaimsFogPhase, SixtyFourRadiiKeepTheGlowsCumulativeAndG) {
  if (HYDROLUX_TEST_ASAN) GTEST_SKIP() << "~6000 Mie solutions at 1025 angles: slow under ASan";
  for (const double mode_um : {4.0, 10.0}) {
    SCOPED_TRACE(mode_um);
    FogSettings s;
    s.visibility_m = 100;
    s.mode_radius_um = mode_um;
    const int angles = 1025;
    const FogOptics o = fog_optics(s, angles, 64);
    const Reference ref = midpoint_reference(mode_um, s.size_alpha, s.wavelength_nm, angles, 0.25);
    const PhaseTable table = PhaseTable::from_values(ref.p);
    const PhaseTable app = table.apparent();
    ASSERT_EQ(app.cum.size(), o.apparent.cum.size());
    double worst_cum = 0, worst_p = 0;
    for (std::size_t i = 0; i < app.cum.size(); ++i)
      worst_cum = std::max(worst_cum, std::abs(o.apparent.cum[i] - app.cum[i]));
    for (std::size_t i = 0; i < table.p.size(); ++i)
      worst_p = std::max(worst_p, std::abs(o.phase.p[i] / table.p[i] - 1));
    EXPECT_LT(worst_cum, 0.0045);
    EXPECT_NEAR(o.g / ref.g, 1, 0.0035);
    if (mode_um == 10.0) {
      EXPECT_GT(worst_p, 0.40);
      EXPECT_LT(worst_p, 0.55);
    }
    std::printf("mode %g um: apparent cumulative %.2e, g %.5f (reference %.5f), worst value %.3f\n",
                mode_um, worst_cum, o.g, ref.g, worst_p);
  }
}

}  // namespace
}  // namespace hydrolux::rain
