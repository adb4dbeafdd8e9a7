#pragma once
// What a user sets for a rain drop's physical properties (hydrolux rainphys) and Garg & Nayar's
// radiance profile (hydrolux drop profile), declared once (core/params.hpp): each number's name,
// unit, range, default and help; the defaults are the requests' initializers.
#include <span>

#include "hydrolux/core/params.hpp"

namespace hydrolux::drop {

struct RainphysRequest {
  double radius_mm = 1.0;       // the drop's equivalent-volume radius: the shape table's range
  double rain_rate_mmh = 30.0;  // of the Marshall-Palmer distribution
};

struct DropProfileRequest {
  double mu = 1.333;  // the drop's index relative to the air
  int samples = 101;  // rho values from 0 to 1
};

std::span<const Field<RainphysRequest>> rainphys_params();
std::span<const Field<DropProfileRequest>> drop_profile_params();

}  // namespace hydrolux::drop
