#include "hydrolux/core/error.hpp"

#include <fmt/format.h>

namespace hydrolux {

namespace {
// A context that states a relation to another quantity ("beyond {near_m}", "at most 1 / {fps}") follows
// the range in parentheses; one that names what the range belongs to ("water (IAPWS R9-97)") with "of".
bool is_relation(const std::string& context) {
  return context.rfind("beyond ", 0) == 0 || context.rfind("at most ", 0) == 0 || context.rfind("at least ", 0) == 0;
}

bool is_name_char(char c) { return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_'; }

// Calls `name(q)` for each quantity {q} of `context` (its name, possibly followed by '=' and a word:
// "{mode=}", "{mode=half-dome}") and
// `text(t)` for the text between them; "{{" and "}}" are a brace of the text (escape_braces).
template <class Text, class Name>
void scan(std::string_view context, Text&& text, Name&& name) {
  std::size_t at = 0;
  while (at < context.size()) {
    const auto open = context.find_first_of("{}", at);
    if (open == std::string_view::npos) {
      text(context.substr(at));
      return;
    }
    text(context.substr(at, open - at));
    if (open + 1 < context.size() && context[open + 1] == context[open]) {  // "{{" or "}}"
      text(context.substr(open, 1));
      at = open + 2;
      continue;
    }
    const auto close = context[open] == '{' ? context.find('}', open) : std::string_view::npos;
    // A name, then possibly '=' and a word ("{mode=}", "{mode=half-dome}").
    bool quantity = close != std::string_view::npos && close > open + 1 && is_name_char(context[open + 1]);
    bool after_equals = false;
    for (std::size_t i = open + 1; quantity && i < close; ++i) {
      const char c = context[i];
      if (c == '=' && !after_equals) after_equals = true;
      else quantity = is_name_char(c) || (after_equals && c == '-');
    }
    if (!quantity) {  // a lone brace
      text(context.substr(open, 1));
      at = open + 1;
      continue;
    }
    name(context.substr(open + 1, close - open - 1));
    at = close + 1;
  }
}

std::string message(const std::string& quantity, double value, double lo, double hi,
                    const std::string& context) {
  std::string m = fmt::format("{} = {:g} is outside [{:g}, {:g}]", quantity, value, lo, hi);
  const std::string c = spell_quantities(context, {});
  if (!c.empty()) m += is_relation(c) ? fmt::format(" ({})", c) : fmt::format(", the valid range of {}", c);
  return m;
}
}  // namespace

std::string spell_quantities(std::string_view text, const Spelling& spell) {
  std::string out;
  scan(text, [&](std::string_view t) { out += t; }, [&](std::string_view q) { out += spell ? spell(q) : std::string(q); });
  return out;
}

std::string escape_braces(std::string_view text) {
  std::string out;
  for (const char c : text) {
    out += c;
    if (c == '{' || c == '}') out += c;
  }
  return out;
}

ParamError::ParamError(std::string text) : Error(spell_quantities(text, {})), text_(std::move(text)) {}

DomainError::DomainError(std::string quantity, double value, double lo, double hi,
                         std::string context)
    : Error(message(quantity, value, lo, hi, context)),
      quantity_(std::move(quantity)),
      value_(value),
      lo_(lo),
      hi_(hi),
      context_(std::move(context)) {}

DomainError::DomainError(Whole, std::string message, std::string quantity, double value, double lo, double hi,
                         std::string unit)
    : Error(std::move(message)), quantity_(std::move(quantity)), value_(value), lo_(lo), hi_(hi), unit_(std::move(unit)) {}

DomainError DomainError::with_message(std::string message, std::string quantity, double value, double lo,
                                      double hi, std::string unit) {
  return DomainError(Whole{}, std::move(message), std::move(quantity), value, lo, hi, std::move(unit));
}

std::string DomainError::range_text(const Spelling& spell) const {
  // The unit: the one given, else the quantity's suffix when it names one: wavelength_nm -> nm,
  // theta_deg -> deg, temperature_c -> C (m_imag has none).
  std::string unit = unit_.empty() ? std::string() : " " + unit_;
  if (const auto us = quantity_.rfind('_'); unit.empty() && us != std::string::npos) {
    const std::string suffix = quantity_.substr(us + 1);
    for (const char* u : {"nm", "um", "mm", "m", "deg", "rad", "s"})
      if (suffix == u) unit = " " + suffix;
    if (suffix == "c") unit = " C";
    if (suffix == "mmh") unit = " mm/h";  // rain_rate_mmh
  }
  std::string m = fmt::format("outside the valid range [{:g}, {:g}]{}", lo_, hi_, unit);
  const std::string c = spell_quantities(context_, spell);
  if (!c.empty()) m += is_relation(c) ? fmt::format(" ({})", c) : fmt::format(" of {}", c);
  return m;
}

std::string DomainError::said(const Spelling& spell) const {
  return fmt::format("{} {:g} is {}", spell ? spell(quantity_) : quantity_, value_, range_text(spell));
}

void require_in_range(const char* quantity, double value, double lo, double hi,
                      const std::string& context) {
  if (!(value >= lo && value <= hi)) throw DomainError(quantity, value, lo, hi, context);
}

std::string printable(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  const auto byte = [&](std::size_t i) { return static_cast<unsigned char>(text[i]); };
  for (std::size_t i = 0; i < text.size();) {
    const unsigned char c = byte(i);
    if (c == '\\') {  // escaped too, so that "\n" in the output always means an escape
      out += "\\\\";
      ++i;
      continue;
    }
    if (c >= 0x20 && c < 0x7f) {
      out += char(c);
      ++i;
      continue;
    }
    // The length of a valid UTF-8 sequence starting here (RFC 3629: no overlong forms, no
    // surrogates, at most U+10FFFF), or 0.
    std::size_t n = 0;
    if (c >= 0xc2 && c <= 0xdf) n = 2;
    else if (c >= 0xe0 && c <= 0xef) n = 3;
    else if (c >= 0xf0 && c <= 0xf4) n = 4;
    if (n != 0 && i + n <= text.size()) {
      bool ok = true;
      for (std::size_t k = 1; k < n; ++k) ok = ok && (byte(i + k) & 0xc0) == 0x80;
      const unsigned char c1 = byte(i + 1);
      if (ok && ((c == 0xe0 && c1 < 0xa0) || (c == 0xed && c1 > 0x9f) || (c == 0xf0 && c1 < 0x90) ||
                 (c == 0xf4 && c1 > 0x8f)))
        ok = false;
      // C1 controls (U+0080-U+009F) act on some terminals as escapes too; zero-width and
      // direction-changing characters (U+200B-U+200F, U+2028-U+202E, U+2066-U+2069) make a name
      // print as something else.
      if (ok && c == 0xc2 && c1 < 0xa0) ok = false;
      if (ok && c == 0xe2 && c1 == 0x80) {
        const unsigned char c2 = byte(i + 2);
        if ((c2 >= 0x8b && c2 <= 0x8f) || (c2 >= 0xa8 && c2 <= 0xae)) ok = false;
      }
      if (ok && c == 0xe2 && c1 == 0x81 && byte(i + 2) >= 0xa6 && byte(i + 2) <= 0xa9) ok = false;
      if (ok) {
        out.append(text.substr(i, n));
        i += n;
        continue;
      }
    }
    switch (c) {
      case '\n': out += "\\n"; break;
      case '\r': out += "\\r"; break;
      case '\t': out += "\\t"; break;
      default: out += fmt::format("\\x{:02x}", c);
    }
    ++i;
  }
  return out;
}

}  // namespace hydrolux
