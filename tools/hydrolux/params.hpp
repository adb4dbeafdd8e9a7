#pragma once
// The CLI's door onto the declared parameters (hydrolux/core/params.hpp): each parameter of a job
// becomes a flag with its range validator, unit, default and help, storing into the request.
#include <CLI/CLI.hpp>

#include <map>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>

#include "common.hpp"
#include "hydrolux/core/params.hpp"

namespace hydrolux::cli {

// The subcommand of `parent` for the library's job `job` (hydrolux/jobs.hpp): named by the last word
// of the job's command ("hydrolux drop render": render), its help the job's description.
CLI::App* add_job_command(CLI::App& parent, std::string_view job);

// The quantities the Lee tables' computation (atmos/lee.hpp, scatter) names that no flag of lee, sky or
// export sets by that name, with the flag that does: the size parameter (--radius-um), the drop
// shape's axis ratio (--shape), the theory's order p (--theory), the table's size (--size).
const std::map<std::string, std::string>& lee_table_quantities();

// One flag for a declared parameter; `store` receives the parsed, range-checked value. A parameter
// with a deprecated name also takes its old flag (hidden from --help; a warning when given).
CLI::Option* add_param(CLI::App& sub, const ParamInfo& info, std::function<void(const ParamValue&)> store);

// One flag (and its short one, "-o,--output") for a declared path; `store` receives the text.
CLI::Option* add_path_param(CLI::App& sub, const ParamInfo& info, std::function<void(const std::string&)> store);

// Every field of `fields` as a flag on `sub`, storing into *request (kept alive by the action).
// Parameters that replace one another (excludes) are registered as exclusive. The names map to
// their flags in `flags` (the library's errors name the quantity; the CLI names the flag).
template <class Request>
void add_params(CLI::App& sub, const std::shared_ptr<Request>& request, std::span<const Field<Request>> fields,
                std::map<std::string, std::string>& flags) {
  const auto infos = describe_fields(fields);
  std::map<std::string_view, CLI::Option*> options;
  for (std::size_t i = 0; i < fields.size(); ++i) {
    const Field<Request>& f = fields[i];
    options[f.param.name] =
        f.param.kind == ParamKind::path
            ? add_path_param(sub, infos[i], [request, &f](const std::string& v) { f.set_text(*request, v); })
            : add_param(sub, infos[i], [request, &f](const ParamValue& v) { f.set_value(*request, v); });
    flags.emplace(std::string(f.param.name), std::string(f.param.flag));
  }
  for (const auto& f : fields)
    if (!f.param.excludes.empty()) options.at(f.param.name)->excludes(options.at(f.param.excludes));
}

// The option of `param` given on the command line (its flag, or its deprecated one), or nullptr.
const CLI::Option* given_option(const CLI::App& sub, const Param& param);
// Whether the flag of parameter `name` was given on the command line.
bool given(const CLI::App& sub, const Param& param);

// What the user gave of `fields` on `sub`, for the library's ParamUse: each flag given, with its text
// as written (a switch: none); the others declared, so that messages can name them.
template <class Request>
void record_given(const CLI::App& sub, std::span<const Field<Request>> fields, ParamUse& use) {
  for (const auto& f : fields) {
    const CLI::Option* opt = given_option(sub, f.param);
    if (opt == nullptr) {
      use.declare(f.param);
      continue;
    }
    use.give(f.param, f.param.kind == ParamKind::flag ? std::string() : opt->results().back());
  }
}

// The fields from the one named `first` to the one named `last`, both included: a run of a table that
// a command registers between its own flags, where it stands in --help.
template <class Request>
std::span<const Field<Request>> fields_from(std::span<const Field<Request>> fields, std::string_view first,
                                            std::string_view last) {
  const auto at = [&](std::string_view name) {
    const auto* f = find_field(fields, name);
    if (!f) throw std::logic_error("fields_from: no parameter " + std::string(name));
    return std::size_t(f - fields.data());
  };
  return fields.subspan(at(first), at(last) - at(first) + 1);
}

}  // namespace hydrolux::cli
