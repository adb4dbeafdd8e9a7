#pragma once
// What a user sets for Mie scattering by one sphere (hydrolux mie, hydrolux.mie) and for a drop's
// phase function (hydrolux phase), declared once (core/params.hpp): each value's name, unit, range,
// default and help. The defaults are MieRequest's and PhaseRequest's initializers. The index m, the
// media, the theory, the size distribution and the angles are texts each door parses; the radius
// and the wavelength, whose ranges are open at 0, stay with the doors too.
#include <optional>
#include <span>
#include <string_view>

#include "hydrolux/core/params.hpp"

namespace hydrolux::scatter {

struct MieRequest {
  std::optional<double> x;              // the size parameter, with the index m
  std::optional<double> temperature_c;  // of the media, in the physical form
  bool no_angles = false;               // efficiencies alone: no amplitudes
  std::optional<int> debye;             // the amplitudes of this Debye order alone
  bool mueller = false;                 // the Mueller matrix elements too
  int threads = 0;                      // 0: every core
};

struct PhaseRequest {
  // Radii in the size average: a fixed Gauss-Legendre count; unset, the average chooses its own radii
  // to `tolerance` (refine_average_intensities).
  std::optional<int> nodes;
  double tolerance = 0.005;  // the size average's relative error allowed at every angle
  std::optional<double> temperature_c;
  int threads = 0;
  bool mueller = false;  // the Mueller matrix elements too
};

// Where a count of radii (the phase's and the medium's nodes) has an effect, declared on its rows: a
// size distribution of many radii, the state hold_size_states declares.
inline constexpr std::string_view kNodesOnlyWith = "many_radii";
inline constexpr std::string_view kNodesWhy =
    "{size_distribution=} is one radius, with nothing to average; {nodes} sets the radii of gamma:W, lognormal:W and "
    "marshall-palmer:H (omit {nodes})";
// The states of a size distribution's text (scatter::parse_size_distribution's) for `use`: its value
// for messages and "many_radii" where it has more than one radius.
void hold_size_states(ParamUse& use, std::string_view size_distribution);

std::span<const Field<MieRequest>> mie_params();
std::span<const Field<PhaseRequest>> phase_params();
// A parameter by name; throws std::logic_error for a name not declared.
const Param& mie_param(std::string_view name);
const Param& phase_param(std::string_view name);

}  // namespace hydrolux::scatter
