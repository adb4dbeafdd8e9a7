#pragma once
// What a user sets for a Lee table (hydrolux lee, hydrolux.lee, the batch job hydrolux.batch
// lee-atlas), declared once (core/params.hpp): the numbers and switches, each with its name, unit,
// range, default and help. The defaults are LeeRequest's initializers (lee.hpp); validate() reads
// the ranges from here. The text choices (table, theory, radius scale, axis, medium, sun, colour
// space) and the spans (radii, angles, size, wavelengths) are parsed by each door in its own words.
#include <span>
#include <string_view>

#include "hydrolux/atmos/lee.hpp"
#include "hydrolux/core/params.hpp"

namespace hydrolux::atmos {

std::span<const Field<LeeRequest>> lee_params();
// A Lee parameter by name; throws std::logic_error for a name not declared.
const Param& lee_param(std::string_view name);

}  // namespace hydrolux::atmos
