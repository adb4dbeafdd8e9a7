// libFuzzer target: the data/ CSV reader (core/table.hpp) and interpolation on what it returns.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "hydrolux/core/error.hpp"
#include "hydrolux/core/table.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace hydrolux;
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    const Table t = parse_table(text, "fuzz.csv");
    if (t.columns.empty() || t.data.size() != t.columns.size()) std::abort();
    for (const auto& column : t.data)
      if (column.size() != t.rows()) std::abort();
    (void)t.column(t.columns.front());
    const auto x = t.data.front();
    if (t.columns.size() >= 2 && x.size() >= 2 && std::is_sorted(x.begin(), x.end()) &&
        std::adjacent_find(x.begin(), x.end()) == x.end() && std::isfinite(x.front()) && std::isfinite(x.back())) {
      const auto& y = t.data[1];
      for (double at : {x.front(), x.back(), 0.5 * x.front() + 0.5 * x.back()}) (void)interpolate_linear(x, y, at);
    }
  } catch (const Error&) {
  }
  return 0;
}
