#include "params.hpp"

#include <fmt/format.h>

#include "hydrolux/core/error.hpp"
#include "hydrolux/jobs.hpp"

namespace hydrolux::cli {

namespace {

// The option of `flag` for the parameter (its validator, unit and default shown).
CLI::Option* add_option_for(CLI::App& sub, const ParamInfo& info, const std::string& flag,
                            std::function<void(const ParamValue&)> store) {
  const Param& p = *info.param;
  const std::string help(p.help), unit(p.unit);
  CLI::Option* opt = nullptr;
  switch (p.kind) {
    case ParamKind::real:
      opt = sub.add_option_function<double>(flag, [store = std::move(store)](double v) { store({v}); }, help)
                ->check(number_in(p.lo, p.hi, unit));
      break;
    case ParamKind::integer:
      opt = sub.add_option_function<long long>(
                   flag, [store = std::move(store)](long long v) { store({double(v)}); }, help)
                ->transform(integer_in((long long)p.lo, (long long)p.hi, unit));
      break;
    case ParamKind::flag: {
      // The flag turns the default around: --no-unresolved for a parameter that is on by default.
      const double turned = info.default_value != 0 ? 0 : 1;
      return sub.add_flag_callback(flag, [store = std::move(store), turned] { store({turned}); }, help);
    }
    case ParamKind::path:
      throw std::logic_error("add_param: a path is add_path_param's");
    default: {
      // A choice's word, or a size's, span's or colour's parts: the library's parser reads and checks the
      // text (its message names the flag), the value stored once the command line has parsed.
      const auto parse = [&p](const std::string& text) { return p.parse_text(text, Door::cli); };
      // The help's type column: "{per-pixel|cube-map}", "WxH in [1, 16384] px".
      const std::string form = p.form(Door::cli);
      const std::string type = p.kind == ParamKind::choice
                                   ? "{" + std::string(p.words) + "}"
                                   : form.substr(0, form.find(", each")) + " in " + p.range_text();
      opt = sub.add_option_function<std::string>(
                   flag, [store = std::move(store), parse](const std::string& text) { store(parse(text)); }, help)
                ->check(CLI::Validator(
                    [parse, &p](std::string& text) -> std::string {
                      try {
                        (void)parse(text);
                        return {};
                      } catch (const Error&) {  // CLI11 puts the flag first: "--size: '12x' is not WxH, ..."
                        return fmt::format("'{}' is not {}{}", printable(text),
                                           p.kind == ParamKind::choice ? "one of " : "", p.form(Door::cli));
                      }
                    },
                    type));
      break;
    }
  }
  const std::string shown = info.default_text();
  if (!shown.empty()) opt->default_str(shown);
  return opt;
}

}  // namespace

CLI::App* add_job_command(CLI::App& parent, std::string_view job) {
  const JobSpec& spec = job_spec(job);
  const std::string_view command = spec.command.substr(spec.command.rfind(' ') + 1);
  return parent.add_subcommand(std::string(command), std::string(spec.description));
}

const std::map<std::string, std::string>& lee_table_quantities() {
  static const std::map<std::string, std::string> names = {
      {"size_parameter", "--radius-um (the size parameter 2 pi r / lambda)"},
      {"shape", "--shape"},
      {"axis_ratio", "--shape"},
      {"p", "--theory"},
      {"columns", "--size"},
      {"rows", "--size"},
      {"width", "--size"},
      {"height", "--size"}};
  return names;
}

CLI::Option* add_path_param(CLI::App& sub, const ParamInfo& info, std::function<void(const std::string&)> store) {
  const Param& p = *info.param;
  const std::string flags = p.short_flag.empty() ? std::string(p.flag) : fmt::format("{},{}", p.short_flag, p.flag);
  CLI::Option* opt = sub.add_option_function<std::string>(flags, std::move(store), std::string(p.help));
  opt->type_name(std::string(p.words));
  if (const std::string shown = info.default_text(); !shown.empty()) opt->default_str(shown);
  return opt;
}

CLI::Option* add_param(CLI::App& sub, const ParamInfo& info, std::function<void(const ParamValue&)> store) {
  const Param& p = *info.param;
  CLI::Option* opt = add_option_for(sub, info, std::string(p.flag), store);
  if (!p.deprecated.empty()) {
    // The old spelling, for one release: it works as the new one, warns once, and is not in --help.
    const std::string old = Param::flag_of(p.deprecated);
    // Both given is refused here, naming both (CLI11's excludes() would name a hidden option as "").
    CLI::Option* alias = add_option_for(sub, info, old, [store, old, &p, opt](const ParamValue& v) {
      if (opt->count() > 0)
        throw CLI::ValidationError(old, fmt::format("give {} or {} (its deprecated name), not both", p.flag, old));
      warn(p.deprecation_warning(old, p.flag));
      store(v);
    });
    alias->group("");
  }
  return opt;
}

const CLI::Option* given_option(const CLI::App& sub, const Param& param) {
  for (const std::string& flag : {std::string(param.flag), param.deprecated.empty() ? std::string() : Param::flag_of(param.deprecated)}) {
    if (flag.empty()) continue;
    const auto* opt = sub.get_option_no_throw(flag);
    if (opt != nullptr && opt->count() > 0) return opt;
  }
  return nullptr;
}

bool given(const CLI::App& sub, const Param& param) { return given_option(sub, param) != nullptr; }

}  // namespace hydrolux::cli
