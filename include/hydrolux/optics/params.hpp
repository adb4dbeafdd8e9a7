#pragma once
// What a user sets for one interface's Fresnel coefficients (hydrolux fresnel) and a medium's
// refractive index (hydrolux ior), declared once (core/params.hpp): each number's name, unit, range,
// default and help. The defaults are the requests' initializers. The medium is a name the door
// resolves (optics::find_medium); ior's wavelength, whose range is open at 0, stays with the door.
#include <optional>
#include <span>
#include <string_view>

#include "hydrolux/core/params.hpp"

namespace hydrolux::optics {

struct FresnelRequest {
  double n1 = 1.0;                   // the incident medium's index (real)
  double n2 = 1.333;                 // the second medium's index, real part
  double k2 = 0.0;                   // its extinction coefficient: > 0 an absorbing medium
  std::optional<double> theta_deg;   // the angle of incidence: no default, the door requires it
};

struct IorRequest {
  std::optional<double> temperature_c;  // of a medium that models it (water); else its own
};

// Indices from 1e-3 (below any known material's, epsilon-near-zero films included) to 1e3: within
// this range every quantity is computed to full precision (tests/optics/test_fresnel.cpp); far
// below it, n^2 underflows and the results go wrong.
inline constexpr double kMinFresnelIndex = 1e-3, kMaxFresnelIndex = 1e3;

std::span<const Field<FresnelRequest>> fresnel_params();
std::span<const Field<IorRequest>> ior_params();

}  // namespace hydrolux::optics
