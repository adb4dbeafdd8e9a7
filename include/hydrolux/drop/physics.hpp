#pragma once
// Physical properties of rain drops (Garg & Nayar 2004, section 2; seed 000). Radii are
// equivalent-sphere radii in metres. The Marshall-Palmer size distribution lives with the other
// size distributions: scatter::SizeDistribution::marshall_palmer (size_distribution.hpp).
#include <array>

namespace hydrolux::drop {

// The paper's terminal-velocity fit v = 200 sqrt(a) (m/s, a in metres), after Gunn & Kinzer (1949).
// Against their measurements it holds within 11% for radii 0.5-2.5 mm (diameters 1-5 mm) and within
// 6% for 0.6-2.2 mm; it overestimates small drops badly (+54% at a = 0.25 mm, +424% at 0.05 mm) and
// large ones by up to 17% (a = 2.9 mm). tests/drop/test_physics.cpp pins these numbers.
double terminal_velocity_fit_mps(double radius_m);

// Gunn & Kinzer's measured terminal velocities (1949; stagnant air, 1013 hPa, 20 C), interpolated
// linearly in diameter between their drops (data/drop/gunn_kinzer_1949.csv). DomainError
// ("radius_m") outside the table's range, gunn_kinzer_radius_range_m().
double terminal_velocity_gunn_kinzer_mps(double radius_m);
std::array<double, 2> gunn_kinzer_radius_range_m();

}  // namespace hydrolux::drop
