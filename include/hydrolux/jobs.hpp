#pragma once
// Every job's declared parameters (core/params.hpp) in one list: what docs/reference.md is generated
// from and what the Python package lists (hydrolux.params). Each job's table lives in its module
// (rain/params.hpp, ...); this list only gathers them.
#include <string_view>
#include <vector>

#include "hydrolux/core/params.hpp"

namespace hydrolux {

const std::vector<JobSpec>& job_specs();
// One job's, by name ("rain"); throws UnknownNameError listing the jobs.
const JobSpec& job_spec(std::string_view name);

}  // namespace hydrolux
