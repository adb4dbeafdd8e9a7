#include "hydrolux/core/parse.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <string>

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

namespace {

// The whole number a decimal text ("+12", "1.5e3", "90071992547409920e-1") stands for exactly, or
// nullopt if it has a fraction, is malformed or does not fit in a long long.
std::optional<long long> exact_integer(std::string_view s) {
  bool negative = false;
  if (!s.empty() && (s.front() == '+' || s.front() == '-')) {
    negative = s.front() == '-';
    s.remove_prefix(1);
  }
  std::string digits;  // the significand's digits, the point removed
  long long point = -1, exponent = 0;
  std::size_t i = 0;
  for (; i < s.size() && (std::isdigit(static_cast<unsigned char>(s[i])) || s[i] == '.'); ++i) {
    if (s[i] == '.') {
      if (point >= 0) return std::nullopt;
      point = static_cast<long long>(digits.size());
    } else {
      digits += s[i];
    }
  }
  if (digits.empty()) return std::nullopt;
  if (i < s.size()) {
    if (s[i] != 'e' && s[i] != 'E') return std::nullopt;
    std::string_view e = s.substr(i + 1);
    if (!e.empty() && e.front() == '+') e.remove_prefix(1);
    const auto [ptr, ec] = std::from_chars(e.data(), e.data() + e.size(), exponent);
    if (e.empty() || ec != std::errc() || ptr != e.data() + e.size() || exponent > 100 || exponent < -100)
      return std::nullopt;
  }
  // The decimal point moved by the exponent: digits before it are the integer, after it must be zeros.
  const long long int_digits = (point < 0 ? static_cast<long long>(digits.size()) : point) + exponent;
  if (int_digits < 0) return std::nullopt;
  for (long long k = int_digits; k < static_cast<long long>(digits.size()); ++k)
    if (digits[std::size_t(k)] != '0') return std::nullopt;
  if (int_digits > 19) return std::nullopt;  // beyond any long long
  std::string whole(negative ? 1 : 0, '-');
  for (long long k = 0; k < int_digits; ++k) whole.push_back(k < static_cast<long long>(digits.size()) ? digits[std::size_t(k)] : '0');
  if (int_digits == 0) whole.push_back('0');
  long long value = 0;
  const auto [ptr, ec] = std::from_chars(whole.data(), whole.data() + whole.size(), value);
  if (ec != std::errc() || ptr != whole.data() + whole.size()) return std::nullopt;
  return value;
}

}  // namespace

std::optional<long long> integer(std::string_view s) {
  const auto v = number(s);
  constexpr double kLimit = 9007199254740992.0;  // 2^53: every whole double below is exact
  if (!v || *v != std::floor(*v) || std::fabs(*v) > kLimit) return std::nullopt;
  if (std::fabs(*v) >= kLimit / 2) {
    // From 2^52 on, doubles are spaced 1 or 2 apart, so a decimal may have been rounded onto a whole
    // one ("9007199254740993", "4503599627370496.5"): there the text itself must be a whole number.
    const auto exact = exact_integer(s);
    if (!exact || *exact > (1LL << 53) || *exact < -(1LL << 53)) return std::nullopt;
    return *exact;
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
    // One value cannot run from A to a different B: "0:180:1" would silently be A alone.
    if (*n == 1 && a != b) throw Error("N = 1 gives one value: N must be >= 2, or A == B");
    const auto count = static_cast<std::size_t>(*n);
    out.reserve(count);
    // std::lerp is exact at both ends, monotonic and never overflows (a + (b - a) t rounded 180 to
    // 180.00000000000003 and 0 to -5.6e-17, outside [lo, hi]: found by fuzz_numbers); the clamp
    // keeps every value between A and B whatever the rounding.
    const double low = std::min(a, b), high = std::max(a, b);
    for (std::size_t i = 0; i < count; ++i)
      out.push_back(count == 1 ? a : std::clamp(std::lerp(a, b, double(i) / double(count - 1)), low, high));
    require_strictly_monotonic(out);  // a span too narrow for N distinct doubles repeats values
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
  require_strictly_monotonic(out);
  return out;
}

void require_strictly_monotonic(std::span<const double> values) {
  if (values.size() < 2) return;
  const bool increasing = values[1] > values[0];
  for (std::size_t i = 1; i < values.size(); ++i) {
    const double before = values[i - 1], v = values[i];
    if (v == before)
      throw Error(fmt::format("{:g} is repeated (values {} and {}); the values must be strictly increasing or "
                              "strictly decreasing",
                              v, i, i + 1));
    if ((v > before) != increasing)
      throw Error(fmt::format("{:g} follows {:g} in values that {}; the values must be strictly increasing or "
                              "strictly decreasing",
                              v, before, increasing ? "increase" : "decrease"));
  }
}

}  // namespace hydrolux::parse
