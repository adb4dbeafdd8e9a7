#include "hydrolux/core/table.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>

#include "hydrolux/core/error.hpp"

namespace hydrolux {

namespace {

std::string_view trim(std::string_view s) {
  const auto b = s.find_first_not_of(" \t\r");
  if (b == std::string_view::npos) return {};
  const auto e = s.find_last_not_of(" \t\r");
  return s.substr(b, e - b + 1);
}

std::vector<std::string_view> split(std::string_view line, char sep) {
  std::vector<std::string_view> out;
  std::size_t start = 0;
  while (true) {
    const auto pos = line.find(sep, start);
    out.push_back(trim(line.substr(start, pos == std::string_view::npos ? pos : pos - start)));
    if (pos == std::string_view::npos) break;
    start = pos + 1;
  }
  return out;
}

}  // namespace

std::span<const double> Table::column(std::string_view name) const {
  const auto it = std::find(columns.begin(), columns.end(), name);
  if (it == columns.end()) throw IoError(fmt::format("table has no column '{}'", name));
  return data[static_cast<std::size_t>(it - columns.begin())];
}

std::string Table::meta_or_empty(const std::string& key) const {
  const auto it = meta.find(key);
  return it == meta.end() ? std::string() : it->second;
}

Table parse_table(std::string_view text, std::string_view origin) {
  Table t;
  std::size_t line_no = 0;
  std::size_t pos = 0;
  while (pos < text.size()) {
    const auto end = text.find('\n', pos);
    const std::string_view raw =
        text.substr(pos, end == std::string_view::npos ? std::string_view::npos : end - pos);
    pos = end == std::string_view::npos ? text.size() : end + 1;
    ++line_no;
    const std::string_view line = trim(raw);
    if (line.empty()) continue;
    if (line.front() == '#') {
      const std::string_view body = trim(line.substr(1));
      const auto colon = body.find(':');
      if (colon != std::string_view::npos) {
        std::string key(trim(body.substr(0, colon)));
        std::string value(trim(body.substr(colon + 1)));
        auto [it, inserted] = t.meta.emplace(key, value);
        if (!inserted) it->second += " " + value;  // continuation of a long field
      }
      continue;
    }
    const auto cells = split(line, ',');
    if (t.columns.empty()) {
      for (auto c : cells) t.columns.emplace_back(c);
      t.data.resize(t.columns.size());
      continue;
    }
    if (cells.size() != t.columns.size())
      throw IoError(fmt::format("{}:{}: expected {} values, found {}", origin, line_no,
                                t.columns.size(), cells.size()));
    for (std::size_t i = 0; i < cells.size(); ++i) {
      double v = 0;
      const auto* first = cells[i].data();
      const auto* last = first + cells[i].size();
      const auto [ptr, ec] = std::from_chars(first, last, v);
      if (ec != std::errc() || ptr != last)
        throw IoError(fmt::format("{}:{}: '{}' is not a number", origin, line_no, cells[i]));
      t.data[i].push_back(v);
    }
  }
  if (t.columns.empty() || t.rows() == 0)
    throw IoError(fmt::format("{}: no data rows", origin));
  return t;
}

double interpolate_linear(std::span<const double> x, std::span<const double> y, double at) {
  const auto it = std::upper_bound(x.begin(), x.end(), at);
  if (it == x.begin()) return y.front();
  if (it == x.end()) return y.back();
  const auto i = static_cast<std::size_t>(it - x.begin());
  const double t = (at - x[i - 1]) / (x[i] - x[i - 1]);
  return y[i - 1] + t * (y[i] - y[i - 1]);
}

}  // namespace hydrolux
