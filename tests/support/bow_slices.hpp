#pragma once
// Synthetic Lee-table slices for the compositor's tests (tests/scene/).
#include <cstddef>

#include "hydrolux/scene/compositor.hpp"

namespace hydrolux::test {

// A slice on the angle axis over [a0, a1] degrees with `rows` rows whose RGB is f(theta).
template <typename F>
scene::BowSlice synthetic_slice(double a0, double a1, int rows, F f) {
  scene::BowSlice s;
  s.first = float(a0);
  s.last = float(a1);
  s.rows = rows;
  s.rgb.resize(std::size_t(rows) * 3);
  for (int i = 0; i < rows; ++i) {
    const auto v = f(a0 + (a1 - a0) * i / (rows - 1));
    for (std::size_t k = 0; k < 3; ++k) s.rgb[std::size_t(i) * 3 + k] = float(v[k]);
  }
  return s;
}

}  // namespace hydrolux::test
