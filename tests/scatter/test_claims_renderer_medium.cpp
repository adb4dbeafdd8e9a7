// Claims of docs/renderer-export.md about the size averages of `hydrolux medium` (a fixed count's noise
// across the spectra; the note for a count given too few for the ripple), checked against a size average
// by a different rule written in this file: the drops' number density written out (gamma:
// r^(alpha - 1) exp(-r / beta), alpha = 1 / w^2, beta = mean w^2, as size_distribution.hpp defines it)
// summed by the midpoint rule on radii evenly spaced in x, with the library's single-radius Mie as the
// integrand (checked against mpmath and MIEV0 in tests/scatter/test_mie.cpp; the quadrature is what is
// under test).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <future>
#include <numbers>
#include <string>
#include <thread>
#include <vector>

#include "hydrolux/optics/media.hpp"
#include "hydrolux/scatter/amplitudes.hpp"
#include "hydrolux/scatter/mie.hpp"
#include "hydrolux/scatter/phase_job.hpp"
#include "hydrolux/scatter/renderer_export.hpp"
#include "hydrolux/scatter/sphere.hpp"
#include "hydrolux/scatter/theories.hpp"
#include "support/asan.hpp"
#include "support/size_reference.hpp"

namespace hydrolux::scatter {
namespace {

using namespace size_reference;

// docs/renderer-export.md l. 69-70: a fixed count left the Mie ripple in r as noise across the spectrum:
// 64 Gauss-Legendre radii in ln r (over the distribution's intensity_range) for 10 um gamma:0.2 fog, the
// extinction at the 48 wavelengths of the grid (360-830 nm) against the midpoint rule on radii 0.1 apart
// in x up to 3 mean radii (the tail beyond holds ~1e-10 of the drops). Measured: up to 1.9% off, 0.88%
// RMS (the reference agrees with steps of 0.05 to 1e-4; 1024 radii: 0.17%). Asserted: worst 1-3%, RMS
// 0.5-1.5%.
TEST(ClaimsRendererMedium, SixtyFourRadiiLeftTheSpectrumNoisy) {
  if (HYDROLUX_TEST_ASAN) GTEST_SKIP() << "170,000 Mie efficiencies: slow under ASan";
  const auto water = optics::find_medium("water");
  const auto air = optics::find_medium("air");
  const double mean = 10, w = 0.2;
  const SizeDistribution d = SizeDistribution::gamma(mean * 1e-6, w, 1.0);
  const auto [lo, hi] = intensity_range(d);
  const RadiusQuadrature q = d.quadrature(64, lo, hi, true);
  double worst = 0, sum2 = 0;
  int count = 0;
  for (int nm = 360; nm <= 830; nm += 10, ++count) {
    const SphereProblem sp = sphere_problem(1.0, nm, *water, *air);
    const double k = sp.x;  // per um
    const MieBulkOptics b = mie_bulk_optics(sp.m, k * 1e6, q, 1);
    double ext = 0, total = 0;
    const double dx = 0.1;
    for (double x = dx / 2; x < k * mean * 3; x += dx) {
      const double n = density(true, mean, w, x / k);
      if (n < 1e-300) continue;
      ext += n * mie_efficiencies(sp.m, x).qext * kPi * (x / k) * (x / k) * 1e-12;  // m^2
      total += n;
    }
    const double dev = b.extinction_per_m / (ext / total) - 1;  // the quadrature's N = 1 per m^3
    worst = std::max(worst, std::abs(dev));
    sum2 += dev * dev;
  }
  ASSERT_EQ(count, 48);
  const double rms = std::sqrt(sum2 / count);
  std::printf("64 radii: extinction up to %.4f off, %.4f RMS\n", worst, rms);
  EXPECT_GT(worst, 0.01);
  EXPECT_LT(worst, 0.03);
  EXPECT_GT(rms, 0.005);
  EXPECT_LT(rms, 0.015);
}

// docs/renderer-export.md l. 126-129 (and docs/mie.md l. 279-280): a count given below 4 radii per unit
// of the size parameters it covers gets a note (undersampled_ripple_note, which `hydrolux medium` and
// `hydrolux phase` share) that advises 8 per unit. Independently: such counts leave the average tens of
// per cent off at some angle, and the 8 per unit advised leave a few per cent on the mean over angles.
// Gauss-Legendre in ln r (`--nodes`), 2 um and 10 um gamma:0.2 at 550 nm, 181 angles, against the
// midpoint rule in x (steps 0.005 and 0.05; good to ~1e-3 and ~5e-3 of S11). Measured, worst angle /
// mean: 2 um 52/13%, 35/7.3%, 68/5.9% at 1, 2 and 3.9 per unit, 20/4.2% at 8; 10 um 25/4.7%, 14/2.4%,
// 23/1.7%, and 3.7/0.76% at 8.
TEST(ClaimsRendererMedium, ACountTooFewForTheRippleGetsANote) {
  if (HYDROLUX_TEST_ASAN) GTEST_SKIP() << "20,000 Mie solutions at 181 angles: slow under ASan";
  for (const double mean : {2.0, 10.0}) {
    SCOPED_TRACE(mean);
    PhaseJob probe = water_drops(mean, "gamma:0.2");
    probe.numbers.nodes = 64;
    const PhasePlan first = plan_phase(probe);
    const auto& r = first.quadrature.radius_m;
    const double span = (*std::max_element(r.begin(), r.end()) - *std::min_element(r.begin(), r.end())) *
                        first.problem.x / r.front();
    const Reference ref = midpoint_reference(first, true, mean, 0.2, mean < 5 ? 0.005 : 0.05);
    for (const double per_unit : {1.0, 2.0, 3.9, 8.0}) {
      PhaseJob job = water_drops(mean, "gamma:0.2");
      job.numbers.nodes = static_cast<int>(std::ceil(per_unit * span));
      const PhasePlan plan = plan_phase(job);
      const Errors e = errors(compute_phase(plan), ref);
      const bool noted = undersampled_ripple_note(plan).has_value();
      std::printf("%g um, %g per unit of x (%d radii): note %d, S11 off %.3f at worst, %.4f on the mean\n", mean,
                  per_unit, *job.numbers.nodes, int(noted), e.s11_worst, e.s11_mean);
      if (per_unit < 4) {
        EXPECT_TRUE(noted);
        EXPECT_GT(e.s11_worst, 0.12);  // tens of per cent at some angle
      } else {
        EXPECT_FALSE(noted);
        EXPECT_LT(e.s11_mean, 0.05);  // a few per cent on the mean over angles
        EXPECT_LT(e.s11_worst, 0.25);
      }
    }
  }
}

// docs/renderer-export.md, "Rain": a drop's intensity ripples in angle with periods down to pi / x (the
// far-field phase of a ray of impact parameter b grows as x b per radian of angle, and b spans [-1, 1]),
// far finer than a table holds at rain's sizes. Its spectrum over angle, written out here: one drop of
// x = 2000 (water at 550 nm), (|S1|^2 + |S2|^2) / 2 at 8192 angles over 60-120 degrees, the mean taken
// out, a Hann window, a plain DFT. Measured: 1.6e-11 of the power at frequencies above 1.05 x / pi
// (periods below pi / x), 14% between 0.1 x / pi and 1.05 x / pi (periods pi / x to 10 pi / x; the rest
// is the phase's slow trend over the 60 degrees), 11% between x / (2 pi) and 1.05 x / pi. Asserted:
// below 1e-3, above 5% and above 3%.
TEST(ClaimsRendererMedium, ADropsIntensityRipplesInAngleDownToPiOverX) {
  const SphereProblem sp = sphere_problem(1.0, 550, *optics::find_medium("water"), *optics::find_medium("air"));
  const double x = 2000;
  constexpr std::size_t kN = 8192;
  const double a = 60 * kPi / 180, b = 120 * kPi / 180, h = (b - a) / double(kN);
  std::vector<double> mu(kN), v(kN);
  for (std::size_t i = 0; i < kN; ++i) mu[i] = std::cos(a + (double(i) + 0.5) * h);
  std::vector<Complex> s1(kN), s2(kN);
  mie_amplitudes(mie_coefficients(sp.m, x), mu, s1, s2, 0);
  double mean = 0;
  for (std::size_t i = 0; i < kN; ++i) mean += (v[i] = (std::norm(s1[i]) + std::norm(s2[i])) / 2) / double(kN);
  for (std::size_t i = 0; i < kN; ++i) v[i] = (v[i] - mean) * 0.5 * (1 - std::cos(2 * kPi * (double(i) + 0.5) / kN));
  double above = 0, ripple = 0, fastest = 0, total = 0;
  const double span = b - a;
  for (std::size_t f = 1; f <= kN / 2; ++f) {  // f cycles over the span: f / span cycles per radian
    Complex sum = 0;
    for (std::size_t i = 0; i < kN; ++i) sum += v[i] * std::polar(1.0, -2 * kPi * double(f * i % kN) / kN);
    const double power = std::norm(sum), cycles_per_rad = double(f) / span;
    total += power;
    if (cycles_per_rad > 1.05 * x / kPi) above += power;
    else if (cycles_per_rad > 0.1 * x / kPi) ripple += power;
    if (cycles_per_rad > 0.5 * x / kPi && cycles_per_rad <= 1.05 * x / kPi) fastest += power;
  }
  std::printf("x = %g: power above x / pi %.2e of the whole, between 0.1 x / pi and x / pi %.3f, between x / (2 pi) "
              "and x / pi %.3f\n",
              x, above / total, ripple / total, fastest / total);
  EXPECT_LT(above / total, 1e-3);
  EXPECT_GT(ripple / total, 0.05);
  EXPECT_GT(fastest / total, 0.03);
}

// Marshall-Palmer rain at 5 mm/h and 550 nm (water in air), by a rule of this file: Marshall and Palmer's
// n(r) ~ exp(-Lambda r), Lambda = 8200 h^-0.21 m^-1 per unit radius, over 50-3000 um, summed by the
// midpoint rule on radii dx apart in x, no smoothing, at the cosines `mu`: the number-weighted means of
// (|S1|^2 + |S2|^2) / 2 (S11) and of k^2 C_sca (so that i / k2_csca is the phase per steradian,
// normalised over the sphere), on every core.
struct RainReference {
  std::vector<double> i;
  double k2_csca = 0;
  std::size_t radii = 0;
};
RainReference rain_reference(const std::vector<double>& mu, double dx) {
  const SphereProblem sp = sphere_problem(1.0, 550, *optics::find_medium("water"), *optics::find_medium("air"));
  const double k = sp.x;  // per um
  const double lambda_per_um = 8200 * std::pow(5.0, -0.21) * 1e-6;
  const double x_lo = k * 50, x_hi = k * 3000;
  const std::size_t n = std::size_t((x_hi - x_lo) / dx);
  const unsigned workers = std::max(1u, std::thread::hardware_concurrency());
  struct Sums {
    std::vector<double> i;
    double csca = 0, count = 0;
  };
  std::vector<std::future<Sums>> parts;
  for (unsigned w = 0; w < workers; ++w)
    parts.push_back(std::async(std::launch::async, [&, w] {
      Sums s{std::vector<double>(mu.size(), 0.0)};
      std::vector<Complex> s1(mu.size()), s2(mu.size());
      MieCoefficients c;
      for (std::size_t j = w; j < n; j += workers) {
        const double x = x_lo + (double(j) + 0.5) * dx;
        const double nr = std::exp(-lambda_per_um * x / k);
        mie_coefficients(sp.m, x, c);
        mie_amplitudes(c, mu, s1, s2, 1);
        for (std::size_t q = 0; q < mu.size(); ++q) s.i[q] += nr * (std::norm(s1[q]) + std::norm(s2[q])) / 2;
        s.csca += nr * mie_efficiencies(c).qsca * kPi * x * x;  // k^2 C_sca
        s.count += nr;
      }
      return s;
    }));
  RainReference ref{std::vector<double>(mu.size(), 0.0)};
  double count = 0;
  for (auto& f : parts) {
    const Sums s = f.get();
    for (std::size_t q = 0; q < mu.size(); ++q) ref.i[q] += s.i[q];
    ref.k2_csca += s.csca;
    count += s.count;
  }
  for (double& v : ref.i) v /= count;
  ref.k2_csca /= count;
  ref.radii = n;
  return ref;
}

// docs/renderer-export.md, "Rain": Marshall-Palmer rain's default table (5 mm/h at 550 nm: 64 radii, each
// radius's intensity smoothed over angle before the size average) against a size average by a rule of
// this file: Marshall and Palmer's n(r) ~ exp(-Lambda r), Lambda = 8200 h^-0.21 m^-1 per unit radius,
// over 50-3000 um, summed by the midpoint rule on radii 0.7 apart in x (48,158 radii), no smoothing.
// That rule moves by 2.4e-4 of the value on the mean and 5.6e-3 at worst from steps of 0.25 (grids not
// nested in each other; measured once, 40 angles). At 16 angles stratified in cos theta over [-1, 0.95]
// and 8 between 0.95 and the cut's edge (uniform in theta), the table (as interpolated, over its
// normalisation) against the reference times the same normalisation: the L1 over the sphere outside the
// cut, estimated by the midpoint rule over the strata and the trapezoid rule over the forward points.
// Measured: 0.0069, the stated table error plus size error 0.0131 (1.9 times), the mean relative error
// 2.0% (worst 10% at 117 degrees, where the phase is near its minimum). Asserted: within the default
// --max-error 0.05 with the estimate within a factor 3 of it, and below 0.015; the mean relative error
// below 5%. Just outside the primary bow the single radii's supernumeraries remain (their Airy fringes
// are wider than the window): at five angles over 141-143 degrees, 16% off at worst (asserted 5-40%).
TEST(ClaimsRendererMedium, RainsDefaultTableAgainstADenseSizeAverage) {
  if (HYDROLUX_TEST_ASAN) GTEST_SKIP() << "48,000 Mie solutions up to x = 34,000: slow under ASan";
  MediumJob job;
  job.size_distribution = "marshall-palmer:5";
  job.medium = optics::find_medium("water");
  job.surrounding = optics::find_medium("air");
  const MediumOptics o = run_medium_job(job);
  const TabulatedPhase& t = o.phase;
  ASSERT_TRUE(o.phase_smoothed && o.phase_size_l1);
  EXPECT_EQ(o.phase_radii, 64u);

  const double mu_c = std::cos(t.cut_deg * kPi / 180), mu_split = 0.95;
  ASSERT_LT(mu_split, mu_c);
  std::vector<double> mu, width;  // width: the stratum's (0: a forward point, trapezoid rule)
  for (int i = 0; i < 16; ++i) mu.push_back(-1 + (i + 0.5) * (mu_split + 1) / 16), width.push_back((mu_split + 1) / 16);
  const double th_split = std::acos(mu_split), th_c = t.cut_deg * kPi / 180;
  for (int i = 0; i < 8; ++i) mu.push_back(std::cos(th_split + (th_c - th_split) * i / 7.0)), width.push_back(0);

  // Besides, 141-143 degrees: just outside the primary bow, where the single radii's supernumeraries remain.
  const std::size_t spread = mu.size();
  std::vector<double> at = mu;
  for (const double deg : {141.0, 141.5, 142.0, 142.5, 143.0}) at.push_back(std::cos(deg * kPi / 180));
  const RainReference ref = rain_reference(at, 0.7);
  const auto table_at = [&](double m) {  // linear in mu, as a renderer reads it
    const double u = (m + 1) / 2 * double(t.values.size() - 1);
    const std::size_t j = std::min(std::size_t(u), t.values.size() - 2);
    return t.values[j] + (t.values[j + 1] - t.values[j]) * (u - double(j));
  };
  double l1 = 0, mean_rel = 0, worst = 0, worst_deg = 0;
  std::vector<double> diff(mu.size());
  for (std::size_t i = 0; i < mu.size(); ++i) {
    const double want = ref.i[i] / ref.k2_csca * t.normalisation, got = table_at(mu[i]);
    diff[i] = std::abs(got - want);
    const double rel = diff[i] / want;
    mean_rel += rel / double(mu.size());
    if (rel > worst) worst = rel, worst_deg = std::acos(mu[i]) * 180 / kPi;
    if (width[i] > 0) l1 += 2 * kPi * diff[i] * width[i];
  }
  for (std::size_t i = 17; i < mu.size(); ++i) l1 += 2 * kPi * (diff[i - 1] + diff[i]) / 2 * (mu[i] - mu[i - 1]);
  double bow_worst = 0;
  for (std::size_t i = spread; i < at.size(); ++i) {
    const double want = ref.i[i] / ref.k2_csca * t.normalisation;
    bow_worst = std::max(bow_worst, std::abs(table_at(at[i]) - want) / want);
  }
  std::printf("rain: at 141-143 degrees off by %.3f at worst\n", bow_worst);
  EXPECT_GT(bow_worst, 0.05);  // the supernumeraries of the single radii: see above
  EXPECT_LT(bow_worst, 0.4);
  const double stated = t.l1_error + *o.phase_size_l1;
  std::printf("rain: L1 %.4f against %zu radii (stated %.4f: table %.4f + size %.4f); relative error mean %.4f, worst "
              "%.3f at %.1f deg\n",
              l1, ref.radii, stated, t.l1_error, *o.phase_size_l1, mean_rel, worst, worst_deg);
  EXPECT_TRUE(t.target_met);
  EXPECT_LT(l1, job.numbers.max_error);
  EXPECT_LT(l1, 0.015);
  EXPECT_GT(stated, l1 / 3);
  EXPECT_LT(stated, 3 * l1);
  EXPECT_LT(mean_rel, 0.05);
}

// docs/mie.md, "Size averages": the phase job's default size average of Marshall-Palmer rain (5 mm/h,
// 550 nm), S11 at 16 angles from 2 to 178 degrees, against rain_reference (0.7 apart in x). Not run by
// ctest (the job alone refines to 262,145 radii, minutes on two cores): run it by hand with
// --gtest_also_run_disabled_tests (4.5 minutes here). Measured 2026-12-06: 262,145 radii (converged: last
// change 1.3e-3), S11 within 1.1e-4 of the reference at every angle (worst at 178 degrees); its estimated
// error, 2.0e-3, is 18 times that, an upper bound here (the reference moves by up to 5.6e-3 from a step
// of 0.25 at its worst angle, so the factor is not resolved). Asserted: within the tolerance.
TEST(ClaimsRendererMedium, DISABLED_RainsPhaseJobAgainstADenseSizeAverage) {
  PhaseJob job;
  job.size_distribution = "marshall-palmer:5";
  job.wavelength_nm = 550;
  job.medium = optics::find_medium("water");
  job.surrounding = optics::find_medium("air");
  job.numbers.mueller = true;
  for (double a = 2; a <= 178; a += 11.7333333333) job.angles_deg.push_back(a);
  std::vector<double> mu;
  for (const double a : job.angles_deg) mu.push_back(std::cos(a * kPi / 180));
  const PhaseResult got = run_phase_job(job);
  const RainReference ref = rain_reference(mu, 0.7);
  ASSERT_TRUE(got.mueller && got.error);
  double worst = 0, worst_deg = 0;
  for (std::size_t q = 0; q < mu.size(); ++q) {
    const double e = std::abs(got.mueller->s11[q] / ref.i[q] - 1);
    if (e > worst) worst = e, worst_deg = job.angles_deg[q];
  }
  std::printf("rain's phase job: %zu radii, last change %.3g, estimated S11 error %.3g; S11 off %.3g at worst (%.1f "
              "deg); notes %zu\n",
              got.radii, got.last_change.value_or(-1), got.error->s11, worst, worst_deg, got.notes.size());
  for (const auto& note : got.notes) std::printf("  note: %s\n", note.c_str());
  EXPECT_LT(worst, job.numbers.tolerance);
}

}  // namespace
}  // namespace hydrolux::scatter
