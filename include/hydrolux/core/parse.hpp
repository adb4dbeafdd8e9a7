#pragma once
// Text to numbers, strictly: what a command line, a spec string or a table cell holds. Every
// parser accepts the whole text or nothing (no leading or trailing spaces, no trailing garbage),
// and never returns NaN or infinity. The CLI names its flag around the reason these give; the
// fuzzers in fuzz/ drive them with arbitrary bytes.
#include <array>
#include <complex>
#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace hydrolux::parse {

// A finite decimal number: "1.5", "-2e-3", "+4", ".5". Not hex, "inf", "nan", "1,5" or "".
std::optional<double> number(std::string_view text);

// A whole number, written as one ("1024") or in exponent form ("1e3"), within +-2^53.
std::optional<long long> integer(std::string_view text);

// A complex number: "1.333", "1.333+1e-8i", "1.333-0i" (the imaginary part last, with its sign).
std::optional<std::complex<double>> complex_number(std::string_view text);

// Two numbers joined by `separator`: "256,240.5" with ',', "640x480" with 'x' (also 'X').
std::optional<std::array<double, 2>> pair(std::string_view text, char separator);

// "A:B:N" (N values evenly spaced from A to B inclusive, N whole in [2, max_count], or 1 with A ==
// B) or a list "a,b,c" (at most max_count values); every value in [lo, hi], and the values strictly
// increasing or strictly decreasing (no value twice: they label a table's rows, a NetCDF
// coordinate, which CF requires to be strictly monotonic). Throws hydrolux::Error with the reason
// (not naming a flag).
std::vector<double> range_or_list(std::string_view text, double lo, double hi, std::size_t max_count);

// Error ("10 is repeated (values 2 and 3); ...", "45 follows 90 in values that increase; ...")
// unless `values` are strictly increasing or strictly decreasing. Not naming what they are.
void require_strictly_monotonic(std::span<const double> values);

}  // namespace hydrolux::parse
