#include "hydrolux/scatter/theories.hpp"

#include <fmt/format.h>

#include <algorithm>

#include <charconv>
#include <cmath>
#include <vector>

#include "hydrolux/core/error.hpp"
#include "hydrolux/scatter/airy.hpp"
#include "hydrolux/scatter/amplitudes.hpp"
#include "hydrolux/scatter/debye.hpp"
#include "hydrolux/scatter/geometric.hpp"
#include "hydrolux/scatter/sphere.hpp"

namespace hydrolux::scatter {

namespace {
constexpr const char* kTheories = "mie, debye:P, airy[:P], geometric[:P]";

int parse_order(std::string_view text, std::string_view whole) {
  int p = 0;
  const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), p);
  if (ec != std::errc() || ptr != text.data() + text.size())
    throw UnknownNameError(fmt::format("theory '{}': the order must be a whole number; valid: {}", whole, kTheories));
  return p;
}
}  // namespace

Theory parse_theory(std::string_view text) {
  const auto colon = text.find(':');
  const std::string_view name = text.substr(0, colon);
  const bool has_p = colon != std::string_view::npos;
  const int p = has_p ? parse_order(text.substr(colon + 1), text) : -1;
  if (name == "mie" && !has_p) return {TheoryKind::Mie, 0};
  if (name == "debye" && has_p) {
    require_in_range("p", p, 0, kMaxDebyeOrder, "the Debye series");
    return {TheoryKind::Debye, p};
  }
  if (name == "airy") {
    const int order = has_p ? p : 2;
    require_in_range("p", order, 2, 20, "Airy theory (rainbow orders)");
    return {TheoryKind::Airy, order};
  }
  if (name == "geometric") {
    const int order = has_p ? p : 3;
    require_in_range("p", order, 0, 50, "geometric optics");
    return {TheoryKind::Geometric, order};
  }
  throw UnknownNameError(fmt::format("unknown theory '{}'; valid: {}", text, kTheories));
}

std::string theory_name(const Theory& t) {
  switch (t.kind) {
    case TheoryKind::Mie: return "mie";
    case TheoryKind::Debye: return fmt::format("debye:{}", t.p);
    case TheoryKind::Airy: return fmt::format("airy:{}", t.p);
    case TheoryKind::Geometric: return fmt::format("geometric:{}", t.p);
  }
  return "?";
}

void amplitudes(const Theory& t, Complex m, double x, std::span<const double> theta_rad,
                std::span<Complex> s1, std::span<Complex> s2, int threads) {
  std::vector<double> mu(theta_rad.size());
  for (std::size_t i = 0; i < mu.size(); ++i) mu[i] = std::cos(theta_rad[i]);
  switch (t.kind) {
    case TheoryKind::Mie: return mie_amplitudes(mie_coefficients(m, x), mu, s1, s2, threads);
    case TheoryKind::Debye: return mie_amplitudes(debye_coefficients(m, x, t.p), mu, s1, s2, threads);
    case TheoryKind::Airy:
      // Airy theory needs a real index between 1 and p (a rainbow of order p exists).
      require_in_range("m_real", m.real(), 1.0 + 1e-9, double(t.p) - 1e-9, theory_name(t));
      return airy_amplitudes(m.real(), x, t.p, theta_rad, s1, s2);
    case TheoryKind::Geometric:
      return geometric_amplitudes(m, x, t.p, theta_rad, s1, s2, /*diffraction=*/true);
  }
}

RadiusQuadrature intensity_quadrature(const SizeDistribution& d, int nodes) {
  switch (d.kind()) {
    case SizeDistributionKind::monodisperse: return d.quadrature(1);
    case SizeDistributionKind::gamma: {
      // Ten standard deviations (sqrt(a) b) either side of the mean a b, the lower end kept above
      // a thousandth of the mean for wide distributions. A fixed lower end at 1e-3 of the mean put
      // every node outside the peak of a narrow distribution (relative width 1e-3: 64 nodes 1.6%
      // apart across a peak 0.1% wide).
      const double a = d.alpha(), b = d.beta();
      const double lo = std::max(1e-3 * d.mean_radius(), b * (a - 10 * std::sqrt(a)));
      return d.quadrature(nodes, lo, b * (a + 4 + 10 * std::sqrt(a + 4)), true);
    }
    case SizeDistributionKind::log_normal: {
      const double mu = d.mu(), s = d.sigma();
      return d.quadrature(nodes, std::exp(mu - 8 * s), std::exp(mu + 4 * s * s + 8 * s), true);
    }
    case SizeDistributionKind::marshall_palmer: break;
  }
  throw Error("intensity_quadrature: give Marshall-Palmer rain its radius range explicitly");
}

Intensities average_intensities(const Theory& t, const RadiusQuadrature& q, double wavelength_nm,
                                const optics::Medium& drop, const optics::Medium& surrounding,
                                std::optional<double> temperature_c, std::span<const double> theta_rad,
                                int threads, const ProgressFn& progress) {
  Intensities out{std::vector<double>(theta_rad.size()), std::vector<double>(theta_rad.size()),
                  std::vector<Complex>(theta_rad.size())};
  std::vector<Complex> s1(theta_rad.size()), s2(theta_rad.size());
  double total = 0;
  for (std::size_t k = 0; k < q.radius_m.size(); ++k) {
    const auto sp = sphere_problem(q.radius_m[k] * 1e6, wavelength_nm, drop, surrounding, temperature_c);
    amplitudes(t, sp.m, sp.x, theta_rad, s1, s2, threads);
    for (std::size_t i = 0; i < theta_rad.size(); ++i) {
      out.i1[i] += q.weight[k] * std::norm(s1[i]);
      out.i2[i] += q.weight[k] * std::norm(s2[i]);
      out.s2_s1conj[i] += q.weight[k] * (s2[i] * std::conj(s1[i]));
    }
    total += q.weight[k];
    if (progress)
      progress(double(k + 1) / double(q.radius_m.size()),
               fmt::format("radius {:.4g} um ({}/{})", q.radius_m[k] * 1e6, k + 1, q.radius_m.size()));
  }
  if (!(total > 0)) throw Error("size distribution: the quadrature has no weight");
  for (std::size_t i = 0; i < theta_rad.size(); ++i) {
    out.i1[i] /= total;
    out.i2[i] /= total;
    out.s2_s1conj[i] /= total;
  }
  return out;
}

}  // namespace hydrolux::scatter
