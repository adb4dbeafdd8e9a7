#include "hydrolux/core/dataset.hpp"

#include <fmt/format.h>

#include <cstdlib>
#include <ctime>
#include <set>
#include <type_traits>

#include "hydrolux/core/error.hpp"
#include "hydrolux/core/parse.hpp"
#include "hydrolux/version.hpp"

namespace hydrolux {

Attributes& Attributes::text(std::string name, std::string_view value) {
  set(std::move(name), std::string(value));
  return *this;
}

Attributes& Attributes::number(std::string name, double value) {
  set(std::move(name), std::vector<double>{value});
  return *this;
}

Attributes& Attributes::numbers(std::string name, std::vector<double> values) {
  set(std::move(name), std::move(values));
  return *this;
}

Attributes& Attributes::integer(std::string name, std::int64_t value) {
  set(std::move(name), std::vector<std::int64_t>{value});
  return *this;
}

const Attribute* Attributes::find(std::string_view name) const {
  for (const auto& a : items_)
    if (a.name == name) return &a;
  return nullptr;
}

void Attributes::set(std::string name, AttributeValue value) {
  for (auto& a : items_)
    if (a.name == name) {
      a.value = std::move(value);
      return;
    }
  items_.push_back({std::move(name), std::move(value)});
}

const std::string& Dataset::dim(std::string name, std::size_t size) {
  dims.emplace_back(std::move(name), size);
  return dims.back().first;
}

Variable& Dataset::add(std::string name, std::vector<std::string> var_dims, VariableData data) {
  variables.push_back({std::move(name), std::move(var_dims), std::move(data), {}});
  return variables.back();
}

const Variable* Dataset::find(std::string_view name) const {
  for (const auto& v : variables)
    if (v.name == name) return &v;
  return nullptr;
}

std::size_t Dataset::dim_size(std::string_view name) const {
  for (const auto& [n, size] : dims)
    if (n == name) return size;
  throw Error(fmt::format("no dimension '{}'", name));
}

std::size_t value_count(const VariableData& data) {
  return std::visit([](const auto& v) { return v.size(); }, data);
}

namespace {
bool valid_name(std::string_view s) {
  if (s.empty() || s.size() > 256) return false;
  const auto letter = [](char c) { return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || c == '_'; };
  if (!letter(s[0])) return false;
  for (char c : s)
    if (!letter(c) && !(c >= '0' && c <= '9')) return false;
  return true;
}
}  // namespace

void Dataset::check() const {
  std::set<std::string_view> names;
  for (const auto& [n, size] : dims) {
    if (!valid_name(n)) throw Error(fmt::format("dataset: '{}' is not a valid dimension name", n));
    if (!names.insert(n).second) throw Error(fmt::format("dataset: dimension '{}' declared twice", n));
  }
  std::set<std::string_view> var_names;
  for (const auto& v : variables) {
    if (!valid_name(v.name)) throw Error(fmt::format("dataset: '{}' is not a valid variable name", v.name));
    if (!var_names.insert(v.name).second) throw Error(fmt::format("dataset: variable '{}' declared twice", v.name));
    std::size_t n = 1;
    for (const auto& d : v.dims) {
      if (!names.count(d)) throw Error(fmt::format("dataset: variable '{}' is over an undeclared dimension '{}'", v.name, d));
      n *= dim_size(d);
    }
    if (value_count(v.data) != n)
      throw Error(fmt::format("dataset: variable '{}' holds {} values, its dimensions {}", v.name,
                              value_count(v.data), n));
    // A coordinate variable (one dimension, of its own name) is strictly monotonic (CF 1.8, 5).
    if (v.dims.size() == 1 && v.dims[0] == v.name && !std::holds_alternative<std::vector<std::string>>(v.data)) {
      const std::vector<double> values = std::visit(
          [](const auto& d) -> std::vector<double> {
            if constexpr (std::is_same_v<std::decay_t<decltype(d)>, std::vector<std::string>>)
              return {};
            else
              return std::vector<double>(d.begin(), d.end());
          },
          v.data);
      try {
        parse::require_strictly_monotonic(values);
      } catch (const Error& e) {
        throw Error(fmt::format("dataset: coordinate '{}': {}", v.name, e.what()));
      }
    }
  }
}

std::string history_line(std::string_view call) {
  // No clock: the same inputs make the same bytes. A time only from SOURCE_DATE_EPOCH
  // (reproducible-builds.org), a whole number of seconds since 1970 up to the year 9999.
  const char* epoch = std::getenv("SOURCE_DATE_EPOCH");
  const auto seconds = epoch ? parse::integer(epoch) : std::nullopt;
  if (!seconds || *seconds < 0 || *seconds > 253402300799LL) return fmt::format("hydrolux {}: {}", kVersion, call);
  const std::time_t when = std::time_t(*seconds);
  std::tm utc{};
  gmtime_r(&when, &utc);
  char stamp[32];
  std::strftime(stamp, sizeof stamp, "%Y-%m-%dT%H:%M:%SZ", &utc);
  return fmt::format("{} hydrolux {}: {}", stamp, kVersion, call);
}

}  // namespace hydrolux
