#pragma once
// What a user sets for a rainbow scene (hydrolux sky) and for an engine's assets (hydrolux export),
// declared once (core/params.hpp): the numbers and switches, each with its name, unit, range,
// default and help. The defaults are SkySettings' (compositor.hpp) and the option structs'
// initializers; validate(SkySettings) reads the ranges from here. The texts (the size, the curtain's
// span, the light's colour, the blend, the mode, the theory, the drops' shape) and the files stay with
// the door.
#include <array>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "hydrolux/core/params.hpp"
#include "hydrolux/scene/compositor.hpp"

namespace hydrolux::scene {

// A scene as hydrolux sky asks for it: the settings, and how the door lights and computes it.
struct SkyOptions {
  SkySettings settings;
  double environment_scale = 1;  // multiplier on an environment map's values
  // Of the tables computed for one radius (sky_profile_spec); unset: automatic.
  std::optional<double> sampling;
  // The drops' shape, atmos::parse_drop_shape's names (a text, not a declared row): non-spherical
  // drops' bow is computed per position angle (bow_tables.hpp, compute_shaped_rainbow).
  std::string shape = "sphere";
};

// The assets hydrolux export writes: the scene's tables (bow_tables.hpp) and sky.json.
struct ExportOptions {
  std::optional<double> radius_um;  // one radius: one-column tables
  std::optional<std::array<int, 2>> size;  // the rainbow table's columns and rows (the corona's 2 x rows)
  std::optional<double> sampling;   // the tables' sampling multiplier; unset: automatic (LeeSpec::sampling_most)
  double turbidity = SkySettings{}.turbidity;
  // Non-spherical drops (a text, not a declared row, as SkyOptions::shape): the position-dependent
  // rainbow table besides the spheres' (bow_tables.hpp, compute_shaped_rainbow_table), for a sun
  // sun_elevation_deg up (hydrolux sky's default).
  std::string shape = "sphere";
  double sun_elevation_deg = SkySettings{}.sun_elevation_deg;
};

std::span<const Field<SkyOptions>> sky_params();
std::span<const Field<ExportOptions>> export_params();
// A sky parameter by name; throws std::logic_error for a name not declared.
const Param& sky_param(std::string_view name);

}  // namespace hydrolux::scene
