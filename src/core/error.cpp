#include "hydrolux/core/error.hpp"

#include <fmt/format.h>

namespace hydrolux {

namespace {
std::string message(const std::string& quantity, double value, double lo, double hi,
                    const std::string& context) {
  std::string m = fmt::format("{} = {:g} is outside [{:g}, {:g}]", quantity, value, lo, hi);
  if (!context.empty()) m += fmt::format(", the valid range of {}", context);
  return m;
}
}  // namespace

DomainError::DomainError(std::string quantity, double value, double lo, double hi,
                         std::string context)
    : Error(message(quantity, value, lo, hi, context)),
      quantity_(std::move(quantity)),
      value_(value),
      lo_(lo),
      hi_(hi),
      context_(std::move(context)) {}

std::string DomainError::range_text() const {
  // The unit is the quantity's suffix when it names one: wavelength_nm -> nm, theta_deg -> deg,
  // temperature_c -> C (m_imag has none).
  std::string unit;
  if (const auto us = quantity_.rfind('_'); us != std::string::npos) {
    const std::string suffix = quantity_.substr(us + 1);
    for (const char* u : {"nm", "um", "mm", "deg", "rad", "s", "mmh"})
      if (suffix == u) unit = " " + suffix;
    if (suffix == "c") unit = " C";
  }
  std::string m = fmt::format("outside the valid range [{:g}, {:g}]{}", lo_, hi_, unit);
  if (!context_.empty()) m += fmt::format(" of {}", context_);
  return m;
}

void require_in_range(const char* quantity, double value, double lo, double hi,
                      const std::string& context) {
  if (!(value >= lo && value <= hi)) throw DomainError(quantity, value, lo, hi, context);
}

}  // namespace hydrolux
