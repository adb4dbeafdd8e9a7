// The declared parameters as JSON (hydrolux/jobs.hpp): written by hand, in the tables' order, with
// fmt's shortest round-trip numbers, so the text is the same on every run and every machine.
#include <fmt/format.h>

#include <cmath>
#include <string>
#include <string_view>

#include "hydrolux/jobs.hpp"
#include "hydrolux/version.hpp"

namespace hydrolux {

namespace {

// A JSON string: quotes, backslashes and control characters escaped; other bytes (UTF-8) as they are.
std::string quoted(std::string_view text) {
  std::string out = "\"";
  for (const char c : text) {
    switch (c) {
      case '"': out += "\\\""; break;
      case '\\': out += "\\\\"; break;
      case '\n': out += "\\n"; break;
      case '\t': out += "\\t"; break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) out += fmt::format("\\u{:04x}", static_cast<unsigned char>(c));
        else out += c;
    }
  }
  return out + "\"";
}

std::string optional_text(std::string_view text) { return text.empty() ? "null" : quoted(text); }

// A number of `kind`: whole for an integer or a flag's 0/1, the shortest round trip for a real; null
// where it is not finite (JSON has no infinity) or none (NaN).
std::string number(double v, ParamKind kind) {
  if (!std::isfinite(v)) return "null";
  if (kind != ParamKind::real && v == std::floor(v) && std::fabs(v) < 9.007199254740992e15)
    return fmt::format("{}", static_cast<long long>(v));
  return fmt::format("{}", v);
}

// "a|b" as ["a", "b"]; empty: [].
std::string word_list(std::string_view text) {
  std::string out = "[";
  while (!text.empty()) {
    const auto bar = text.find('|');
    out += (out.size() > 1 ? ", " : "") + quoted(text.substr(0, bar));
    if (bar == std::string_view::npos) break;
    text.remove_prefix(bar + 1);
  }
  return out + "]";
}

std::string_view kind_name(ParamKind kind) {
  switch (kind) {
    case ParamKind::real: return "real";
    case ParamKind::integer: return "integer";
    case ParamKind::flag: return "flag";
  }
  return "real";
}

std::string param_json(const ParamInfo& info) {
  const Param& p = *info.param;
  const std::string def = std::isnan(info.default_value) ? "null"
                          : p.kind == ParamKind::flag   ? (info.default_value != 0 ? "true" : "false")
                                                        : number(info.default_value, p.kind);
  return fmt::format(
      "{{\"name\": {}, \"flag\": {}, \"group\": {}, \"kind\": {}, \"unit\": {}, \"lo\": {}, \"hi\": {}, "
      "\"default\": {}, \"help\": {}, \"excludes\": {}, \"only_with\": {}, \"not_with\": {}, \"why\": {}, "
      "\"deprecated\": {}}}",
      quoted(p.name), quoted(p.flag), quoted(p.group), quoted(kind_name(p.kind)), quoted(p.unit),
      number(p.lo, p.kind), number(p.hi, p.kind), def, quoted(p.help), optional_text(p.excludes),
      word_list(p.only_with), word_list(p.not_with), optional_text(p.why), optional_text(p.deprecated));
}

}  // namespace

std::string job_spec_json(const JobSpec& job) {
  std::string out = fmt::format("{{\"name\": {}, \"command\": {}, \"summary\": {}, \"python\": {}, \"params\": [",
                                quoted(job.name), quoted(job.command), quoted(job.summary),
                                optional_text(job.python));
  for (std::size_t i = 0; i < job.params.size(); ++i)
    out += (i == 0 ? "\n      " : ",\n      ") + param_json(job.params[i]);
  return out + (job.params.empty() ? "]}" : "\n    ]}");
}

std::string job_specs_json() {
  std::string out = fmt::format(
      "{{\n  \"format\": \"hydrolux-spec\",\n  \"format_version\": 1,\n  \"hydrolux_version\": {},\n  \"jobs\": [",
      quoted(kVersion));
  const auto& jobs = job_specs();
  for (std::size_t i = 0; i < jobs.size(); ++i) out += (i == 0 ? "\n    " : ",\n    ") + job_spec_json(jobs[i]);
  return out + "\n  ]\n}\n";
}

}  // namespace hydrolux
