#pragma once
// From a physical drop to the dimensionless Mie problem: relative index m and size parameter x.
#include <optional>

#include "hydrolux/optics/media.hpp"
#include "hydrolux/scatter/mie.hpp"

namespace hydrolux::scatter {

struct SphereProblem {
  Complex m;              // index of the sphere relative to the surrounding medium
  double x = 0;           // 2 pi r n_surrounding / lambda_vacuum
  Complex n_sphere;       // absolute indices at this wavelength
  double n_surrounding = 1;
};

// A sphere of radius `radius_um` (micrometres) of medium `sphere` in `surrounding` (real part used:
// a surrounding medium must be transparent), lit at vacuum wavelength `wavelength_nm`. The
// temperature goes to the media that model it. Throws DomainError outside the media's ranges.
SphereProblem sphere_problem(double radius_um, double wavelength_nm, const optics::Medium& sphere,
                             const optics::Medium& surrounding,
                             std::optional<double> temperature_c = {});

}  // namespace hydrolux::scatter
