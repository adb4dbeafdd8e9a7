// The declared parameters as JSON (hydrolux/jobs.hpp), with nlohmann-json's escaping and shortest
// round-trip numbers: in the tables' order, one parameter a line, the same text on every run and
// every machine. It lives with the files (hydrolux_io, which links nlohmann-json); the tables it
// reads are the physics library's.
#include <cmath>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

#include "hydrolux/jobs.hpp"
#include "hydrolux/version.hpp"

namespace hydrolux {

namespace {

using Json = nlohmann::ordered_json;

Json optional_text(std::string_view text) { return text.empty() ? Json(nullptr) : Json(std::string(text)); }

// A number of `kind`: whole for an integer, a size, a choice's index or a flag's 0/1, the real itself
// otherwise (a real, a span's or a colour's parts); null where it is not finite (JSON has no infinity)
// or none (NaN).
Json number(double v, ParamKind kind) {
  if (!std::isfinite(v)) return nullptr;
  if (kind == ParamKind::path) return nullptr;  // no range
  const bool whole_kind = kind != ParamKind::real && kind != ParamKind::span && kind != ParamKind::colour;
  if (whole_kind && v == std::floor(v) && std::fabs(v) <= 9.007199254740992e15)  // to 2^53
    return static_cast<long long>(v);
  return v;
}

// "a|b" as ["a", "b"]; empty: [].
Json word_list(std::string_view text) {
  Json out = Json::array();
  for (const auto w : split_words(text)) out.push_back(std::string(w));
  return out;
}

Json param_json(const ParamInfo& info) {
  const Param& p = *info.param;
  Json row;
  row["name"] = std::string(p.name), row["flag"] = std::string(p.flag), row["group"] = std::string(p.group);
  if (!p.short_flag.empty()) row["short_flag"] = std::string(p.short_flag);
  row["kind"] = kind_name(p.kind), row["unit"] = std::string(p.unit);
  row["lo"] = number(p.lo, p.kind), row["hi"] = number(p.hi, p.kind);
  // The default as the door takes it: a number, true/false, a choice's word, a list of a size's parts.
  Json parts = Json::array();
  for (int i = 0; i < p.parts(); ++i) parts.push_back(number(info.default_parts[std::size_t(i)], p.kind));
  row["default"] = p.kind == ParamKind::path        ? optional_text(info.default_path)
                   : std::isnan(info.default_value) ? Json(nullptr)
                   : p.kind == ParamKind::flag      ? Json(info.default_value != 0)
                   : p.kind == ParamKind::choice    ? Json(p.value_text(info.default_value))
                   : p.parts() > 1                  ? parts
                                                    : number(info.default_value, p.kind);
  // A choice's words, or the names of a size's, span's or colour's parts; [] otherwise.
  row["words"] = word_list(p.words);
  row["help"] = std::string(p.help), row["excludes"] = optional_text(p.excludes);
  row["only_with"] = word_list(p.only_with), row["not_with"] = word_list(p.not_with);
  row["why"] = optional_text(p.why), row["deprecated"] = optional_text(p.deprecated);
  return row;
}

// `value` on one line (UTF-8 as it is; bytes that are not UTF-8 replaced, never thrown on).
std::string line(const Json& value) { return value.dump(-1, ' ', false, Json::error_handler_t::replace); }

}  // namespace

std::string job_spec_json(const JobSpec& job) {
  Json head;
  head["name"] = std::string(job.name), head["command"] = std::string(job.command);
  head["summary"] = std::string(job.summary), head["python"] = optional_text(job.python);
  std::string out = line(head);
  out.pop_back();  // the closing brace: the parameters follow, one a line
  out += ",\"params\":[";
  for (std::size_t i = 0; i < job.params.size(); ++i)
    out += (i == 0 ? "\n      " : ",\n      ") + line(param_json(job.params[i]));
  return out + (job.params.empty() ? "]}" : "\n    ]}");
}

std::string job_specs_json() {
  std::string out = "{\n  \"format\": \"hydrolux-spec\",\n  \"format_version\": 1,\n  \"hydrolux_version\": " +
                    line(Json(std::string(kVersion))) + ",\n  \"jobs\": [";
  const auto& jobs = job_specs();
  for (std::size_t i = 0; i < jobs.size(); ++i) out += (i == 0 ? "\n    " : ",\n    ") + job_spec_json(jobs[i]);
  return out + "\n  ]\n}\n";
}

}  // namespace hydrolux
