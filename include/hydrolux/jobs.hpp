#pragma once
// Every job's declared parameters (core/params.hpp) in one list: what docs/reference.md is generated
// from and what the Python package lists (hydrolux.params). Each job's table lives in its module
// (rain/params.hpp, ...); this list only gathers them.
#include <string>
#include <string_view>
#include <vector>

#include "hydrolux/core/params.hpp"

namespace hydrolux {

const std::vector<JobSpec>& job_specs();
// One job's, by name ("rain"); throws UnknownNameError listing the jobs.
const JobSpec& job_spec(std::string_view name);

// Every job's declared parameters as JSON (`hydrolux spec --json`; the web demo's ranges and defaults
// are built from it): {"format": "hydrolux-spec", "format_version": 1, "hydrolux_version", "jobs": [{
// "name", "command", "summary", "python" (null: none), "params": [{"name", "flag", "short_flag" (only
// where one is declared: "-o"), "group", "kind" ("real", "integer", "flag", "choice", "size", "span",
// "colour" or "path"), "unit" ("" for a pure number), "lo", "hi" (both included; each part's for a size,
// span or colour; null for a path), "default" (null: none; true/false for a flag; a choice's word; a
// list of a size's, span's or colour's parts; a path's text), "words" (a choice's words, the parts'
// names or a path's FILE or DIR; [] otherwise), "help", "excludes", "only_with" and "not_with" (lists of
// words), "why", "deprecated" (null where none)}]}]}, one parameter a line, the jobs and parameters in
// the tables' order: the same text on every run. Written by hydrolux_io (src/io/spec_json.cpp,
// nlohmann-json), not by the physics library that holds the tables.
std::string job_specs_json();
std::string job_spec_json(const JobSpec& job);

}  // namespace hydrolux
