#include "hydrolux/core/parse.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cmath>

#include "hydrolux/core/error.hpp"

namespace hydrolux::parse {

std::optional<double> number(std::string_view s) {
  const char* first = s.data();
  const char* last = s.data() + s.size();
  if (first != last && *first == '+') ++first;
  if (first != s.data() && first != last && *first == '-') return std::nullopt;  // "+-1"
  if (first == last || *first == '+') return std::nullopt;
  double v = 0;
  const auto [ptr, ec] = std::from_chars(first, last, v, std::chars_format::general);
  if (ec != std::errc() || ptr != last || !std::isfinite(v)) return std::nullopt;
  return v;
}

std::optional<long long> integer(std::string_view s) {
  const auto v = number(s);
  constexpr double kLimit = 9007199254740992.0;  // 2^53: every whole double below is exact
  if (!v || *v != std::floor(*v) || std::fabs(*v) > kLimit) return std::nullopt;
  if (std::fabs(*v) == kLimit) {
    // At 2^53 a decimal may have been rounded onto it ("9007199254740993" reads as 2^53): only the
    // digits of 2^53 itself, read exactly, are accepted there.
    std::string_view digits = s;
    if (!digits.empty() && digits.front() == '+') digits.remove_prefix(1);
    long long exact = 0;
    const auto [ptr, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), exact);
    if (ec != std::errc() || ptr != digits.data() + digits.size() || (exact != (1LL << 53) && exact != -(1LL << 53)))
      return std::nullopt;
  }
  return static_cast<long long>(*v);
}

std::optional<std::complex<double>> complex_number(std::string_view s) {
  if (s.empty()) return std::nullopt;
  if (s.back() != 'i') {
    const auto v = number(s);
    if (!v) return std::nullopt;
    return std::complex<double>(*v, 0.0);
  }
  s.remove_suffix(1);
  // The sign between the parts: the last '+' or '-' that is neither an exponent's sign nor the
  // first character.
  std::size_t split = std::string_view::npos;
  for (std::size_t i = s.size(); i-- > 1;)
    if ((s[i] == '+' || s[i] == '-') && s[i - 1] != 'e' && s[i - 1] != 'E') {
      split = i;
      break;
    }
  if (split == std::string_view::npos) return std::nullopt;
  const auto im_text = s.substr(split + 1);
  if (im_text.empty() || im_text.front() == '+' || im_text.front() == '-') return std::nullopt;
  const auto re = number(s.substr(0, split));
  const auto im = number(im_text);
  if (!re || !im) return std::nullopt;
  return std::complex<double>(*re, s[split] == '-' ? -*im : *im);
}

std::optional<std::array<double, 2>> pair(std::string_view text, char separator) {
  auto pos = text.find(separator);
  if (pos == std::string_view::npos && separator == 'x') pos = text.find('X');
  if (pos == std::string_view::npos) return std::nullopt;
  const auto a = number(text.substr(0, pos));
  const auto b = number(text.substr(pos + 1));
  if (!a || !b) return std::nullopt;
  return std::array<double, 2>{*a, *b};
}

std::vector<double> range_or_list(std::string_view text, double lo, double hi, std::size_t max_count) {
  const auto value = [&](std::string_view part) {
    const auto v = number(part);
    if (!v) throw Error(fmt::format("'{}' is not a number", part));
    if (*v < lo || *v > hi) throw Error(fmt::format("{:g} is outside [{:g}, {:g}]", *v, lo, hi));
    return *v;
  };
  std::vector<double> out;
  if (text.find(':') != std::string_view::npos) {
    std::vector<std::string_view> parts;
    std::size_t start = 0;
    for (std::size_t pos; (pos = text.find(':', start)) != std::string_view::npos; start = pos + 1)
      parts.push_back(text.substr(start, pos - start));
    parts.push_back(text.substr(start));
    if (parts.size() != 3) throw Error("A:B:N needs three parts");
    const double a = value(parts[0]), b = value(parts[1]);
    const auto n = integer(parts[2]);
    if (!n || *n < 1 || static_cast<unsigned long long>(*n) > max_count)
      throw Error(fmt::format("N must be a whole number in [1, {}]", max_count));
    const auto count = static_cast<std::size_t>(*n);
    out.reserve(count);
    // std::lerp is exact at both ends, monotonic and never overflows (a + (b - a) t rounded 180 to
    // 180.00000000000003 and 0 to -5.6e-17, outside [lo, hi]: found by fuzz_numbers); the clamp
    // keeps every value between A and B whatever the rounding.
    const double low = std::min(a, b), high = std::max(a, b);
    for (std::size_t i = 0; i < count; ++i)
      out.push_back(count == 1 ? a : std::clamp(std::lerp(a, b, double(i) / double(count - 1)), low, high));
    return out;
  }
  std::size_t start = 0;
  while (true) {
    const auto pos = text.find(',', start);
    out.push_back(value(text.substr(start, pos == std::string_view::npos ? pos : pos - start)));
    if (out.size() > max_count) throw Error(fmt::format("more than {} values", max_count));
    if (pos == std::string_view::npos) break;
    start = pos + 1;
  }
  return out;
}

}  // namespace hydrolux::parse
