// The Airy function against published and high-precision values, and Airy theory of the rainbow:
// the position of the maximum, the supernumerary spacing, the x^(7/3) growth, the polarisation,
// and the match with geometric optics on the lit side (which carries the B&H normalisation).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>

#include "hydrolux/core/error.hpp"
#include "hydrolux/core/math.hpp"
#include "hydrolux/scatter/airy.hpp"
#include "hydrolux/scatter/geometric.hpp"

namespace hydrolux::scatter {
namespace {

// ---------------------------------------------------------------------------------------------
// The Airy function
// ---------------------------------------------------------------------------------------------

// Ai(0) = 3^(-2/3) / Gamma(2/3) = 0.355028053887817 and Ai'(0) = -3^(-1/3) / Gamma(1/3) =
// -0.258819403792807 (Abramowitz & Stegun 10.4.4, 10.4.5). The series returns its constants: 1e-16.
TEST(AiryFunction, ValuesAtZero) {
  EXPECT_NEAR(airy_ai(0.0), 0.355028053887817, 1e-15);
  EXPECT_NEAR(airy_ai_prime(0.0), -0.258819403792807, 1e-15);
  EXPECT_NEAR(airy_ai(0.0), std::pow(3.0, -2.0 / 3) / std::tgamma(2.0 / 3), 1e-16);
  EXPECT_NEAR(airy_ai_prime(0.0), -std::pow(3.0, -1.0 / 3) / std::tgamma(1.0 / 3), 1e-16);
}

// Zeros of Ai and Ai' (A&S Table 10.13: a_1 = -2.33810741, a_2 = -4.08794944, a_3 = -5.52055983;
// a'_1 = -1.01879297, a'_2 = -3.24819758, a'_3 = -4.82009921), to 16 digits from mpmath 1.3.0
// airyaizero. |Ai'| <= 1 near them, so a value below 2e-15 puts the zero within ~2e-15.
constexpr double kAiZeros[] = {-2.338107410459767, -4.087949444130971, -5.520559828095551};
constexpr double kAiPrimeZeros[] = {-1.018792971647471, -3.248197582179837, -4.820099211178736};

TEST(AiryFunction, Zeros) {
  for (double a : kAiZeros) EXPECT_NEAR(airy_ai(a), 0.0, 2e-15) << a;
  for (double a : kAiPrimeZeros) EXPECT_NEAR(airy_ai_prime(a), 0.0, 2e-15) << a;
  // the 8-digit table values are zeros to their rounding (|Ai'| ~ 0.7, |Ai''| = |x Ai| ~ 0.5)
  EXPECT_NEAR(airy_ai(-2.33810741), 0.0, 1e-8);
  EXPECT_NEAR(airy_ai(-4.08794944), 0.0, 1e-8);
}

// Reference values from mpmath 1.3.0 (airyai(x), airyai(x, 1) at 40 digits, rounded to 17),
// across the series (|x| <= 2) and both Bessel forms. The argument zeta = (2/3)|x|^(3/2) of the
// Bessel functions carries a rounding of ~eps zeta: into the exponent exp(-zeta) for x > 2
// (relative error ~eps zeta) and into the phase for x < -2. Tolerances: 5e-15 relative for |x|
// <= 2.5, (5e-15 + 2e-15 zeta) relative for x > 2.5, and 2e-15 (1 + zeta) times the envelope
// |x|^(-1/4) (Ai) or |x|^(1/4) (Ai') absolute where Ai oscillates, x < -2.5.
struct AiryRef {
  double x, ai, aip;
};
constexpr AiryRef kAiryRef[] = {
    {-150, 0.049038082702410901, -1.8808154281540912},
    {-60.5, 0.068533667377445427, -1.4801596331558451},
    {-25, 0.16352657883042947, 0.96237885138769741},
    {-10.25, -0.19540104411200782, 0.78755256173365248},
    {-6, -0.32914517362982311, 0.34593548728134289},
    {-3.5, -0.37553382314043191, -0.34344343345404815},
    {-2.5, -0.11232506769296609, 0.67885273426479436},
    {-1.75, 0.36548325221423157, 0.47865157166730629},
    {-1, 0.53556088329235212, -0.010160567116645209},
    {-0.25, 0.41872461427545292, -0.24638918992017597},
    {0.3, 0.27880648195500492, -0.2451463642190548},
    {1, 0.13529241631288142, -0.15914744129679321},
    {1.75, 0.050569880805794872, -0.072853713762028385},
    {2.5, 0.01572592338047049, -0.02625088103590323},
    {4, 0.00095156385120480187, -0.0019586409502041789},
    {7, 7.4921288639971671e-7, -2.008150894738792e-6},
    {15, 2.1649625207379923e-18, -8.4205679540177728e-18},
    {40, 6.3657426585529149e-75, -4.030017977600678e-74},
    {90, 5.7151634080015967e-249, -5.4234664561307261e-248},
};

TEST(AiryFunction, MatchesHighPrecisionReference) {
  for (const auto& r : kAiryRef) {
    const double ai = airy_ai(r.x), aip = airy_ai_prime(r.x);
    if (r.x >= -2.5) {
      const double zeta = r.x > 2.5 ? 2.0 / 3 * r.x * std::sqrt(r.x) : 0.0;
      EXPECT_NEAR(ai, r.ai, (5e-15 + 2e-15 * zeta) * std::abs(r.ai)) << r.x;
      EXPECT_NEAR(aip, r.aip, (5e-15 + 2e-15 * zeta) * std::abs(r.aip)) << r.x;
    } else {
      const double z = -r.x, zeta = 2.0 / 3 * z * std::sqrt(z);
      EXPECT_NEAR(ai, r.ai, 2e-15 * (1 + zeta) * std::pow(z, -0.25)) << r.x;
      EXPECT_NEAR(aip, r.aip, 2e-15 * (1 + zeta) * std::pow(z, 0.25)) << r.x;
    }
  }
}

// Ai solves y'' = x y: a central difference of Ai' (step 1e-4: truncation ~1e-9, rounding ~1e-12)
// equals x Ai, also across the switches between series and Bessel forms at |x| = 2, where the two
// sides also agree to 1e-15.
TEST(AiryFunction, SolvesAirysEquationAndIsContinuous) {
  for (double x = -12; x <= 6; x += 0.37) {
    const double h = 1e-4;
    const double second = (airy_ai_prime(x + h) - airy_ai_prime(x - h)) / (2 * h);
    EXPECT_NEAR(second, x * airy_ai(x), 1e-8 * std::max(1.0, std::abs(x))) << x;
  }
  for (double s : {-2.0, 2.0}) {
    const double below = std::nextafter(s, 0.0), above = std::nextafter(s, 3 * s);
    EXPECT_NEAR(airy_ai(below), airy_ai(above), 1e-15);
    EXPECT_NEAR(airy_ai_prime(below), airy_ai_prime(above), 1e-15);
  }
  EXPECT_EQ(airy_ai(200.0), 0.0);  // underflow, not NaN
  EXPECT_TRUE(std::isnan(airy_ai(std::nan(""))));
}

// ---------------------------------------------------------------------------------------------
// Airy theory of the rainbow
// ---------------------------------------------------------------------------------------------

// van de Hulst's h (section 13.21), written out here: (p^2-1)^2 sqrt(p^2-n^2) / (p^2 (n^2-1)^1.5).
double h_parameter(double n, int p) {
  const double pp = p * p;
  return sqr(pp - 1) * std::sqrt(pp - n * n) / (pp * std::pow(n * n - 1, 1.5));
}

double intensity1(double n, double x, int p, double theta) {
  Complex s1, s2;
  airy_amplitudes(n, x, p, {&theta, 1}, {&s1, 1}, {&s2, 1});
  return std::norm(s1);
}

// Golden-section search for the maximum of f on [a, b] (unimodal there); ~1e-9 of (b - a).
double argmax(const std::function<double(double)>& f, double a, double b) {
  const double g = (std::sqrt(5.0) - 1) / 2;
  for (int it = 0; it < 200 && b - a > 1e-12 * std::abs(a); ++it) {
    const double c = b - g * (b - a), d = a + g * (b - a);
    if (f(c) > f(d))
      b = d;
    else
      a = c;
  }
  return 0.5 * (a + b);
}

// The Airy maximum lies on the lit side of the geometric rainbow, at z = -a'_1 = 1.018793: for
// the primary at theta_R + 1.018793 h^(1/3) x^(-2/3) rad, i.e. inside the geometric bow (a smaller
// radius about the antisolar point), by an amount proportional to x^(-2/3) (van de Hulst
// section 13.23). The search resolves the peak to ~1e-9 of the bracket: tolerance 1e-6 relative.
TEST(AiryRainbow, MaximumInsideTheGeometricBowByXToTheMinusTwoThirds) {
  const double n = 1.333;
  double previous_shift = 0;
  for (double x : {1000.0, 8000.0, 64000.0}) {
    const double scale = std::cbrt(x * x / h_parameter(n, 2));
    EXPECT_NEAR(airy_angular_scale(n, x, 2), scale, 1e-13 * scale);
    const double theta_r = rainbow_angle(n, 2);
    const double peak =
        argmax([&](double t) { return intensity1(n, x, 2, t); }, theta_r, theta_r + 2.0 / scale);
    const double shift = peak - theta_r;
    EXPECT_GT(shift, 0.0);  // larger scattering angle = smaller radius: inside the bow
    EXPECT_NEAR(shift, -kAiPrimeZeros[0] / scale, 1e-6 * shift) << x;
    if (previous_shift > 0) {
      EXPECT_NEAR(previous_shift / shift, 4.0, 1e-5);  // (8x)^(2/3) = 4 x^(2/3)
    }
    previous_shift = shift;
  }
  // x = 1000 (a 0.09 mm drop in green light): the maximum is 0.99 degrees inside 42.08 degrees.
  EXPECT_NEAR(rad_to_deg(-kAiPrimeZeros[0] / airy_angular_scale(n, 1000, 2)), 0.991, 0.001);
  // The secondary's maximum lies on its own lit side, at smaller scattering angles (outside it).
  const double x = 5000, theta_r3 = rainbow_angle(n, 3), scale3 = airy_angular_scale(n, x, 3);
  const double peak3 =
      argmax([&](double t) { return intensity1(n, x, 3, t); }, theta_r3 - 2.0 / scale3, theta_r3);
  EXPECT_NEAR(peak3 - theta_r3, kAiPrimeZeros[0] / scale3, 1e-6 / scale3);
}

// Supernumerary bows: the maxima of Ai(-z)^2 are at the zeros of Ai', so the first two
// supernumeraries lie (a'_1 - a'_2) h^(1/3) x^(-2/3) and (a'_2 - a'_3) h^(1/3) x^(-2/3) beyond the
// main maximum (van de Hulst section 13.23); spacings shrink as z^(-1/2). Tolerance as above.
TEST(AiryRainbow, SupernumerarySpacing) {
  const double n = 1.333;
  for (int p : {2, 3})
    for (double x : {2000.0, 20000.0}) {
      const RainbowRay rb = rainbow_ray(n, p);
      const double scale = std::cbrt(x * x / h_parameter(n, p));
      double peaks[3];
      for (int k = 0; k < 3; ++k) {
        const double z0 = -kAiPrimeZeros[k];
        const double t1 = rb.scattering_angle + rb.side * (z0 - 0.5) / scale;
        const double t2 = rb.scattering_angle + rb.side * (z0 + 0.5) / scale;
        peaks[k] = argmax([&](double t) { return intensity1(n, x, p, t); }, std::min(t1, t2),
                          std::max(t1, t2));
      }
      const double d1 = std::abs(peaks[1] - peaks[0]), d2 = std::abs(peaks[2] - peaks[1]);
      EXPECT_NEAR(d1, (kAiPrimeZeros[0] - kAiPrimeZeros[1]) / scale, 1e-6 * d1) << p << " " << x;
      EXPECT_NEAR(d2, (kAiPrimeZeros[1] - kAiPrimeZeros[2]) / scale, 1e-6 * d2) << p << " " << x;
      EXPECT_LT(d2, d1);
    }
}

// The rainbow's peak intensity grows as x^(7/3) (van de Hulst section 13.23): |S|^2 = x^2 eps^2 D
// summed over a region of width x^(-2/3) around a caustic whose D grows as x^(1/3). In Airy
// theory the ratio for 8x is exactly 8^(7/3) = 128; rounding only.
TEST(AiryRainbow, PeakGrowsAsXToTheSevenThirds) {
  const double n = 1.333;
  for (int p : {2, 3}) {
    auto peak = [&](double x) {
      const RainbowRay rb = rainbow_ray(n, p);
      const double theta =
          rb.scattering_angle - rb.side * kAiPrimeZeros[0] / airy_angular_scale(n, x, p);
      return intensity1(n, x, p, theta);
    };
    EXPECT_NEAR(peak(8000) / peak(1000), 128.0, 1e-9);
  }
}

// Polarisation (Konnen & de Boer 1979): in Airy theory both polarisations share Ai(-z) and differ
// by the Fresnel factors at the rainbow ray, eps_j = t_j t'_j (r'_j)^(p-1), so i2/i1 =
// (T_p^2 R_p^(p-1)) / (T_s^2 R_s^(p-1)). The primary's rainbow ray meets the back of the drop at
// theta_t = 40.2 degrees, near Brewster's 36.9: R_p = 0.0035 against R_s = 0.111. So the
// primary is strongly polarised: 96% of its light is perpendicular, i1 / (i1 + i2) = 0.962
// (the "96% polarised" of the rainbow literature), a degree of polarisation (i1 - i2)/(i1 + i2)
// of 0.924; the secondary 90% (0.904) and 0.807. The Fresnel factors are written out here with
// Hecht's formulas; the closed-form comparison holds to rounding (1e-12), the quoted
// percentages to their last digit.
TEST(AiryRainbow, PrimaryIsStronglyPolarised) {
  const double n = 1.333;
  struct Case {
    int p;
    double perpendicular_share, degree;
  };
  for (const Case c : {Case{2, 0.962, 0.924}, Case{3, 0.904, 0.807}}) {
    const double cos_i = std::sqrt((n * n - 1) / (c.p * c.p - 1));
    const double cos_t = std::sqrt(1 - (1 - cos_i * cos_i) / (n * n));
    const double rs = (cos_i - n * cos_t) / (cos_i + n * cos_t);
    const double rp = (n * cos_i - cos_t) / (n * cos_i + cos_t);
    const double ratio = sqr(1 - rp * rp) * std::pow(rp * rp, c.p - 1) /
                         (sqr(1 - rs * rs) * std::pow(rs * rs, c.p - 1));
    const RainbowRay rb = rainbow_ray(n, c.p);
    for (double z : {-1.0, 0.0, 1.0188, 2.5, 4.0}) {
      const double theta = rb.scattering_angle + rb.side * z / airy_angular_scale(n, 3000, c.p);
      Complex s1, s2;
      airy_amplitudes(n, 3000, c.p, {&theta, 1}, {&s1, 1}, {&s2, 1});
      EXPECT_NEAR(std::norm(s2) / std::norm(s1), ratio, 1e-12 * ratio) << c.p << " " << z;
      const double i1 = std::norm(s1), i2 = std::norm(s2);
      EXPECT_NEAR(i1 / (i1 + i2), c.perpendicular_share, 0.0005) << c.p;
      EXPECT_NEAR((i1 - i2) / (i1 + i2), c.degree, 0.0005) << c.p;
    }
  }
}

// The normalisation and phase of the Airy amplitude are those of geometric optics on the lit side:
// at the supernumerary maxima z = -a'_2, -a'_3 the Airy amplitude equals the coherent sum of the
// two geometric-optics rays of geometric.hpp (B&H normalisation, focal-line phases), which the
// derivation matches term by term as z -> infinity. Residuals: the asymptotic form of Ai is good to
// ~5/(72 zeta) ~ 2% at z = 3.2 in each of the two waves, partly cancelling (0.3% seen); the
// neglected quartic term of the wavefront shifts the common phase by ~c_p z^2 x^(-1/3) (primary at
// z = 3.25: 0.03 rad at x = 1e7, 0.07 at 1e6, 0.15 at 1e5; the secondary's c_p is larger: 0.1 rad
// at z = 4.8, x = 1e7). Tolerances at x = 1e7: 1% in magnitude, 0.15 rad in phase.
// Against exact Mie theory (offline, x = 5000-20000, perpendicular polarisation, with the p = 0
// reflection added), the Airy peak intensity agrees to ~2%.
TEST(AiryRainbow, MatchesGeometricOpticsOnTheLitSide) {
  const double n = 1.333, x = 1e7;
  for (int p : {2, 3}) {
    const RainbowRay rb = rainbow_ray(n, p);
    const double scale = airy_angular_scale(n, x, p);
    for (double z : {-kAiPrimeZeros[1], -kAiPrimeZeros[2]}) {
      const double theta = rb.scattering_angle + rb.side * z / scale;
      EXPECT_NEAR(airy_argument(n, x, p, theta), z, 1e-6);
      Complex a1, a2, g1, g2;
      airy_amplitudes(n, x, p, {&theta, 1}, {&a1, 1}, {&a2, 1});
      geometric_amplitudes_order(Complex(n, 0), x, p, {&theta, 1}, {&g1, 1}, {&g2, 1});
      EXPECT_NEAR(std::abs(a1) / std::abs(g1), 1.0, 0.01) << p << " " << z;
      EXPECT_NEAR(std::arg(a1 / g1), 0.0, 0.15) << p << " " << z;
      EXPECT_NEAR(std::abs(a2) / std::abs(g2), 1.0, 0.01) << p << " " << z;
      EXPECT_NEAR(std::arg(a2 / g2), 0.0, 0.15) << p << " " << z;
    }
  }
}

// On the dark side the amplitude decays as Ai(-z) for z < 0: no rays, only the evanescent tail.
TEST(AiryRainbow, DarkSideDecays) {
  const double n = 1.333, x = 4000;
  const RainbowRay rb = rainbow_ray(n, 2);
  const double scale = airy_angular_scale(n, x, 2);
  const double peak = intensity1(n, x, 2, rb.scattering_angle - kAiPrimeZeros[0] / scale);
  const double dark = intensity1(n, x, 2, rb.scattering_angle - 3 / scale);
  EXPECT_NEAR(dark / peak, sqr(airy_ai(3.0) / airy_ai(kAiPrimeZeros[0])), 1e-12);
  EXPECT_LT(dark / peak, 2e-4);
}

TEST(AiryRainbow, DomainErrors) {
  double theta = 2.4;
  Complex s1, s2;
  EXPECT_THROW(airy_amplitudes(1.333, 1000, 1, {&theta, 1}, {&s1, 1}, {&s2, 1}), DomainError);
  EXPECT_THROW(airy_amplitudes(2.5, 1000, 2, {&theta, 1}, {&s1, 1}, {&s2, 1}), DomainError);
  EXPECT_THROW(airy_amplitudes(1.333, -5, 2, {&theta, 1}, {&s1, 1}, {&s2, 1}), DomainError);
  theta = -0.1;
  EXPECT_THROW(airy_amplitudes(1.333, 1000, 2, {&theta, 1}, {&s1, 1}, {&s2, 1}), DomainError);
  EXPECT_THROW(airy_argument(1.333, 1000, 2, 7.0), DomainError);
}

}  // namespace
}  // namespace hydrolux::scatter

// The tabulated Ai used by the Lee tables: within 1e-8 (absolute; |Ai| <= 0.54) of the Bessel-function
// evaluation over the lit and dark sides, the table's nodes, between them, and across the switch to
// the asymptotic expansion at -16; exactly 0 beyond 12 (Ai(12) = 1.1e-11).
TEST(AiryFunction, TabulatedAgreesWithBessel) {
  double worst = 0, at = 0;
  for (double x = -40; x <= 14; x += 0.00173) {
    const double d = std::abs(hydrolux::scatter::airy_ai_fast(x) - hydrolux::scatter::airy_ai(x));
    if (d > worst) {
      worst = d;
      at = x;
    }
  }
  EXPECT_LT(worst, 1e-8) << "at x = " << at;
  EXPECT_EQ(hydrolux::scatter::airy_ai_fast(12.5), 0.0);
  EXPECT_NEAR(hydrolux::scatter::airy_ai_fast(-16.0001), hydrolux::scatter::airy_ai(-16.0001), 1e-8);
}
