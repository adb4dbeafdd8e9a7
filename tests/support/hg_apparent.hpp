#pragma once
// Henyey-Greenstein's apparent phase function in closed form, for the fog's glow (rain/fog.hpp): the
// phase p(u) = (1 - g^2) / ((1 - g)^2 + 4 g u^2)^(3/2) with u = sin(theta / 2) (cos theta = 1 - 2 u^2),
// normalised as docs/fog.md's (integral_0^1 p 2 u du = 1). With integral dv / (a^2 + b^2 v^2)^(3/2) =
// v / (a^2 sqrt(a^2 + b^2 v^2)), a = 1 - g, b^2 = 4 g, a^2 + b^2 = (1 + g)^2:
//   P(u) = integral_u^1 p dv = (1 + g) / (1 - g) [1 / (1 + g) - u / sqrt((1 - g)^2 + 4 g u^2)],
//   p_app(u) = P(u) / u,
//   F_app(u) = integral_0^u 2 P dw = 2 (1 + g) / (1 - g) [u / (1 + g) - (sqrt((1 - g)^2 + 4 g u^2) - (1 - g)) / (4 g)],
// the fraction of the once-scattered light within the apparent cap of half-angle 2 asin(u) when the
// scatterers are spread evenly along the path; F_app(1) = 1.
#include <cmath>
#include <cstddef>

#include "hydrolux/rain/fog.hpp"

namespace hydrolux::testing {

inline double hg_app_P(double u, double g) {
  return (1 + g) / (1 - g) * (1 / (1 + g) - u / std::sqrt((1 - g) * (1 - g) + 4 * g * u * u));
}
inline double hg_app_F(double u, double g) {
  return 2 * (1 + g) / (1 - g) * (u / (1 + g) - (std::sqrt((1 - g) * (1 - g) + 4 * g * u * u) - (1 - g)) / (4 * g));
}

// The apparent table filled from the closed forms (not from PhaseTable::apparent()): the renderer reads
// p_app(u) = P(u) / u and F_app by linear interpolation on these n nodes.
inline rain::PhaseTable hg_apparent_table(double g, int n) {
  rain::PhaseTable t;
  t.divided_by_u = true;
  t.p.resize(std::size_t(n));
  t.cum.resize(std::size_t(n));
  for (int i = 0; i < n; ++i) {
    const double u = double(i) / (n - 1);
    t.p[std::size_t(i)] = hg_app_P(u, g);
    t.cum[std::size_t(i)] = hg_app_F(u, g);
  }
  return t;
}

}  // namespace hydrolux::testing
