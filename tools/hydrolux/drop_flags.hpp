#pragma once
// The drops of a size average as `hydrolux phase` and `hydrolux medium` take them: --radius-um,
// --size-distribution, --medium, --surrounding (and --temperature-c for the media), filled into the
// library's job (scatter::PhaseJob, scatter::MediumJob); the library's errors name the flags
// themselves (ParamError, said by the CLI with each command's flags).
#include <CLI/CLI.hpp>

#include <map>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "common.hpp"
#include "hydrolux/scatter/params.hpp"
#include "hydrolux/scatter/phase_job.hpp"
#include "params.hpp"

namespace hydrolux::cli {

struct DropFlags {
  std::optional<double> radius_um;
  std::string distribution = "mono";
  std::string medium = "water", surrounding = "air";
};

// --radius-um and --size-distribution; `rain_note` ends the latter's help after marshall-palmer's
// radii ("no --radius-um"). Adds the library's quantities these flags answer for in its messages
// (the size parameter, the relative index, the distribution's radii) to `flags_for_quantity`.
void add_drop_size_flags(CLI::App& sub, DropFlags& drops, std::string_view rain_note,
                         std::map<std::string, std::string>& flags_for_quantity);
// --medium and --surrounding.
void add_media_flags(CLI::App& sub, DropFlags& drops);

// Refuses a flag of `params` given on `sub` where it has no effect for the drops' size distribution
// (--nodes, even at its default, for one radius): the table's conditions, checked by the library.
template <class Request>
void refuse_unused_size_flags(const CLI::App& sub, std::span<const Field<Request>> params, const DropFlags& drops) {
  ParamUse use(Door::cli);
  record_given(sub, params, use);
  scatter::hold_size_states(use, drops.distribution);
  use.report_unused();
}

// The job's drops from the flags: the media (an unknown name names its flag), the temperature checked
// for them, the radius and the distribution.
template <class Job>
void fill_drops(Job& job, const DropFlags& drops, const std::optional<double>& temperature_c) {
  job.medium = medium_flag("--medium", drops.medium);
  job.surrounding = medium_flag("--surrounding", drops.surrounding);
  check_temperature_flag(temperature_c, {job.medium.get(), job.surrounding.get()});
  job.radius_um = drops.radius_um;
  job.size_distribution = drops.distribution;
}

}  // namespace hydrolux::cli
