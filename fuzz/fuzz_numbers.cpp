// libFuzzer target: the strict number parsers (core/parse.hpp) and the CLI's flag validators built
// on them. Invariants: nothing returned is NaN or infinite; whole numbers are whole; ranges and
// lists stay within their bounds and counts; a value a validator accepts parses within its range.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "common.hpp"
#include "hydrolux/core/error.hpp"
#include "hydrolux/core/parse.hpp"

namespace {
void check(bool ok) {
  if (!ok) std::abort();
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace hydrolux;
  if (size == 0) return 0;
  const int which = data[0] % 8;
  std::string text(reinterpret_cast<const char*>(data + 1), size - 1);
  switch (which) {
    case 0:
      if (const auto v = parse::number(text)) check(std::isfinite(*v));
      break;
    case 1:
      if (const auto v = parse::integer(text)) check(std::fabs(double(*v)) <= 9007199254740992.0);
      break;
    case 2:
      if (const auto v = parse::complex_number(text)) check(std::isfinite(v->real()) && std::isfinite(v->imag()));
      break;
    case 3:
      for (char sep : {',', 'x'})
        if (const auto v = parse::pair(text, sep)) check(std::isfinite((*v)[0]) && std::isfinite((*v)[1]));
      break;
    case 4:
      try {
        const auto v = parse::range_or_list(text, 0, 180, 1000);
        check(!v.empty() && v.size() <= 1000);
        for (double x : v) check(x >= 0 && x <= 180);
      } catch (const Error&) {
      }
      break;
    case 5: {  // number_in: accepted means finite and in range
      auto validator = cli::number_in(-1.5, 1e3, "nm");
      std::string s = text;
      if (validator(s).empty()) {
        const auto v = parse::number(s);
        check(v && *v >= -1.5 && *v <= 1e3);
      }
      break;
    }
    case 6: {  // positive_number: (0, hi]
      auto validator = cli::positive_number(1e6);
      std::string s = text;
      if (validator(s).empty()) {
        const auto v = parse::number(s);
        check(v && *v > 0 && *v <= 1e6);
      }
      break;
    }
    case 7: {  // integer_in rewrites what it accepts to plain digits for CLI11's conversion
      auto validator = cli::integer_in(-5, 16384);
      std::string s = text;
      if (validator(s).empty()) {
        const auto v = parse::integer(s);
        check(v && *v >= -5 && *v <= 16384 && s == std::to_string(*v));
      }
      break;
    }
  }
  return 0;
}
