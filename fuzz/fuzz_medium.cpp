// libFuzzer target: media, theories, light sources and colour spaces by name, as the CLI's
// --medium, --surrounding, --theory, --sun and --color-space take them (optics::find_medium,
// "const:<n>[+<k>i]" included; scatter::parse_theory; color::Illuminant::parse, "blackbody:<K>"
// included; color::parse_rgb_space); for a medium or source found, its value at a fuzzer-chosen
// wavelength and temperature. Errors must be hydrolux::Error (DomainError, UnknownNameError); a
// value returned must be finite.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <string>

#include "hydrolux/color/cie.hpp"
#include "hydrolux/core/error.hpp"
#include "hydrolux/optics/media.hpp"
#include "hydrolux/scatter/theories.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace hydrolux;
  if (size < 16) return 0;
  double lambda_nm = 0, temperature_c = 0;
  std::memcpy(&lambda_nm, data, 8);
  std::memcpy(&temperature_c, data + 8, 8);
  const std::string name(reinterpret_cast<const char*>(data + 16), size - 16);
  try {
    (void)scatter::parse_theory(name);
  } catch (const Error&) {
  }
  try {
    (void)color::parse_rgb_space(name);
  } catch (const Error&) {
  }
  try {
    const auto source = color::Illuminant::parse(name);
    const double v = source(lambda_nm);
    if (!std::isfinite(v) || v < 0) std::abort();
  } catch (const Error&) {
  }
  try {
    const auto medium = optics::find_medium(name);
    const auto n = medium->index(lambda_nm, std::isnan(temperature_c) ? std::nullopt : std::optional(temperature_c));
    if (!std::isfinite(n.real()) || !std::isfinite(n.imag())) std::abort();
  } catch (const Error&) {
  }
  return 0;
}
