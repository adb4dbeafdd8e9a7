#include "hydrolux/scatter/params.hpp"

#include <limits>
#include <stdexcept>
#include <string>

#include "hydrolux/core/shared_params.hpp"
#include "hydrolux/scatter/debye.hpp"
#include "hydrolux/scatter/mie.hpp"
#include "hydrolux/scatter/size_distribution.hpp"

namespace hydrolux::scatter {

namespace {

constexpr double kNone = std::numeric_limits<double>::quiet_NaN();
using K = ParamKind;


// Shared by both jobs: the media's temperature and the worker threads.
constexpr Param kTemperature = temperature_param(
    "media", "Temperature in Celsius of the media that model it (water: 0 to 100); refused when neither medium does");
constexpr Param kThreads = threads_param("run", "Worker threads (0 = all cores)");

const Field<MieRequest> kMie[] = {
    {{"x", "--x", "sphere", K::real, "", kMieMinSizeParameter, kMieMaxSizeParameter,
      "Size parameter 2 pi r / lambda, 1e-6 to 1e6"},
     HYDROLUX_PARAM_OPTIONAL(x)},
    {kTemperature, HYDROLUX_PARAM_OPTIONAL(temperature_c)},
    {flag_param("no_angles", "--no-angles", "amplitudes",
                "Efficiencies only (Qext, Qsca, Qabs, Qback, g): no amplitudes, the fast path for size sweeps"),
     HYDROLUX_PARAM_MEMBER(no_angles)},
    {{"debye", "--debye", "amplitudes", K::integer, "", 0, kMaxDebyeOrder,
      "Restrict S1, S2 to Debye order P (0 diffraction + external reflection, 1 direct transmission, 2 primary "
      "rainbow, 3 secondary, ...); efficiencies stay the whole sphere's"},
     [](const MieRequest& o, int) { return o.debye ? double(*o.debye) : kNone; },
     [](MieRequest& o, int, double v) { o.debye = int(v); }},
    {flag_param("mueller", "--mueller", "amplitudes",
                "Add the Mueller matrix elements S11, S12, S33, S34 (Bohren & Huffman eq. 4.77) to the output"),
     HYDROLUX_PARAM_MEMBER(mueller)},
    {kThreads, HYDROLUX_PARAM_MEMBER(threads)},
};

const Field<PhaseRequest> kPhase[] = {
    {{"nodes", "--nodes", "sizes", K::integer, "", 1, kMaxQuadratureNodes,
      "A fixed count of radii in the size average (Gauss-Legendre in ln r) instead of the automatic refinement to "
      "--tolerance; cloud droplets' Mie ripple needs about 8 per unit of the size parameters covered (a note says "
      "when there are fewer than 4)",
      {}, kNodesOnlyWith, {}, kNodesWhy},
     HYDROLUX_PARAM_OPTIONAL(nodes)},
    {{"tolerance", "--tolerance", "sizes", K::real, "", 1e-4, 0.1,
      "The size average's relative error allowed at every angle: radii evenly spaced, halved until two spacings "
      "agree to half of it and, for Mie, a grid shifted by 0.618 of the last spacing does too (docs/mie.md, \"Size "
      "averages\")",
      "nodes", kNodesOnlyWith, {}, "{size_distribution=} is one radius, with nothing to average (omit {tolerance})"},
     HYDROLUX_PARAM_MEMBER(tolerance)},
    {kTemperature, HYDROLUX_PARAM_OPTIONAL(temperature_c)},
    {kThreads, HYDROLUX_PARAM_MEMBER(threads)},
    {flag_param("mueller", "--mueller", "output",
         "Add the size-averaged Mueller matrix elements S11, S12, S33, S34 (Bohren & Huffman eq. 4.77) as columns"),
     HYDROLUX_PARAM_MEMBER(mueller)},
};

}  // namespace

void hold_size_states(ParamUse& use, std::string_view size_distribution) {
  use.note("size_distribution", std::string(size_distribution));
  if (parse_size_distribution(size_distribution).kind != SizeDistributionKind::monodisperse) use.hold("many_radii");
}

std::span<const Field<MieRequest>> mie_params() { return kMie; }
std::span<const Field<PhaseRequest>> phase_params() { return kPhase; }

const Param& mie_param(std::string_view name) {
  if (const auto* f = find_field(mie_params(), name)) return f->param;
  throw std::logic_error("mie_param: no parameter " + std::string(name));
}

const Param& phase_param(std::string_view name) {
  if (const auto* f = find_field(phase_params(), name)) return f->param;
  throw std::logic_error("phase_param: no parameter " + std::string(name));
}

}  // namespace hydrolux::scatter
