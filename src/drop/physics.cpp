#include "hydrolux/drop/physics.hpp"

#include <cmath>

#include "hydrolux/core/embedded_data.hpp"
#include "hydrolux/core/error.hpp"
#include "hydrolux/core/table.hpp"

namespace hydrolux::drop {

namespace {
const Table& gunn_kinzer() {
  static const Table t = parse_table(embedded_file("drop/gunn_kinzer_1949.csv"), "drop/gunn_kinzer_1949.csv");
  return t;
}
}  // namespace

double terminal_velocity_fit_mps(double radius_m) {
  require_in_range("radius_m", radius_m, 0.0, 1.0);
  return 200.0 * std::sqrt(radius_m);
}

std::array<double, 2> gunn_kinzer_radius_range_m() {
  const auto d = gunn_kinzer().column("diameter_mm");
  return {d.front() * 0.5e-3, d.back() * 0.5e-3};
}

double terminal_velocity_gunn_kinzer_mps(double radius_m) {
  const auto& t = gunn_kinzer();
  const auto range = gunn_kinzer_radius_range_m();
  require_in_range("radius_m", radius_m, range[0], range[1], "Gunn & Kinzer (1949)");
  return interpolate_linear(t.column("diameter_mm"), t.column("velocity_mps"), 2e3 * radius_m);
}

}  // namespace hydrolux::drop
