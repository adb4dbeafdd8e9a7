// libFuzzer target: size-distribution specs (scatter::parse_size_distribution, the CLI's
// --size-distribution) and, for accepted ones, the distribution and its intensity quadrature:
// finite, non-negative weights that add up to a positive number.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "hydrolux/core/error.hpp"
#include "hydrolux/scatter/size_distribution.hpp"
#include "hydrolux/scatter/theories.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace hydrolux::scatter;
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const auto spec = parse_size_distribution(text);
    RadiusQuadrature q;
    switch (spec.kind) {
      case SizeDistributionKind::monodisperse: q = SizeDistribution::monodisperse(10e-6).quadrature(1); break;
      case SizeDistributionKind::gamma: q = intensity_quadrature(SizeDistribution::gamma(10e-6, spec.parameter), 16); break;
      case SizeDistributionKind::log_normal:
        q = intensity_quadrature(SizeDistribution::log_normal(10e-6, spec.parameter), 16);
        break;
      case SizeDistributionKind::marshall_palmer:
        q = SizeDistribution::marshall_palmer(spec.parameter).quadrature(16, 50e-6, 3000e-6);
        break;
    }
    double total = 0;
    for (std::size_t i = 0; i < q.size(); ++i) {
      if (!std::isfinite(q.weight[i]) || q.weight[i] < 0 || !(q.radius_m[i] > 0)) std::abort();
      total += q.weight[i];
    }
    if (!(total > 0)) std::abort();  // an accepted spec must give drops to average over
  } catch (const hydrolux::Error&) {
  }
  return 0;
}
