#pragma once
// Water's refractive index written out for the tests, apart from the library's tables (optics/media):
// at 20 C relative to vacuum, the Sellmeier fit of M. Daimon and A. Masumura, Appl. Opt. 46, 3811
// (2007), 20.0 C (coefficients as tabulated by refractiveindex.info); lambda in um.
#include <cmath>

namespace hydrolux::test_support {

inline double water_daimon_masumura_20c(double um) {
  const double c[8] = {5.684027565e-1, 5.101829712e-3, 1.726177391e-1, 1.821153936e-2,
                       2.086189578e-2, 2.620722293e-2, 1.130748688e-1, 1.069792721e1};
  const double l2 = um * um;
  double s = 1;
  for (int i = 0; i < 4; ++i) s += c[2 * i] * l2 / (l2 - c[2 * i + 1]);
  return std::sqrt(s);
}

}  // namespace hydrolux::test_support
