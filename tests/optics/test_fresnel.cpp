// Fresnel equations: published values, exact identities, energy, and an independent closed form
// for absorbing media.
#include <gtest/gtest.h>

#include "hydrolux/optics/fresnel.hpp"
#include "hydrolux/optics/snell.hpp"

namespace hydrolux::optics {
namespace {

double cosd(double deg) { return std::cos(deg_to_rad(deg)); }

// Air to glass n = 1.5 at 45 degrees: R_s = 0.0920, R_p = 0.0085 (Hecht, Optics, 5th ed., Fig. 4.49
// plots these curves for n_ti = 1.5). The exact values are closed-form; 1e-6 is the rounding of
// the quoted digits.
TEST(FresnelDielectric, GlassAt45Degrees) {
  const auto f = fresnel_dielectric(cosd(45), 1.0, 1.5);
  EXPECT_NEAR(f.R_s, 0.092013, 1e-6);
  EXPECT_NEAR(f.R_p, 0.008466, 1e-6);
  EXPECT_NEAR(f.R, 0.050240, 1e-6);
  EXPECT_NEAR(rad_to_deg(std::acos(f.cos_t)), 28.1255, 1e-4);
  EXPECT_FALSE(f.tir);
}

// Abeles' identity: at 45 degrees incidence R_p = R_s^2 for any dielectric interface (F. Abeles,
// Ann. Phys. 1950; Born & Wolf, Principles of Optics, section 1.5 problems). Exact, so 1e-15.
TEST(FresnelDielectric, AbelesIdentityAt45Degrees) {
  for (double n : {1.1, 1.333, 1.5, 2.0, 3.5}) {
    const auto f = fresnel_dielectric(cosd(45), 1.0, n);
    EXPECT_NEAR(f.R_p, f.R_s * f.R_s, 1e-15) << n;
  }
}

// Normal incidence: R = ((n-1)/(n+1))^2, about 2% for water and 4% for glass (Hecht, section 4.6.2).
TEST(FresnelDielectric, NormalIncidence) {
  EXPECT_NEAR(fresnel_dielectric(1.0, 1.0, 1.333).R, 0.0204, 5e-5);
  EXPECT_NEAR(fresnel_dielectric(1.0, 1.0, 1.5).R, 0.04, 1e-15);
  for (double n : {1.2, 1.333, 1.5, 2.4}) {
    const auto f = fresnel_dielectric(1.0, 1.0, n);
    EXPECT_NEAR(f.R_s, f.R_p, 1e-15);
    EXPECT_NEAR(f.r_p.real(), -f.r_s.real(), 1e-15);  // Hecht's sign convention
  }
}

TEST(FresnelDielectric, ParallelReflectanceVanishesAtBrewster) {
  for (double n : {1.333, 1.5}) {
    const auto f = fresnel_dielectric(std::cos(brewster_angle(1.0, n)), 1.0, n);
    EXPECT_NEAR(f.R_p, 0.0, 1e-15);
    EXPECT_GT(f.R_s, 0.0);
    const auto g = fresnel_dielectric(std::cos(brewster_angle(n, 1.0)), n, 1.0);  // internal side
    EXPECT_NEAR(g.R_p, 0.0, 1e-15);
  }
}

// Energy: R + T = 1 with T = (n_t cos_t)/(n_i cos_i) |t|^2 computed from the amplitudes, for each
// polarisation, from either side, at every angle.
TEST(FresnelDielectric, ReflectancePlusTransmittanceIsOne) {
  for (double n1 : {1.0, 1.333, 1.5})
    for (double n2 : {1.0, 1.0003, 1.333, 1.5, 2.4})
      for (int i = 0; i <= 900; ++i) {
        const auto f = fresnel_dielectric(cosd(0.1 * i), n1, n2);
        EXPECT_NEAR(f.R_s + f.T_s, 1.0, 1e-13);
        EXPECT_NEAR(f.R_p + f.T_p, 1.0, 1e-13);
        EXPECT_NEAR(f.R + f.T, 1.0, 1e-13);
        EXPECT_GE(f.R, 0.0);
        EXPECT_LE(f.R, 1.0);
      }
}

// Stokes relations between the two directions through the same interface (Hecht section 4.10):
// r' = -r and t t' = 1 - r^2, the reverse path taken at the refraction angle.
TEST(FresnelDielectric, StokesRelations) {
  for (int i = 0; i < 89; ++i) {
    const double ci = cosd(i);
    const auto f = fresnel_dielectric(ci, 1.0, 1.333);
    const auto b = fresnel_dielectric(f.cos_t, 1.333, 1.0);
    EXPECT_NEAR(b.r_s.real(), -f.r_s.real(), 1e-13);
    EXPECT_NEAR(b.r_p.real(), -f.r_p.real(), 1e-13);
    EXPECT_NEAR((f.t_s * b.t_s).real(), 1 - std::norm(f.r_s), 1e-13);
    EXPECT_NEAR((f.t_p * b.t_p).real(), 1 - std::norm(f.r_p), 1e-13);
  }
}

// Total internal reflection from water into air past 48.6 degrees: R = 1, T = 0, and the phase
// jumps of Born & Wolf section 1.5.4, tan(delta_s / 2) = sqrt(sin^2 - n^2) / cos and
// tan(delta_p / 2) = sqrt(sin^2 - n^2) / (n^2 cos), with n = n_t / n_i.
TEST(FresnelDielectric, TotalInternalReflectionFromWater) {
  const double n = 1.0 / 1.333;
  EXPECT_FALSE(fresnel_dielectric(cosd(48.5), 1.333, 1.0).tir);
  EXPECT_LT(fresnel_dielectric(cosd(48.5), 1.333, 1.0).R, 1.0);
  for (double deg = 48.7; deg < 90; deg += 0.5) {
    const auto f = fresnel_dielectric(cosd(deg), 1.333, 1.0);
    EXPECT_TRUE(f.tir) << deg;
    EXPECT_EQ(f.R, 1.0);
    EXPECT_EQ(f.T, 0.0);
    EXPECT_NEAR(std::abs(f.r_s), 1.0, 1e-14);
    EXPECT_NEAR(std::abs(f.r_p), 1.0, 1e-14);
    const double s = std::sin(deg_to_rad(deg)), c = std::cos(deg_to_rad(deg));
    const double root = std::sqrt(s * s - n * n);
    EXPECT_NEAR(std::abs(std::arg(f.r_s)), 2 * std::atan(root / c), 1e-12) << deg;
    EXPECT_NEAR(std::abs(std::arg(f.r_p)), 2 * std::atan(root / (n * n * c)), 1e-12) << deg;
    EXPECT_EQ(fr_dielectric(-c, 1.0 / n), 1.0);
  }
}

// The real-arithmetic BSDF path agrees with the amplitude path, from both sides.
TEST(FresnelDielectric, FastPathMatchesFullEquations) {
  for (double eta : {1.333, 1.5, 1 / 1.333})
    for (int i = 0; i <= 200; ++i) {
      const double c = std::cos(0.5 * kPi<> * i / 200.0);
      EXPECT_NEAR(fr_dielectric(c, eta), fresnel_dielectric(c, 1.0, eta).R, 1e-14);
      EXPECT_NEAR(fr_dielectric(-c, eta), fresnel_dielectric(c, eta, 1.0).R, 1e-14);
    }
}

// Independent exact form for an absorbing medium seen from vacuum, in real arithmetic (Born &
// Wolf, section 14.2; as in pbrt-v3's FrConductor): a^2 + b^2 = sqrt((eta^2 - k^2 - sin^2)^2 +
// 4 eta^2 k^2), a^2 = (a^2 + b^2 + eta^2 - k^2 - sin^2) / 2,
// R_s = (a^2+b^2 - 2a cos + cos^2) / (a^2+b^2 + 2a cos + cos^2),
// R_p = R_s (a^2+b^2 - 2a sin tan + sin^2 tan^2) / (a^2+b^2 + 2a sin tan + sin^2 tan^2).
TEST(FresnelConductor, MatchesBornWolfClosedForm) {
  const std::complex<double> metals[] = {{0.43, 2.455}, {0.06, 3.586}, {1.02, 2.577}, {0.958, 6.69},
                                         {1.5, 0.001}, {3.0, 0.5}};
  for (const auto m : metals) {
    const double eta = m.real(), k = m.imag();
    for (int i = 0; i < 90; ++i) {
      const double t = deg_to_rad(double(i)), c = std::cos(t), s = std::sin(t), tn = std::tan(t);
      const double d = eta * eta - k * k - s * s;
      const double a2b2 = std::sqrt(d * d + 4 * eta * eta * k * k);
      const double a = std::sqrt((a2b2 + d) / 2);
      const double rs = (a2b2 - 2 * a * c + c * c) / (a2b2 + 2 * a * c + c * c);
      const double rp = rs * (a2b2 - 2 * a * s * tn + s * s * tn * tn) / (a2b2 + 2 * a * s * tn + s * s * tn * tn);
      const auto f = fresnel_conductor(c, 1.0, m);
      EXPECT_NEAR(f.R_s, rs, 1e-13) << m << " at " << i;
      EXPECT_NEAR(f.R_p, rp, 1e-13) << m << " at " << i;
      EXPECT_NEAR(fr_conductor(c, m), (rs + rp) / 2, 1e-13);
    }
  }
}

// Normal incidence on a metal: R = ((n-1)^2 + k^2) / ((n+1)^2 + k^2) (Born & Wolf eq. 14.2(25)),
// and a conductor with k -> 0 is a dielectric.
TEST(FresnelConductor, NormalIncidenceAndDielectricLimit) {
  const std::complex<double> m(0.43, 2.455);
  EXPECT_NEAR(fresnel_conductor(1.0, 1.0, m).R,
              (sqr(0.43 - 1) + sqr(2.455)) / (sqr(0.43 + 1) + sqr(2.455)), 1e-15);
  for (int i = 0; i < 90; ++i) {
    const double c = cosd(i);
    EXPECT_NEAR(fresnel_conductor(c, 1.0, {1.5, 0.0}).R, fresnel_dielectric(c, 1.0, 1.5).R, 1e-14);
    EXPECT_NEAR(fresnel_conductor(c, 1.333, {1.5, 1e-12}).R, fresnel_dielectric(c, 1.333, 1.5).R, 1e-10);
  }
}

// No NaN anywhere, grazing incidence and index-matched interfaces included.
TEST(Fresnel, FiniteEverywhere) {
  for (double n2 : {1.0, 1.333, 0.75})
    for (double c : {0.0, 1e-300, 1e-8, 0.5, 1.0}) {
      const auto f = fresnel_dielectric(c, 1.0, n2);
      for (double v : {f.R_s, f.R_p, f.R, f.T_s, f.T_p, f.T, f.cos_t}) EXPECT_TRUE(std::isfinite(v)) << n2 << " " << c;
      const auto g = fresnel_conductor(c, 1.0, {n2, 3.0});
      EXPECT_TRUE(std::isfinite(g.R));
    }
  EXPECT_EQ(fresnel_dielectric(0.0, 1.333, 1.333).T, 0.0);
  EXPECT_EQ(fresnel_dielectric(1.0, 1.333, 1.333).R, 0.0);
}

// The CLI's index range, [1e-3, 1e3] for n1, n2 (hydrolux fresnel): at its corners, at every angle,
// R_s and R_p equal the textbook equations evaluated in long double (64-bit mantissa) to 1e-12,
// and R + T = 1. Far below the range (n ~ 1e-154) n^2 underflows, which is why the CLI refuses it.
TEST(FresnelDielectric, AccurateAcrossTheCliRange) {
  for (double n1 : {1e-3, 1.0, 1e3})
    for (double n2 : {1e-3, 1.0, 1.333, 1e3})
      for (double deg : {0.0, 10.0, 45.0, 80.0, 89.9}) {
        const long double ci = std::cos(static_cast<long double>(deg) * 3.14159265358979323846264338327950288L / 180);
        const long double si2 = 1 - ci * ci;
        const long double st2 = (static_cast<long double>(n1) / n2) * (static_cast<long double>(n1) / n2) * si2;
        const auto f = fresnel_dielectric(static_cast<double>(ci), n1, n2);
        if (st2 >= 1) {
          EXPECT_TRUE(f.tir) << n1 << " " << n2 << " " << deg;
          EXPECT_NEAR(f.R, 1.0, 1e-12);
          continue;
        }
        const long double ct = std::sqrt(1 - st2);
        const long double rs = (n1 * ci - n2 * ct) / (n1 * ci + n2 * ct);
        const long double rp = (n2 * ci - n1 * ct) / (n2 * ci + n1 * ct);
        EXPECT_NEAR(f.R_s, static_cast<double>(rs * rs), 1e-12) << n1 << " " << n2 << " " << deg;
        EXPECT_NEAR(f.R_p, static_cast<double>(rp * rp), 1e-12) << n1 << " " << n2 << " " << deg;
        EXPECT_NEAR(f.R + f.T, 1.0, 1e-12);
      }
}

}  // namespace
}  // namespace hydrolux::optics
