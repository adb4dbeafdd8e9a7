// docs/reference.md: every command's flags in one table each, generated from the CLI's registration
// and, for the declared parameters (hydrolux/jobs.hpp), from the library's table itself: flag, the
// Python keyword, unit, valid range, default and help. tests/cli/test_reference.cpp checks that the
// file in the repository is current (`make reference` writes it).
#include <fmt/format.h>

#include <map>
#include <string>

#include "common.hpp"
#include "hydrolux/jobs.hpp"

namespace hydrolux::cli {

namespace {

// Text as Markdown shows it literally: a '<' would open an HTML tag (const:<n> would vanish), on GitHub
// and on the documentation site alike.
std::string text(std::string t) {
  for (std::size_t pos = 0; (pos = t.find('<', pos)) != std::string::npos; pos += 4) t.replace(pos, 1, "&lt;");
  return t;
}

std::string cell(std::string t) {
  t = text(std::move(t));
  for (std::size_t pos = 0; (pos = t.find('|', pos)) != std::string::npos; pos += 2) t.replace(pos, 1, "\\|");
  return t;
}

// What CLI11 states of an option's value: "FLOAT:[0, 500] mm/h" -> "[0, 500] mm/h".
std::string stated_range(const CLI::Option& opt) {
  std::string t = opt.get_type_name();
  if (const auto colon = t.find(':'); colon != std::string::npos) return t.substr(colon + 1);
  return {};
}

std::string command_path(const CLI::App& sub) {
  std::string path = sub.get_name();
  for (const auto* p = sub.get_parent(); p && p->get_parent(); p = p->get_parent()) path = p->get_name() + " " + path;
  return path;
}

}  // namespace

std::string reference_markdown(const std::vector<Command>& commands) {
    std::string md =
      "# Command reference\n\n"
      "Generated from the code (`make reference`; a test fails when this file is not current). The rows with a\n"
      "group are declared parameters, written once in the library ([parameters.md](parameters.md) says where\n"
      "and how each door reads them); where a command's parameters are Python keywords too, the Python column\n"
      "names them, with the same ranges, defaults and messages.\n";
  for (const auto& cmd : commands) {
    const std::string path = command_path(*cmd.app);
    const JobSpec* job = nullptr;
    for (const auto& j : job_specs())
      if (j.command == "hydrolux " + path) job = &j;
    std::map<std::string, const ParamInfo*> params;
    bool params_python = true;
    if (job)
      for (const auto& info : job->params) params[std::string(info.param->flag)] = &info;
    md += fmt::format("\n## hydrolux {}\n\n{}\n\n", path, text(cmd.app->get_description()));
    if (job && !job->python.empty())
      md += fmt::format("The declared parameters are keywords of the same names in {}.\n\n", job->python);
    if (job && job->python.empty()) params_python = false;
    md += "| flag | Python | group | unit | valid | default | what it sets |\n|---|---|---|---|---|---|---|\n";
    for (const auto* opt : cmd.app->get_options()) {
      if (opt->get_lnames().empty() && opt->get_snames().empty()) continue;
      if (opt->get_group().empty()) continue;  // hidden: a deprecated spelling (add_param)
      if (!opt->get_lnames().empty() && opt->get_lnames().front() == "help") continue;
      std::string names;
      for (const auto& s : opt->get_snames()) names += (names.empty() ? "" : ", ") + ("`-" + s + "`");
      for (const auto& l : opt->get_lnames()) names += (names.empty() ? "" : ", ") + ("`--" + l + "`");
      const std::string lname = opt->get_lnames().empty() ? "" : "--" + opt->get_lnames().front();
      if (const auto it = params.find(lname); it != params.end()) {
        const Param& p = *it->second->param;
        const std::string valid = p.kind == ParamKind::flag ? "switch" : p.form(Door::cli);
        // The Python calls of a frame job take arrays, not files: a path is the CLI's and the batch's.
        const bool in_python = params_python && p.kind != ParamKind::path;
        const std::string python = in_python ? fmt::format("`{}`", p.name) : std::string();
        md += fmt::format("| {} | {} | {} | {} | {} | {} | {} |\n", names, python, p.group, p.unit, cell(valid),
                          it->second->default_text(), cell(std::string(p.help)));
      } else {
        const bool is_switch = opt->get_type_size() == 0;
        md += fmt::format("| {} |  |  |  | {} | {} | {} |\n", names, cell(is_switch ? "switch" : stated_range(*opt)),
                          cell(opt->get_default_str()), cell(opt->get_description()));
      }
    }
  }
  return md;
}

}  // namespace hydrolux::cli
