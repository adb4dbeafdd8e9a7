// hydrolux spec: every job's declared parameters (hydrolux/jobs.hpp), as a table to read or, with
// --json, the library's JSON dump (job_specs_json) that the web demo builds its ranges and defaults from.
#include <fmt/format.h>

#include <memory>
#include <string>

#include "common.hpp"
#include "hydrolux/jobs.hpp"

namespace hydrolux::cli {

namespace {

// One line a parameter: its name, its flag, its valid range (or "switch"), its default.
void print_table() {
  for (const auto& job : job_specs()) {
    fmt::print("{}: {}\n", job.command, job.summary);
    for (const auto& info : job.params) {
      const Param& p = *info.param;
      const std::string valid = p.kind == ParamKind::flag ? "switch" : p.range_text();
      const std::string def = info.default_text();
      fmt::print("  {:<22} {:<24} {:<22} {}\n", p.name, p.flag, valid, def.empty() ? "(no default)" : "default " + def);
    }
  }
}

}  // namespace

Command add_spec(CLI::App& app) {
  auto json = std::make_shared<bool>(false);
  auto* sub = app.add_subcommand(
      "spec",
      "Every job's declared parameters: name, flag, group, kind, unit, valid range, default and help, as the library "
      "declares them (docs/parameters.md); the web demo takes the sky's ranges and defaults from the JSON.");
  sub->add_flag("--json", *json,
                "JSON instead of the table: {\"format\": \"hydrolux-spec\", \"jobs\": [{\"name\", \"command\", "
                "\"params\": [{\"name\", \"flag\", \"kind\", \"unit\", \"lo\", \"hi\", \"default\", ...}]}]}");
  return {sub,
          [json] {
            if (*json)
              fmt::print("{}", job_specs_json());
            else
              print_table();
            return 0;
          },
          {}};
}

}  // namespace hydrolux::cli
