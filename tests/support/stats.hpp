#pragma once
// Statistical test harness shared by the tests: chi-square goodness of fit of a direction sampler
// against its pdf on the sphere, the chi-square distribution's tail, and Monte Carlo integrals of
// f |cos| (furnace tests). Everything is seeded explicitly (hydrolux::Rng): a test run is
// reproducible bit for bit.
//
// Chi-square test (after pbrt-v4's bsdfs_test.cpp, which follows the classical Pearson test):
//   1. Draw N samples from the sampler and histogram their directions on a theta x phi grid
//      (theta in [0, pi] from +z, phi in [0, 2 pi) from +x; default 80 x 160 cells, N = 1e6).
//   2. Expected counts E_k = N int_cell pdf dw, integrated numerically: composite Simpson in theta
//      (with the sin theta of dw) and phi on a sub-grid of 2 `subdivisions` intervals per cell and
//      axis, the pdf evaluated once per node of a shared global grid (0.8 M evaluations by
//      default). The integral of the pdf over the sphere is reported; for the lobes tested here
//      it is within 2e-5 of its true value.
//      A row of nodes on a boundary between cell rows is evaluated just inside each row, so that a
//      pdf that jumps there (at the horizon) is integrated correctly on both sides.
//   3. Cells with E_k < 5 (Cochran's rule) are pooled into one cell (made up to >= 5 with the next
//      smallest cells if needed); the statistic X^2 = sum (O - E)^2 / E over the pooled table has
//      dof = cells - 1 and p = Q(dof / 2, X^2 / 2), Q the regularised upper incomplete gamma.
//      More than 1e-5 N samples in a cell whose expected count is exactly 0 reject outright.
//   A sampler may fail (return nothing): failures are counted in no cell, and its pdf then
//   integrates to less than one, which lowers the expected counts by the same amount. (Over the
//   cells only, E[X^2] = cells - 1 + q for a failure probability q: the difference is negligible
//   against thousands of cells.)
//   Significance: a test file that runs n chi-square tests compares each p with the Sidak-corrected
//   level 1 - (1 - 0.01)^(1/n), so that the whole file fails by chance with probability 1 %.
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "hydrolux/core/random.hpp"
#include "hydrolux/core/vec.hpp"
#include "hydrolux/optics/bsdf.hpp"

namespace hydrolux::test {

// ------------------------------------------------------------------------------------------------
// Special functions
// ------------------------------------------------------------------------------------------------

// Regularised incomplete gamma functions P(a, x) = gamma(a, x) / Gamma(a) and Q = 1 - P, a > 0,
// x >= 0: series (A&S 6.5.29) for x < a + 1, Legendre's continued fraction (A&S 6.5.31) evaluated
// by the modified Lentz method otherwise (Numerical Recipes 3rd ed. §6.2 describes the pair).
// Whichever of P, Q is small is computed directly, so tails keep their relative accuracy.
double regularized_gamma_p(double a, double x);
double regularized_gamma_q(double a, double x);

// Upper tail of the chi-square distribution with dof degrees of freedom: Q(dof / 2, x / 2).
double chi_square_survival(double x, double dof);

// Per-run significance for a family-wise level `alpha` over `runs` independent runs (Sidak).
double sidak_alpha(double alpha, int runs);

// Gauss-Legendre nodes and weights on [a, b] (n nodes; Newton on P_n, Golub-Welsch not needed).
struct Quadrature {
  std::vector<double> x, w;
};
Quadrature gauss_legendre(int n, double a, double b);

// ------------------------------------------------------------------------------------------------
// Chi-square goodness of fit on the sphere
// ------------------------------------------------------------------------------------------------

// Draws one direction (unit vector) from the random stream, or nothing when the sampler fails.
using DirectionSampler = std::function<std::optional<Vec3>(Rng&)>;
// Solid-angle density of the sampler at a unit direction.
using DirectionPdf = std::function<double(const Vec3&)>;

struct ChiSquareConfig {
  int theta_bins = 80;
  int phi_bins = 160;
  std::int64_t samples = 1'000'000;
  int subdivisions = 4;  // Simpson panel pairs per cell and axis (2x this intervals)
  double min_expected = 5.0;
  std::uint64_t seed = 1;
};

struct ChiSquareResult {
  double statistic = 0;  // X^2
  int dof = 0;           // cells after pooling - 1
  double p_value = 1;    // P(chi2_dof >= X^2)
  std::int64_t samples = 0;
  std::int64_t failures = 0;     // sampler returned nothing
  double pdf_integral = 0;       // int pdf over the sphere (numerical)
  int pooled_cells = 0;          // cells merged into the pooled cell
  std::string describe() const;  // one line for test failure messages
};

// Histogram of sample directions (row-major, theta rows); failures counted separately.
struct Histogram {
  std::vector<std::int64_t> counts;
  std::int64_t failures = 0;
};
Histogram sample_histogram(const DirectionSampler& sampler, const ChiSquareConfig& config);

// N * int_cell pdf for every cell (row-major, theta rows).
std::vector<double> expected_counts(const DirectionPdf& pdf, const ChiSquareConfig& config);

// Pearson test of observed against expected counts, with the pooling described above.
ChiSquareResult chi_square_from_counts(const std::vector<std::int64_t>& observed,
                                       const std::vector<double>& expected,
                                       double min_expected = 5.0);

// The whole test: histogram, expected counts, statistic and p-value.
ChiSquareResult chi_square_test(const DirectionSampler& sampler, const DirectionPdf& pdf,
                                const ChiSquareConfig& config = {});

// Chi-square of a BxDF's sample() against its pdf() for a fixed wo (delta samples are failures:
// they carry no density).
ChiSquareResult chi_square_bxdf(const optics::BxDF& bxdf, const Vec3& wo,
                                const ChiSquareConfig& config = {});

// ------------------------------------------------------------------------------------------------
// Monte Carlo integrals
// ------------------------------------------------------------------------------------------------

struct Estimate {
  double mean = 0;
  double std_error = 0;  // sample standard deviation / sqrt(n)
  std::int64_t n = 0;
};

// Mean of g over n draws of a stream seeded with `seed` (Welford's running variance).
Estimate monte_carlo(std::int64_t n, std::uint64_t seed, const std::function<double(Rng&)>& g);

// Which directions wi an albedo integral counts.
enum class Hemisphere { All, Reflection, Transmission };

// int f(wo, wi) |cos theta_i| dwi over the chosen wi, estimated with the BxDF's own sampling:
// mean of f |cos| / pdf (0 for a failed sample or a wi outside `which`). Includes delta lobes.
Estimate integrate_f_cos(const optics::BxDF& bxdf, const Vec3& wo, optics::TransportMode mode,
                         std::int64_t n, std::uint64_t seed, Hemisphere which = Hemisphere::All);

// The same integral with directions drawn uniformly on the sphere (pdf 1 / (4 pi)): independent of
// the BxDF's sampler, so the two estimates cross-check f, pdf and sample(). Misses delta lobes.
Estimate integrate_f_cos_uniform(const optics::BxDF& bxdf, const Vec3& wo,
                                 optics::TransportMode mode, std::int64_t n, std::uint64_t seed,
                                 Hemisphere which = Hemisphere::All);

// Uniform direction on the unit sphere from two uniforms.
Vec3 uniform_sphere(double u1, double u2);
// The same from the next two draws of `rng` (u1 first), for tests that need random directions.
Vec3 uniform_sphere(Rng& rng);

}  // namespace hydrolux::test
