#pragma once
// Declared parameters: what a user sets for a job (its name, unit, valid range, default and one
// line of help), written once in the library beside the settings it fills, and read by every door:
// the CLI registers its flags from it, the Python functions take its names as keywords, the batch
// jobs build their argparse options from it and docs/reference.md is generated from it (checked
// current by a test). The models are pbrt-v4's ParameterDictionary and Mitsuba 3's declared plugin
// parameters; here a job's table is a plain array the compiler checks.
//
// A parameter's default is not restated here: it is the value of the member it fills in a
// default-constructed request (`get(Request{})`), so the struct's initializer stays the one place.
#include <cmath>
#include <limits>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace hydrolux {

enum class ParamKind {
  real,     // a finite number in [lo, hi]
  integer,  // a whole number in [lo, hi] (exact up to 2^53)
  flag,     // on or off; the CLI's flag turns the default around (e.g. --no-unresolved)
};

struct Param {
  std::string_view name;  // the Python keyword, the JSON key, the library's quantity: "rate_mmh"
  std::string_view flag;  // the CLI's and the batch jobs' flag: "--rate-mmh"
  // Which part of the job it sets ("rain", "camera", "files"): the docs group by it, and a door
  // that takes only a part (the Python functions take arrays, not files) selects by it.
  std::string_view group;
  ParamKind kind = ParamKind::real;
  std::string_view unit;  // "mm/h", "deg"; empty for a pure number
  double lo = 0, hi = 0;  // the valid range, both ends included
  std::string_view help;  // one line, as the CLI's --help shows it
  // Another parameter this one replaces (fov_deg for focal_mm): giving both is refused.
  std::string_view excludes = {};

  // "[0, 500] mm/h"
  std::string range_text() const;
  // Throws DomainError "rate_mmh = 600 is outside [0, 500] mm/h" (quantity: the name) unless the
  // value lies in the range; for an integer also unless it is whole.
  void check(double value) const;
};

// Ranges that several jobs' parameters share, stated once: a temperature before the medium's own
// range is checked (from absolute zero to 1000 C), and the worker threads (0: every core).
inline constexpr double kMinTemperatureC = -273.15, kMaxTemperatureC = 1000;
// The rain rate the rain and the sky take, mm/h (0: no rain; Marshall-Palmer is fitted to at most
// ~100 mm/h, and cloudbursts reach a few hundred).
inline constexpr double kMaxRainRateMmh = 500;
inline constexpr int kMaxThreads = 1024;

// A parameter bound to the request it fills. `get` reads it (NaN where it has no value of its own
// until given, e.g. a field of view that replaces the focal length); `set` stores a checked value.
template <class Request>
struct Field {
  Param param;
  double (*get)(const Request&);
  void (*set)(Request&, double);
};

// The accessors of a table row (a Field's get and set) for a member of the request:
// HYDROLUX_PARAM_MEMBER(settings.rate_mmh) for a number or a bool, HYDROLUX_PARAM_OPTIONAL(fov_deg) for
// a std::optional<double> (NaN while unset: no default of its own).
#define HYDROLUX_PARAM_MEMBER(path)                         \
  [](const auto& o) { return double(o.path); },             \
      [](auto& o, double v) { o.path = decltype(o.path)(v); }
#define HYDROLUX_PARAM_OPTIONAL(path)                                                                \
  [](const auto& o) { return o.path ? double(*o.path) : std::numeric_limits<double>::quiet_NaN(); }, \
      [](auto& o, double v) { o.path = v; }

// A parameter with its default, for the doors that list them (docs, Python signatures, argparse).
struct ParamInfo {
  const Param* param;
  double default_value;  // NaN: none (derived, or replaced by another parameter)
  // The default as the CLI's help shows it: "25", "0.008", "on"; empty for none.
  std::string default_text() const;
};

// A job's declared parameters.
struct JobSpec {
  std::string_view name;     // "rain"
  std::string_view command;  // "hydrolux rain"
  std::string_view summary;  // one line
  std::vector<ParamInfo> params;
  // The Python calls that take the parameters by name as keywords; empty where none does (then only
  // the CLI and the docs read the table).
  std::string_view python = {};
};

template <class Request>
std::vector<ParamInfo> describe_fields(std::span<const Field<Request>> fields) {
  const Request defaults{};
  std::vector<ParamInfo> out;
  out.reserve(fields.size());
  for (const auto& f : fields) out.push_back({&f.param, f.get(defaults)});
  return out;
}

// The field of `name` in `fields`, or nullptr.
template <class Request>
const Field<Request>* find_field(std::span<const Field<Request>> fields, std::string_view name) {
  for (const auto& f : fields)
    if (f.param.name == name) return &f;
  return nullptr;
}

}  // namespace hydrolux
