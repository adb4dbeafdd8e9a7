// Geometric optics with interference: rainbow angles, ray finding, Fresnel energy bookkeeping,
// the geometric cross-section, closed forms for p = 0 and p = 1, and Fraunhofer diffraction.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <vector>

#include "hydrolux/core/error.hpp"
#include "hydrolux/core/math.hpp"
#include "hydrolux/scatter/geometric.hpp"
#include "support/stats.hpp"

namespace hydrolux::scatter {
namespace {

constexpr double kPiD = kPi<double>;

double rad(double deg) { return deg_to_rad(deg); }
double deg(double r) { return rad_to_deg(r); }

// Hecht's amplitude ratios for light from air into a real index n (Hecht, Optics, 5th ed.,
// eqs. 4.34, 4.40), written out here independently of optics/fresnel.hpp.
struct Hecht {
  double rs, rp, ts, tp, cos_t;
};
Hecht hecht(double n, double theta_i) {
  const double ci = std::cos(theta_i), st = std::sin(theta_i) / n, ct = std::sqrt(1 - st * st);
  return {(ci - n * ct) / (ci + n * ct), (n * ci - ct) / (n * ci + ct), 2 * ci / (ci + n * ct),
          2 * ci / (n * ci + ct), ct};
}

// Gauss-Legendre on [a, b] after theta = a + (b - a)(1 - cos(pi s))/2: the substitution turns
// the integrable 1/sqrt singularity of a caustic (the rainbow angle) and the sqrt kink where a
// branch of rays ends (the grazing ray) at either endpoint into smooth integrands, and keeps every
// node well away from the endpoints, where the rays merge. 400 nodes give ~1e-10 here.
double smooth_ends(const std::function<double(double)>& f, double a, double b, int nodes = 400) {
  const auto q = test::gauss_legendre(nodes, 0.0, 1.0);
  double sum = 0;
  for (std::size_t i = 0; i < q.x.size(); ++i) {
    const double s = q.x[i];
    const double t = a + 0.5 * (b - a) * (1 - std::cos(kPiD * s));
    sum += q.w[i] * f(t) * 0.5 * (b - a) * kPiD * std::sin(kPiD * s);
  }
  return sum;
}

// ---------------------------------------------------------------------------------------------
// Rainbow angles
// ---------------------------------------------------------------------------------------------

// The primary rainbow of water (n = 1.333) has a 42.08 degree radius about the antisolar point,
// i.e. a 137.92 degree scattering angle (Descartes' minimum deviation; van de Hulst 1957 section
// 13.1; the value quoted for n = 1.333 in the rainbow literature, e.g. Lee 1998). The tolerance
// 0.005 degrees is the rounding of the quoted digits.
TEST(Rainbow, PrimaryOfWaterAt42Degrees) {
  const double theta = rainbow_angle(1.333, 2);
  EXPECT_NEAR(deg(theta), 137.92, 0.005);
  EXPECT_NEAR(180 - deg(theta), 42.08, 0.005);
  EXPECT_EQ(rainbow_ray(1.333, 2).side, 1);
}

// The secondary (p = 3) is about 50.9 degrees from the antisolar point (129.1 degree scattering
// angle), on the other side of Alexander's dark band; 0.05 degrees is the rounding of "50.9".
TEST(Rainbow, SecondaryOfWaterAt51Degrees) {
  const double theta = rainbow_angle(1.333, 3);
  EXPECT_NEAR(180 - deg(theta), 50.9, 0.05);
  EXPECT_EQ(rainbow_ray(1.333, 3).side, -1);  // theta = 2 pi - Theta: lit side at smaller theta
}

// Descartes' ray is the minimum of the deviation computed ray by ray: a golden-section search on
// Theta_p(theta_i) finds the same incidence (to 1e-7 rad: the minimum is quadratic, so the search
// resolves theta_i only to ~sqrt(machine epsilon)) and the same deviation (to 1e-12 rad).
TEST(Rainbow, DescartesRayIsTheMinimumOfTheComputedDeviation) {
  for (double n : {1.31, 1.333, 1.34, 1.5}) {
    for (int p : {2, 3, 4, 5}) {
      double a = 0, b = kPiD / 2;
      const double g = (std::sqrt(5.0) - 1) / 2;
      for (int it = 0; it < 200 && b - a > 1e-15; ++it) {
        const double c = b - g * (b - a), d = a + g * (b - a);
        if (deviation(n, p, c) < deviation(n, p, d))
          b = d;
        else
          a = c;
      }
      const double ti = 0.5 * (a + b);
      const RainbowRay rb = rainbow_ray(n, p);
      EXPECT_NEAR(rb.theta_i, ti, 1e-7) << n << " " << p;
      EXPECT_NEAR(rb.deviation, deviation(n, p, ti), 1e-12) << n << " " << p;
      EXPECT_NEAR(deviation_derivative(n, p, rb.theta_i), 0.0, 1e-12);
      // the folded scattering angle
      const double t = std::fmod(rb.deviation, 2 * kPiD);
      EXPECT_NEAR(rb.scattering_angle, t <= kPiD ? t : 2 * kPiD - t, 1e-14);
    }
  }
}

// van de Hulst's h (section 13.21): half the second derivative of the deviation with respect to
// the impact parameter b = sin theta_i at the rainbow ray. Central second differences at steps
// 2h and h, Richardson-extrapolated (truncation O(h^4) ~ 1e-13; rounding ~ eps Theta / h^2 ~ 1e-7
// for h = 1e-4): tolerance 1e-6 relative.
TEST(Rainbow, CurvatureIsHalfTheSecondDerivativeInImpactParameter) {
  for (double n : {1.333, 1.5}) {
    for (int p : {2, 3, 6}) {
      const RainbowRay rb = rainbow_ray(n, p);
      const double h = 1e-4, b = rb.impact_parameter;
      auto dev_b = [&](double bb) { return deviation(n, p, std::asin(bb)); };
      auto d2 = [&](double step) {
        return (dev_b(b + step) - 2 * dev_b(b) + dev_b(b - step)) / (step * step);
      };
      const double second = (4 * d2(h) - d2(2 * h)) / 3;
      EXPECT_NEAR(rb.curvature, 0.5 * second, 1e-6 * rb.curvature) << n << " " << p;
    }
  }
}

TEST(Rainbow, DerivativeMatchesFiniteDifferences) {
  for (int p = 0; p <= 6; ++p)
    for (double ti = 0.05; ti < 1.55; ti += 0.1) {
      const double h = 1e-6;
      const double fd = (deviation(1.333, p, ti + h) - deviation(1.333, p, ti - h)) / (2 * h);
      EXPECT_NEAR(deviation_derivative(1.333, p, ti), fd, 1e-8) << p << " " << ti;
    }
}

TEST(Rainbow, DomainErrors) {
  EXPECT_THROW(rainbow_angle(1.333, 1), DomainError);  // no rainbow for p < 2
  EXPECT_THROW(rainbow_angle(2.5, 2), DomainError);    // n >= p: deviation is monotonic
  EXPECT_THROW(rainbow_angle(1.0, 2), DomainError);
  EXPECT_THROW(rainbow_angle(std::nan(""), 2), DomainError);
}

// ---------------------------------------------------------------------------------------------
// Ray finding
// ---------------------------------------------------------------------------------------------

// Every ray returned reaches the requested angle (Theta = +-theta mod 2 pi to 1e-12 rad), and the
// number of rays equals the number of solutions found by brute force: sign changes of the folded
// scattering angle minus theta, counted on 2e5 incidences per order.
TEST(Rays, EveryRayReachesTheAngleAndNoneIsMissed) {
  const double n = 1.333;
  const Complex m(n, 0);
  for (int p = 0; p <= 6; ++p) {
    // brute-force scan of the folded scattering angle along theta_i
    const int steps = 200000;
    std::vector<double> folded(steps + 1);
    for (int k = 0; k <= steps; ++k) {
      const double t = std::fmod(
          std::fmod(deviation(n, p, 0.5 * kPiD * k / steps), 2 * kPiD) + 2 * kPiD, 2 * kPiD);
      folded[k] = t <= kPiD ? t : 2 * kPiD - t;
    }
    for (double theta_deg = 2.5; theta_deg < 180; theta_deg += 5) {
      const double theta = rad(theta_deg);
      int expected = 0;
      for (int k = 0; k < steps; ++k)
        if ((folded[k] - theta) * (folded[k + 1] - theta) < 0) ++expected;
      const auto rays = geometric_rays(m, 100.0, p, theta);
      EXPECT_EQ(static_cast<int>(rays.size()), expected) << "p " << p << " theta " << theta_deg;
      for (const auto& r : rays) {
        const double d = r.deviation;
        const double err = std::min(std::abs(std::remainder(d - theta, 2 * kPiD)),
                                    std::abs(std::remainder(d + theta, 2 * kPiD)));
        EXPECT_LT(err, 1e-12) << p << " " << theta_deg;
        EXPECT_NEAR(std::sin(r.theta_i), n * std::sin(r.theta_t), 1e-15);
      }
    }
  }
}

// Ray counts of the primary: none on the dark side (theta < theta_R), two between theta_R and the
// grazing ray's Theta_2(pi/2) = 360 - 4 theta_c degrees (165.6 degrees, theta_c the critical
// angle), one beyond; the two branches straddle the rainbow ray.
TEST(Rays, PrimaryHasTwoBranches) {
  const Complex m(1.333, 0);
  const RainbowRay rb = rainbow_ray(1.333, 2);
  const double grazing = deg(deviation(1.333, 2, kPiD / 2));
  EXPECT_NEAR(grazing, 360 - 4 * deg(std::asin(1 / 1.333)), 1e-12);
  EXPECT_TRUE(geometric_rays(m, 100, 2, rad(137)).empty());
  const auto two = geometric_rays(m, 100, 2, rad(150));
  ASSERT_EQ(two.size(), 2u);
  EXPECT_LT(two[0].theta_i, rb.theta_i);
  EXPECT_GT(two[1].theta_i, rb.theta_i);
  // The outer branch touches the rainbow caustic once more: one more focal line.
  EXPECT_EQ(two[1].focal_lines, two[0].focal_lines + 1);
  EXPECT_EQ(geometric_rays(m, 100, 2, rad(170)).size(), 1u);
}

// ---------------------------------------------------------------------------------------------
// Energy
// ---------------------------------------------------------------------------------------------

// Without interference every ray's power goes somewhere: R + T T' sum_{p>=1} R'^(p-1) = 1, per
// polarisation, since R' = R and T' = T = 1 - R (Stokes; van de Hulst section 12.21). The partial
// sum to order P is exactly 1 - (1 - R) R^P; the ray factors are products of O(P) terms, so 1e-13.
TEST(Energy, FresnelFractionsOfAllOrdersSumToOne) {
  for (Complex m : {Complex(1.333, 0), Complex(1.5, 0), Complex(2.4, 0)})
    for (double ti_deg = 0; ti_deg <= 89.5; ti_deg += 0.5) {
      const double ti = rad(ti_deg);
      const auto r0 = ray_fresnel_factors(m, 0, ti);
      const double rs = std::norm(r0.perpendicular), rp = std::norm(r0.parallel);
      double sum_s = 0, sum_p = 0;
      const int orders = 60;
      for (int p = 0; p <= orders; ++p) {
        const auto e = ray_fresnel_factors(m, p, ti);
        sum_s += std::norm(e.perpendicular);
        sum_p += std::norm(e.parallel);
        EXPECT_NEAR(e.perpendicular.imag(), 0.0, 1e-15);  // real for a real index
      }
      EXPECT_NEAR(sum_s, 1 - (1 - rs) * std::pow(rs, orders), 1e-13) << ti_deg;
      EXPECT_NEAR(sum_p, 1 - (1 - rp) * std::pow(rp, orders), 1e-13) << ti_deg;
      if (ti_deg <= 60) {  // R^60 < 1e-14 up to 60 degrees for these indices
        EXPECT_NEAR(sum_s, 1.0, 2e-12) << ti_deg;
        EXPECT_NEAR(sum_p, 1.0, 2e-12) << ti_deg;
      }
    }
}

// Integrating the geometric-optics intensity over the sphere gives the geometric cross-section:
// (1 / (pi x^2)) int |S_j|^2 dOmega summed over all rays of order p equals
// 2 int_0^(pi/2) eps_p^2 sin(theta_i) cos(theta_i) dtheta_i (the share of pi a^2 that order p
// carries), and the orders together give 1 (Q_sca = 1 without diffraction; van de Hulst 12.21).
// The left side integrates over theta the rays the library finds, with its D: a test of the
// divergence factor and of the ray finding (no ray missed or counted twice). Quadrature on the
// pieces between the rainbow angle and the grazing ray's angle, where the integrand has
// 1/sqrt singularities or kinks (smooth_ends above); its error is ~1e-10, the tolerance 1e-8.
TEST(Energy, GeometricIntensityIntegratesToTheGeometricCrossSection) {
  const double n = 1.333, x = 1000;
  const Complex m(n, 0);
  const int orders = 12;
  double total_s = 0, total_p = 0;
  for (int p = 0; p <= orders; ++p) {
    std::vector<double> cuts = {0.0, kPiD};
    if (p >= 2) cuts.push_back(rainbow_angle(n, p));
    const double g = std::fmod(deviation(n, p, kPiD / 2) + 4 * kPiD, 2 * kPiD);
    cuts.push_back(g <= kPiD ? g : 2 * kPiD - g);
    std::sort(cuts.begin(), cuts.end());
    double sum_s = 0, sum_p = 0;
    for (std::size_t k = 0; k + 1 < cuts.size(); ++k) {
      if (cuts[k + 1] - cuts[k] < 1e-12) continue;
      for (int pol = 0; pol < 2; ++pol) {
        const double v = smooth_ends(
            [&](double theta) {
              double s = 0;
              for (const auto& r : geometric_rays(m, x, p, theta))
                s += std::norm(pol == 0 ? r.s1 : r.s2);
              return s / (x * x) * std::sin(theta);
            },
            cuts[k], cuts[k + 1]);
        (pol == 0 ? sum_s : sum_p) += 2 * v;  // (1/(pi x^2)) 2 pi int ... sin theta dtheta
      }
    }
    auto share = [&](bool perpendicular) {
      return 2 * smooth_ends(
                     [&](double ti) {
                       const auto e = ray_fresnel_factors(m, p, ti);
                       return std::norm(perpendicular ? e.perpendicular : e.parallel) *
                              std::sin(ti) * std::cos(ti);
                     },
                     0, kPiD / 2);
    };
    EXPECT_NEAR(sum_s, share(true), 1e-8) << "p = " << p;
    EXPECT_NEAR(sum_p, share(false), 1e-8) << "p = " << p;
    total_s += sum_s;
    total_p += sum_p;
  }
  // What orders > 12 carry: 2 int (1 - R) R^12 sin cos dtheta_i (the partial sums above).
  auto tail = [&](bool perpendicular) {
    return 2 * smooth_ends(
                   [&](double ti) {
                     const auto r = ray_fresnel_factors(m, 0, ti);
                     const double R = std::norm(perpendicular ? r.perpendicular : r.parallel);
                     return (1 - R) * std::pow(R, orders) * std::sin(ti) * std::cos(ti);
                   },
                   0, kPiD / 2);
  };
  EXPECT_NEAR(total_s + tail(true), 1.0, 1e-7);
  EXPECT_NEAR(total_p + tail(false), 1.0, 1e-7);
  EXPECT_GT(tail(true), 1e-5);  // the tail is not negligible: the bookkeeping needs it
}

// ---------------------------------------------------------------------------------------------
// Amplitudes against closed forms
// ---------------------------------------------------------------------------------------------

// p = 0, external reflection (van de Hulst section 12.31, in B&H normalisation): theta_i =
// (pi - theta)/2, D = 1/4, no focal line, path -2 x cos theta_i, and B&H's 1/(-ikr) gives -i:
//   S_j = -i (x/2) r_j exp(-2 i x cos theta_i),
// so |S_j|^2 = x^2 R_j / 4 at every angle. Checked against exact Mie theory offline (m = 1.333 +
// 0.1i, where only reflection and diffraction survive; x = 1000 to 16000, 100-170 degrees: complex
// S1 and S2 agree to 5e-4 rad). Tolerance: relative 1e-12, the rounding of a phase ~2x = 1000 rad.
TEST(Amplitudes, ExternalReflectionClosedForm) {
  const double x = 500;
  for (double n : {1.333, 1.5})
    for (double theta_deg : {20.0, 60.0, 90.0, 137.0, 170.0, 180.0}) {
      const double theta = rad(theta_deg), ti = 0.5 * (kPiD - theta);
      const Hecht h = hecht(n, ti);
      const Complex common = Complex(0, -0.5 * x) * std::exp(Complex(0, -2 * x * std::cos(ti)));
      Complex s1, s2;
      const double t[1] = {theta};
      geometric_amplitudes_order(Complex(n, 0), x, 0, t, {&s1, 1}, {&s2, 1});
      EXPECT_NEAR(std::abs(s1 - h.rs * common), 0.0, 1e-12 * x) << theta_deg;
      EXPECT_NEAR(std::abs(s2 - h.rp * common), 0.0, 1e-12 * x) << theta_deg;
      EXPECT_NEAR(std::norm(s1), x * x * h.rs * h.rs / 4, 1e-10 * x * x);
    }
  // Backscattering: S1(pi) = -S2(pi), as Mie's pi_n(-1) = -tau_n(-1) demands.
  Complex s1, s2;
  const double t[1] = {kPiD};
  geometric_amplitudes(Complex(1.333, 0), 300, 6, t, {&s1, 1}, {&s2, 1}, false);
  EXPECT_NEAR(std::abs(s1 + s2), 0.0, 1e-12 * std::abs(s1));
}

// p = 1, transmission straight through: for a chosen theta_i the angle is theta = 2 (theta_i -
// theta_t) in closed form, D = sin ti cos ti / (sin theta |2 - 2 cos ti / (n cos tt)|), path
// 2 x (n cos tt - cos ti), and two focal lines (the tangential one, outside or inside the drop,
// and the crossing of the axis), so with B&H's -i: (-i)^3 = +i,
//   S_j = i x t_j t'_j sqrt(D) exp(2 i x (n cos tt - cos ti)),   t t' = 1 - r^2.
// Checked against exact Mie theory offline (x = 1000-16000, 10-75 degrees: coherence 0.99,
// magnitude within 1%, phase within 0.02 rad). Tolerance 1e-9 relative: Newton's theta_i to ~1e-15
// times dphase/dtheta_i ~ x.
TEST(Amplitudes, TransmissionClosedForm) {
  const double x = 800;
  for (double n : {1.333, 1.5})
    for (double ti_deg : {10.0, 30.0, 50.0, 70.0, 85.0}) {
      const double ti = rad(ti_deg);
      const Hecht h = hecht(n, ti);
      const double tt = std::asin(std::sin(ti) / n);
      const double theta = 2 * (ti - tt);
      const double d = std::sin(ti) * std::cos(ti) /
                       (std::sin(theta) * std::abs(2 - 2 * std::cos(ti) / (n * std::cos(tt))));
      const Complex common = Complex(0, x * std::sqrt(d)) *
                             std::exp(Complex(0, 2 * x * (n * std::cos(tt) - std::cos(ti))));
      const auto rays = geometric_rays(Complex(n, 0), x, 1, theta);
      ASSERT_EQ(rays.size(), 1u);
      EXPECT_EQ(rays[0].focal_lines, 2);
      EXPECT_NEAR(rays[0].theta_i, ti, 1e-13);
      EXPECT_NEAR(rays[0].divergence, d, 1e-12 * d);
      const Complex e1 = (1 - h.rs * h.rs) * common, e2 = (1 - h.rp * h.rp) * common;
      EXPECT_NEAR(std::abs(rays[0].s1 - e1), 0.0, 1e-9 * std::abs(e1)) << ti_deg;
      EXPECT_NEAR(std::abs(rays[0].s2 - e2), 0.0, 1e-9 * std::abs(e2)) << ti_deg;
      // Hecht's t t' = 1 - r^2 for both polarisations (Stokes)
      const double ts_back = 2 * n * std::cos(tt) / (n * std::cos(tt) + std::cos(ti));
      EXPECT_NEAR(h.ts * ts_back, 1 - h.rs * h.rs, 1e-14);
    }
}

// The central rays on the axis: p = 1 at theta = 0 with D = 1 / (2 - 2/n)^2, the limit of
// sin ti / sin theta; S1(0) = S2(0) as Mie requires; p = 2 at theta = pi with S1 = -S2.
TEST(Amplitudes, CentralRaysOnTheAxis) {
  const double n = 1.333, x = 200;
  const double t0[1] = {0.0}, tpi[1] = {kPiD};
  Complex s1, s2;
  geometric_amplitudes_order(Complex(n, 0), x, 1, t0, {&s1, 1}, {&s2, 1});
  const double d0 = 1 / sqr(2 - 2 / n), tt = 4 * n / sqr(1 + n);
  EXPECT_NEAR(std::abs(s1), x * tt * std::sqrt(d0), 1e-12 * x);
  EXPECT_NEAR(std::abs(s1 - s2), 0.0, 1e-12 * x);
  // continuity: a small angle off the axis gives nearly the same ray
  const double t_small[1] = {1e-5};
  Complex u1, u2;
  geometric_amplitudes_order(Complex(n, 0), x, 1, t_small, {&u1, 1}, {&u2, 1});
  EXPECT_NEAR(std::abs(u1), std::abs(s1), 1e-6 * std::abs(s1));
  geometric_amplitudes_order(Complex(n, 0), x, 2, tpi, {&s1, 1}, {&s2, 1});
  EXPECT_GT(std::abs(s1), 0.0);
  EXPECT_NEAR(std::abs(s1 + s2), 0.0, 1e-12 * x);
}

// The ray's power: |S_j|^2 = x^2 eps_j^2 D for every ray, whatever its phase.
TEST(Amplitudes, IntensityIsSizeSquaredTimesFresnelTimesDivergence) {
  const Complex m(1.333, 0);
  for (int p = 0; p <= 5; ++p)
    for (double theta_deg = 3; theta_deg < 180; theta_deg += 7)
      for (const auto& r : geometric_rays(m, 300, p, rad(theta_deg))) {
        const auto e = ray_fresnel_factors(m, p, r.theta_i);
        EXPECT_NEAR(std::norm(r.s1), 9e4 * std::norm(e.perpendicular) * r.divergence,
                    1e-12 * 9e4 * r.divergence);
        if (p == 0) {
          EXPECT_NEAR(r.divergence, 0.25, 1e-14);
        }
      }
}

// Absorption: every chord of length 2 a cos theta_t attenuates the amplitude by
// exp(-2 x k cos theta_t) (van de Hulst section 14.2). Offline against Mie (x = 1000-16000,
// k = 1/x): the p = 1 contribution agrees in magnitude to ~5%.
TEST(Amplitudes, AbsorptionAttenuatesEachChord) {
  const double x = 1000, k = 1e-3;
  for (int p : {1, 2, 3}) {
    const auto clear = geometric_rays(Complex(1.333, 0), x, p, rad(150));
    const auto dark = geometric_rays(Complex(1.333, k), x, p, rad(150));
    ASSERT_EQ(clear.size(), dark.size());
    for (std::size_t i = 0; i < clear.size(); ++i) {
      const double expected = std::exp(-2 * x * k * p * std::cos(clear[i].theta_t));
      // the Fresnel factors change by O(k) too: 1e-3
      EXPECT_NEAR(std::abs(dark[i].s1) / std::abs(clear[i].s1), expected, 1e-3 * expected) << p;
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Diffraction
// ---------------------------------------------------------------------------------------------

// Fraunhofer diffraction by the projected disk: S(0) = x^2 / 2, real and positive (so that the
// optical theorem gives the extinction paradox's Q_ext = 2 with Q_sca,GO = 1), and it scatters
// pi a^2: (1/(pi x^2)) int |S|^2 dOmega = 2 int_0^x J1(u)^2 / u / cos(theta) du -> 2 * 1/2 = 1,
// with an O(1/x) deficit from the tail beyond u = x (~0.6/x) and the obliquity. x = 2000:
// tolerance 1e-3.
TEST(Diffraction, ForwardPeakAndCrossSection) {
  for (double x : {10.0, 1000.0}) {
    EXPECT_EQ(fraunhofer_amplitude(x, 0.0), Complex(x * x / 2, 0));
    EXPECT_NEAR(fraunhofer_amplitude(x, 1e-9).real(), x * x / 2, 1e-9 * x * x);
  }
  EXPECT_EQ(fraunhofer_amplitude(100, 2.0), Complex(0, 0));  // backward hemisphere: none
  // first dark ring at x sin(theta) = 3.8317 (first zero of J1, A&S table 9.5)
  EXPECT_NEAR(fraunhofer_amplitude(100, std::asin(3.8317059702 / 100)).real(), 0.0, 1e-6);
  const double x = 2000;
  double q = 0;
  const int panels = 20000;
  const double ht = 0.5 * kPiD / panels;
  const double gx[4] = {-0.8611363115940526, -0.3399810435848563, 0.3399810435848563,
                        0.8611363115940526};
  const double gw[4] = {0.3478548451374538, 0.6521451548625461, 0.6521451548625461,
                        0.3478548451374538};
  for (int k = 0; k < panels; ++k)
    for (int j = 0; j < 4; ++j) {
      const double th = (k + 0.5 + 0.5 * gx[j]) * ht;
      q += 0.5 * ht * gw[j] * std::norm(fraunhofer_amplitude(x, th)) * std::sin(th);
    }
  q *= 2 / (x * x);
  EXPECT_NEAR(q, 1.0, 1e-3);
}

TEST(Amplitudes, SumWithDiffractionAddsTheDiffractedWave) {
  const Complex m(1.333, 0);
  const double x = 150;
  std::vector<double> theta = {0.0, 0.01, 0.3, 1.2, 2.0, 2.6, kPiD};
  std::vector<Complex> a1(theta.size()), a2(theta.size()), b1(theta.size()), b2(theta.size());
  geometric_amplitudes(m, x, 5, theta, a1, a2, true);
  geometric_amplitudes(m, x, 5, theta, b1, b2, false);
  for (std::size_t i = 0; i < theta.size(); ++i) {
    EXPECT_NEAR(std::abs(a1[i] - b1[i] - fraunhofer_amplitude(x, theta[i])), 0.0, 1e-9 * x * x);
    EXPECT_NEAR(std::abs(a2[i] - b2[i] - fraunhofer_amplitude(x, theta[i])), 0.0, 1e-9 * x * x);
    Complex o1 = 0;
    for (int p = 0; p <= 5; ++p) {
      Complex c1, c2;
      geometric_amplitudes_order(m, x, p, {&theta[i], 1}, {&c1, 1}, {&c2, 1});
      o1 += c1;
    }
    EXPECT_NEAR(std::abs(o1 - b1[i]), 0.0, 1e-12 * x * x);
  }
  EXPECT_NEAR(std::abs(a1[0] - a2[0]), 0.0, 1e-9 * x * x);  // S1(0) = S2(0)
}

TEST(Geometric, DomainErrors) {
  std::vector<double> theta = {0.5};
  std::vector<Complex> s1(1), s2(1), short_span;
  EXPECT_THROW(geometric_amplitudes(Complex(0.9, 0), 100, 3, theta, s1, s2, false), DomainError);
  EXPECT_THROW(geometric_amplitudes(Complex(1.333, -0.1), 100, 3, theta, s1, s2, false),
               DomainError);
  EXPECT_THROW(geometric_amplitudes(Complex(1.333, 0), 0, 3, theta, s1, s2, false), DomainError);
  EXPECT_THROW(geometric_amplitudes(Complex(1.333, 0), 100, -1, theta, s1, s2, false), DomainError);
  EXPECT_THROW(geometric_amplitudes(Complex(1.333, 0), 100, 3, theta, short_span, s2, false),
               DomainError);
  std::vector<double> bad = {4.0};
  EXPECT_THROW(geometric_amplitudes(Complex(1.333, 0), 100, 3, bad, s1, s2, false), DomainError);
  EXPECT_THROW(geometric_rays(Complex(1.333, 0), 100, 2, std::nan("")), DomainError);
  EXPECT_THROW(ray_fresnel_factors(Complex(1.333, 0), 2, 2.0), DomainError);
}

}  // namespace
}  // namespace hydrolux::scatter
