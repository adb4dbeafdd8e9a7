#include "common.hpp"

#include <fmt/format.h>

#include <charconv>
#include <cmath>
#include <optional>

namespace hydrolux::cli {

namespace {

std::optional<double> parse_number(const std::string& s) {
  double v = 0;
  const char* first = s.data();
  const char* last = s.data() + s.size();
  if (first != last && *first == '+') ++first;
  const auto [ptr, ec] = std::from_chars(first, last, v);
  if (ec != std::errc() || ptr != last) return std::nullopt;
  return v;
}

std::string with_unit(const std::string& text, const std::string& unit) {
  return unit.empty() ? text : text + " " + unit;
}

CLI::Validator bounded(double lo, double hi, bool lo_open, const std::string& unit) {
  const std::string range =
      with_unit(fmt::format("{}{:g}, {:g}]", lo_open ? "(" : "[", lo, hi), unit);
  return CLI::Validator(
      [=](std::string& s) -> std::string {
        const auto v = parse_number(s);
        if (!v || !std::isfinite(*v))
          return fmt::format("'{}' is not a finite number; valid range {}", s, range);
        if ((lo_open ? !(*v > lo) : !(*v >= lo)) || !(*v <= hi))
          return fmt::format("{} is outside the valid range {}", s, range);
        return {};
      },
      range);
}

}  // namespace

CLI::Validator number_in(double lo, double hi, const std::string& unit) {
  return bounded(lo, hi, false, unit);
}

CLI::Validator positive_number(double hi, const std::string& unit) {
  return bounded(0, hi, true, unit);
}

}  // namespace hydrolux::cli
