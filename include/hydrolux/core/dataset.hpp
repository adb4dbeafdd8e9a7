#pragma once
// A labelled dataset: named dimensions, variables over them with their attributes, and global
// attributes (NetCDF's data model, as CF describes it and xarray holds it). A table's labelled form
// is built once as a Dataset (io::lee_dataset, io::mie_dataset); the NetCDF writer
// (io/netcdf.hpp) and the Python package's to_xarray() both take it from there, so a file and an
// xarray.Dataset of the same table hold the same names, units and attributes.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <utility>
#include <variant>
#include <vector>

namespace hydrolux {

// An attribute's value: text, or one or more numbers (doubles or 64-bit integers).
using AttributeValue = std::variant<std::string, std::vector<double>, std::vector<std::int64_t>>;

struct Attribute {
  std::string name;
  AttributeValue value;
};

class Attributes {
 public:
  Attributes& text(std::string name, std::string_view value);
  Attributes& number(std::string name, double value);
  Attributes& numbers(std::string name, std::vector<double> values);
  Attributes& integer(std::string name, std::int64_t value);
  // The attribute of that name, or nullptr.
  const Attribute* find(std::string_view name) const;
  // Sets `name` to `value`, replacing an attribute of that name (kept in its place) or appending.
  void set(std::string name, AttributeValue value);
  const std::vector<Attribute>& items() const { return items_; }

 private:
  std::vector<Attribute> items_;
};

// A variable's values, row-major over its dimensions (the last varies fastest).
using VariableData =
    std::variant<std::vector<double>, std::vector<float>, std::vector<std::int32_t>, std::vector<std::string>>;

struct Variable {
  std::string name;
  std::vector<std::string> dims;  // empty: a scalar
  VariableData data;
  Attributes attrs;
};

struct Dataset {
  std::vector<std::pair<std::string, std::size_t>> dims;
  std::vector<Variable> variables;
  Attributes attrs;

  // Adds a dimension and returns its name.
  const std::string& dim(std::string name, std::size_t size);
  Variable& add(std::string name, std::vector<std::string> dims, VariableData data);
  const Variable* find(std::string_view name) const;
  std::size_t dim_size(std::string_view name) const;  // Error if no such dimension
  // Error naming the fault: a name used twice or not a NetCDF name ([A-Za-z_][A-Za-z0-9_]*), a
  // variable over a dimension that does not exist, or whose values are not the product of its
  // dimensions' sizes, or a numeric coordinate variable (one dimension of its own name) whose values
  // are not strictly increasing or strictly decreasing (CF).
  void check() const;
};

// The number of values a variable holds.
std::size_t value_count(const VariableData& data);

// A CF "history" line: "hydrolux <version>: <call>", with no time, so that the same inputs make the
// same bytes (README); "<UTC time, ISO 8601> hydrolux <version>: <call>" when the environment sets
// SOURCE_DATE_EPOCH (reproducible-builds.org: whole seconds since 1970-01-01 UTC, at most the end
// of the year 9999; any other value is not a time and is left out).
std::string history_line(std::string_view call);

}  // namespace hydrolux
