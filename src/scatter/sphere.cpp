#include "hydrolux/scatter/sphere.hpp"

#include "hydrolux/core/error.hpp"
#include "hydrolux/core/math.hpp"

namespace hydrolux::scatter {

SphereProblem sphere_problem(double radius_um, double wavelength_nm, const optics::Medium& sphere,
                             const optics::Medium& surrounding,
                             std::optional<double> temperature_c) {
  require_in_range("radius_um", radius_um, 1e-6, 1e6);
  const auto temp_for = [&](const optics::Medium& m) {
    return m.info().temperature_dependent ? temperature_c : std::nullopt;
  };
  SphereProblem p;
  p.n_sphere = sphere.index(wavelength_nm, temp_for(sphere));
  p.n_surrounding = surrounding.index(wavelength_nm, temp_for(surrounding)).real();
  p.m = p.n_sphere / p.n_surrounding;
  p.x = 2 * kPi<> * radius_um * 1e3 * p.n_surrounding / wavelength_nm;
  return p;
}

}  // namespace hydrolux::scatter
