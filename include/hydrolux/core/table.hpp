#pragma once
// Tabulated data with provenance: CSV text whose leading '# key: value' lines say where the
// numbers come from (source, via, notes), then a header row and numeric rows.
#include <map>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace hydrolux {

struct Table {
  std::map<std::string, std::string> meta;  // from '# key: value' lines
  std::vector<std::string> columns;
  std::vector<std::vector<double>> data;  // data[column][row]

  // The column named `name`; throws IoError if absent.
  std::span<const double> column(std::string_view name) const;
  std::size_t rows() const { return data.empty() ? 0 : data.front().size(); }
  // meta[key], or "" if absent.
  std::string meta_or_empty(const std::string& key) const;
};

// Parses a table; `origin` names it in error messages. Throws IoError on malformed input.
Table parse_table(std::string_view text, std::string_view origin);

// Piecewise-linear interpolation of y(x) on strictly increasing x; x must lie in [x.front(),
// x.back()] (the caller checks the range and reports it).
double interpolate_linear(std::span<const double> x, std::span<const double> y, double at);

}  // namespace hydrolux
