#pragma once
// A size average by a rule of the tests' own, for the claims of the phase job and the medium
// (tests/scatter/test_claims_phase_average.cpp, test_claims_renderer_medium.cpp): the distribution's
// number density written out (gamma: r^(alpha - 1) exp(-r / beta), alpha = 1 / w^2, beta = mean w^2;
// log-normal: ln r normal with s^2 = ln(1 + w^2), mu = ln(mean) - s^2 / 2; as size_distribution.hpp
// defines them), summed by the midpoint rule on radii evenly spaced in the size parameter, with the
// library's single-sphere Mie as the integrand.
#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>
#include <string>
#include <vector>

#include "hydrolux/optics/media.hpp"
#include "hydrolux/scatter/amplitudes.hpp"
#include "hydrolux/scatter/mie.hpp"
#include "hydrolux/scatter/phase_job.hpp"

namespace hydrolux::scatter::size_reference {

inline constexpr double kPi = std::numbers::pi;

inline std::vector<double> every_degree() {
  std::vector<double> deg;
  for (int a = 0; a <= 180; ++a) deg.push_back(a);
  return deg;
}

inline PhaseJob water_drops(double mean_um, const std::string& distribution) {
  PhaseJob job;
  job.radius_um = mean_um;
  job.size_distribution = distribution;
  job.wavelength_nm = 550;
  job.medium = optics::find_medium("water");
  job.surrounding = optics::find_medium("air");
  job.angles_deg = every_degree();
  job.numbers.mueller = true;
  return job;
}

// The number density, unnormalised (r and mean in um).
inline double density(bool gamma, double mean, double w, double r) {
  if (gamma) {
    const double alpha = 1 / (w * w), beta = mean * w * w;
    return std::exp((alpha - 1) * std::log(r / mean) - (r - mean) / beta);
  }
  const double s2 = std::log(1 + w * w), mu = std::log(mean) - s2 / 2;
  const double l = std::log(r) - mu;
  return std::exp(-l * l / (2 * s2)) / r;
}

// S11 and S12 of the number-weighted mean (Bohren & Huffman eq. 4.77: (i1 + i2) / 2, (i2 - i1) / 2),
// at every degree, for the job's index and wavelength.
struct Reference {
  std::vector<double> s11, s12;
};
inline Reference midpoint_reference(const PhasePlan& plan, bool gamma, double mean, double w, double dx) {
  const double k = 2 * kPi * plan.problem.n_surrounding / (plan.job.wavelength_nm * 1e-3);  // per um
  double r_hi = mean, peak = 0;
  for (double r = mean / 100; r < 100 * mean; r *= 1.01) {
    const double v = std::pow(r, 4) * density(gamma, mean, w, r);
    peak = std::max(peak, v);
    if (v > 1e-14 * peak) r_hi = r;
  }
  const std::size_t angles = plan.job.angles_deg.size();
  std::vector<double> mu(angles);
  for (std::size_t i = 0; i < angles; ++i) mu[i] = std::cos(plan.job.angles_deg[i] * kPi / 180);
  std::vector<Complex> s1(mu.size()), s2(mu.size());
  std::vector<double> i1(mu.size(), 0.0), i2(mu.size(), 0.0);
  double total = 0;
  MieCoefficients c;
  for (double x = dx / 2; x < k * r_hi; x += dx) {
    const double n = density(gamma, mean, w, x / k);
    if (n < 1e-300) continue;
    mie_coefficients(plan.problem.m, x, c);
    mie_amplitudes(c, mu, s1, s2, 1);
    for (std::size_t i = 0; i < mu.size(); ++i) {
      i1[i] += n * std::norm(s1[i]);
      i2[i] += n * std::norm(s2[i]);
    }
    total += n;
  }
  Reference ref{std::vector<double>(angles), std::vector<double>(angles)};
  for (std::size_t i = 0; i < angles; ++i) {
    ref.s11[i] = (i1[i] + i2[i]) / 2 / total;
    ref.s12[i] = (i2[i] - i1[i]) / 2 / total;
  }
  return ref;
}

// The result's errors against the reference, relative to the reference's S11 at each angle.
struct Errors {
  double s11_worst = 0, s11_mean = 0, s12_worst = 0;
  double worst_deg = 0;
};
inline Errors errors(const PhaseResult& got, const Reference& ref) {
  Errors e;
  for (std::size_t i = 0; i < ref.s11.size(); ++i) {
    const double d11 = std::abs(got.mueller->s11[i] / ref.s11[i] - 1);
    if (d11 > e.s11_worst) {
      e.s11_worst = d11;
      e.worst_deg = got.angles_deg[i];
    }
    e.s11_mean += d11 / double(ref.s11.size());
    e.s12_worst = std::max(e.s12_worst, std::abs(got.mueller->s12[i] - ref.s12[i]) / ref.s11[i]);
  }
  return e;
}

}  // namespace hydrolux::scatter::size_reference
