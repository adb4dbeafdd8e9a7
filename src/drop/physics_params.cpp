#include "hydrolux/drop/physics_params.hpp"

namespace hydrolux::drop {

namespace {

using K = ParamKind;

const Field<RainphysRequest> kRainphys[] = {
    {{"radius_mm", "--radius-mm", "drop", K::real, "mm", 0.5, 4.5,
      "Equivalent-volume radius of the drop, millimetres (the shape table's range)"},
     HYDROLUX_PARAM_MEMBER(radius_mm)},
    {{"rain_rate_mmh", "--rain-rate-mmh", "rain", K::real, "mm/h", kMinDistributionRainRateMmh, kMaxRainRateMmh,
      "Rain rate h, millimetres per hour"},
     HYDROLUX_PARAM_MEMBER(rain_rate_mmh)},
};

const Field<DropProfileRequest> kProfile[] = {
    {{"mu", "--mu", "drop", K::real, "", 1.0001, 10, "Refractive index of the drop relative to the air"},
     HYDROLUX_PARAM_MEMBER(mu)},
    {{"samples", "--samples", "output", K::integer, "", 2, 1000000, "Number of rho values from 0 to 1"},
     HYDROLUX_PARAM_MEMBER(samples)},
};

}  // namespace

std::span<const Field<RainphysRequest>> rainphys_params() { return kRainphys; }
std::span<const Field<DropProfileRequest>> drop_profile_params() { return kProfile; }

}  // namespace hydrolux::drop
