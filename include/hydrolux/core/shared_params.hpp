#pragma once
// Rows that several declared tables (params.hpp) write alike, each with its kind, unit and range
// stated once: an on/off flag, a temperature, the random seed and the worker threads. The table
// still says the group and the help, which differ from job to job.
#include <string_view>

#include "hydrolux/core/params.hpp"
#include "hydrolux/core/random.hpp"

namespace hydrolux {

// On or off: no unit, 0 or 1 (the CLI's flag turns the default around: --no-unresolved).
constexpr Param flag_param(std::string_view name, std::string_view flag, std::string_view group,
                           std::string_view help) {
  return {name, flag, group, ParamKind::flag, "", 0, 1, help};
}

// One of the words of `choices` ("physical|whitepaper"), filling an enum whose values are the words in
// their order (its range: 0 to the last word's index).
constexpr Param choice_param(std::string_view name, std::string_view flag, std::string_view group,
                             std::string_view choices, std::string_view help) {
  Param p{name, flag, group, ParamKind::choice, "", 0, 0, help};
  for (const char c : choices) p.hi += c == '|' ? 1 : 0;
  p.words = choices;
  return p;
}

// A value of parts (ParamKind::size, span or colour) named `parts` ("W|H"), each in [lo, hi] `unit`.
constexpr Param parts_param(std::string_view name, std::string_view flag, std::string_view group, ParamKind kind,
                            std::string_view parts, std::string_view unit, double lo, double hi,
                            std::string_view help) {
  Param p{name, flag, group, kind, unit, lo, hi, help};
  p.words = parts;
  return p;
}

// temperature_c, degrees Celsius, from absolute zero to 1000 C (a medium checks its own range).
constexpr Param temperature_param(std::string_view group, std::string_view help) {
  return {"temperature_c", "--temperature-c", group, ParamKind::real, "C", kMinTemperatureC, kMaxTemperatureC, help};
}

// seed, a whole number in [0, kMaxSeed] (random.hpp).
constexpr Param seed_param(std::string_view group, std::string_view help) {
  return {"seed", "--seed", group, ParamKind::integer, "", 0, double(kMaxSeed), help};
}

// threads, 0 (every core) to kMaxThreads.
constexpr Param threads_param(std::string_view group, std::string_view help) {
  return {"threads", "--threads", group, ParamKind::integer, "", 0, kMaxThreads, help};
}

}  // namespace hydrolux
