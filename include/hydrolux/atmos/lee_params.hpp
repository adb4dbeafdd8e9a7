#pragma once
// What a user sets for a Lee table (hydrolux lee, hydrolux.lee, the batch job hydrolux.batch
// lee-atlas), declared once (core/params.hpp): the numbers and switches, each with its name, unit,
// range, default and help. The defaults are LeeRequest's initializers (lee.hpp); validate() reads
// the ranges from here. The text choices (table, theory, radius scale, axis, medium, sun, colour
// space) and the spans (radii, angles, size, wavelengths) are parsed by each door in its own words.
#include <span>
#include <string>
#include <string_view>

#include "hydrolux/atmos/lee.hpp"
#include "hydrolux/core/params.hpp"

namespace hydrolux::atmos {

std::span<const Field<LeeRequest>> lee_params();
// A Lee parameter by name; throws std::logic_error for a name not declared.
const Param& lee_param(std::string_view name);

// The parameters of non-spherical drops alone (sun_elevation_deg, position_deg, canting_deg): spheres
// do not depend on them, so each door refuses one given for spheres (make_lee_spec: one other than
// its default; the CLI: any given), in one wording, shared with export's --sun-elevation-deg:
// "<name> <value>: sets <what> of the non-spherical drops' table (<shape>); the spheres' tables do
// not depend on it (omit it or give <shape>)", the parameter called `name` and the shape `shape`
// ("--sun-elevation-deg", "--shape" in the CLI; the parameter's own names in the library).
inline constexpr std::string_view kShapeOnlyParams[] = {"sun_elevation_deg", "position_deg", "canting_deg"};
std::string shape_only_message(std::string_view param, double value, std::string_view name, std::string_view shape);

}  // namespace hydrolux::atmos
