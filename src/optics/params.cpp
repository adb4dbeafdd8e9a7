#include "hydrolux/optics/params.hpp"

#include "hydrolux/core/shared_params.hpp"

namespace hydrolux::optics {

namespace {

using K = ParamKind;

const Field<FresnelRequest> kFresnel[] = {
    {{"n1", "--n1", "interface", K::real, "", kMinFresnelIndex, kMaxFresnelIndex,
      "Refractive index of the incident medium (real)"},
     HYDROLUX_PARAM_MEMBER(n1)},
    {{"n2", "--n2", "interface", K::real, "", kMinFresnelIndex, kMaxFresnelIndex,
      "Real part of the second medium's refractive index"},
     HYDROLUX_PARAM_MEMBER(n2)},
    {{"k2", "--k2", "interface", K::real, "", 0, kMaxFresnelIndex,
      "Imaginary part (extinction coefficient) of the second medium's index; > 0 makes it a conductor (no "
      "transmitted beam)"},
     HYDROLUX_PARAM_MEMBER(k2)},
    {{"theta_deg", "--theta-deg", "interface", K::real, "deg", 0, 90, "Angle of incidence from the normal, degrees"},
     HYDROLUX_PARAM_OPTIONAL(theta_deg)},
};

const Field<IorRequest> kIor[] = {
    {temperature_param("medium",
                       "Temperature, Celsius (temperature-dependent media only; water: 0 to 100, default 20)"),
     HYDROLUX_PARAM_OPTIONAL(temperature_c)},
};

}  // namespace

std::span<const Field<FresnelRequest>> fresnel_params() { return kFresnel; }
std::span<const Field<IorRequest>> ior_params() { return kIor; }

}  // namespace hydrolux::optics
