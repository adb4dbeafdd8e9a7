#include "common.hpp"

#include "hydrolux/core/error.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <filesystem>
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

std::complex<double> parse_complex(const std::string& text, const std::string& flag) {
  const auto fail = [&] {
    return Error(fmt::format("{} '{}': expected a complex index like 1.333 or 1.333+1e-8i", flag, text));
  };
  std::string s = text;
  if (s.empty()) throw fail();
  if (s.back() != 'i') {
    const auto v = parse_number(s);
    if (!v || !std::isfinite(*v)) throw fail();
    return {*v, 0.0};
  }
  s.pop_back();
  // The sign between the parts: the last '+' or '-' that is not an exponent's sign or the first
  // character.
  std::size_t split = std::string::npos;
  for (std::size_t i = s.size(); i-- > 1;)
    if ((s[i] == '+' || s[i] == '-') && s[i - 1] != 'e' && s[i - 1] != 'E') {
      split = i;
      break;
    }
  if (split == std::string::npos) throw fail();
  const auto re = parse_number(s.substr(0, split));
  const auto im = parse_number(s.substr(split + 1));
  if (!re || !im || !std::isfinite(*re) || !std::isfinite(*im)) throw fail();
  return {*re, s[split] == '-' ? -*im : *im};
}

std::vector<double> parse_angles_deg(const std::string& text, const std::string& flag) {
  const auto fail = [&](const std::string& why) {
    return Error(fmt::format("{} '{}': {}; expected A:B:N (N angles from A to B) or a list "
                             "0,10,90, angles in [0, 180] deg",
                             flag, text, why));
  };
  const auto angle = [&](const std::string& part) {
    const auto v = parse_number(part);
    if (!v || !std::isfinite(*v)) throw fail("'" + part + "' is not a number");
    if (*v < 0 || *v > 180) throw fail(fmt::format("{:g} is outside [0, 180] deg", *v));
    return *v;
  };
  std::vector<double> out;
  if (text.find(':') != std::string::npos) {
    std::vector<std::string> parts;
    std::size_t start = 0;
    for (std::size_t pos; (pos = text.find(':', start)) != std::string::npos; start = pos + 1)
      parts.push_back(text.substr(start, pos - start));
    parts.push_back(text.substr(start));
    if (parts.size() != 3) throw fail("A:B:N needs three parts");
    const double a = angle(parts[0]), b = angle(parts[1]);
    const auto n = parse_number(parts[2]);
    if (!n || *n != std::floor(*n) || *n < 1 || *n > 1e6) throw fail("N must be a whole number in [1, 1000000]");
    const auto count = static_cast<std::size_t>(*n);
    for (std::size_t i = 0; i < count; ++i)
      out.push_back(count == 1 ? a : a + (b - a) * double(i) / double(count - 1));
    return out;
  }
  std::size_t start = 0;
  while (true) {
    const auto pos = text.find(',', start);
    out.push_back(angle(text.substr(start, pos == std::string::npos ? pos : pos - start)));
    if (pos == std::string::npos) break;
    start = pos + 1;
  }
  return out;
}

std::string output_image_extension(const std::string& path, const std::string& flag) {
  const std::filesystem::path p(path);
  std::string ext = p.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  if (ext != ".png" && ext != ".exr")
    throw Error(fmt::format("{} {}: the output must be a .png or .exr file", flag, path));
  const auto parent = p.parent_path();
  std::error_code ec;
  if (!parent.empty() && !std::filesystem::is_directory(parent, ec))
    throw Error(fmt::format("{} {}: directory {} does not exist", flag, path, parent.string()));
  return ext;
}

}  // namespace hydrolux::cli
