#include "hydrolux/core/params.hpp"

#include <fmt/format.h>

#include "hydrolux/core/error.hpp"

namespace hydrolux {

namespace {
std::string with_unit(std::string text, std::string_view unit) {
  if (!unit.empty()) text += fmt::format(" {}", unit);
  return text;
}
}  // namespace

std::string Param::range_text() const {
  if (kind == ParamKind::flag) return {};
  if (kind == ParamKind::integer) return with_unit(fmt::format("[{}, {}]", (long long)lo, (long long)hi), unit);
  return with_unit(fmt::format("[{:g}, {:g}]", lo, hi), unit);
}

void Param::check(double value) const {
  const bool whole = kind != ParamKind::integer || value == std::floor(value);
  if (value >= lo && value <= hi && whole) return;
  const std::string what = fmt::format("{} = {:g} is {} {}", name, value,
                                       whole ? "outside" : "not a whole number in", range_text());
  throw DomainError::with_message(what, std::string(name), value, lo, hi);
}

std::string ParamInfo::default_text() const {
  if (std::isnan(default_value)) return {};
  if (param->kind == ParamKind::flag) return default_value != 0 ? "on" : "off";
  if (param->kind == ParamKind::integer) return fmt::format("{}", (long long)default_value);
  return fmt::format("{:g}", default_value);
}

}  // namespace hydrolux
