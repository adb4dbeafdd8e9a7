#pragma once
// The Python door onto the declared parameters (hydrolux/core/params.hpp): keyword arguments of
// the declared names, converted and range-checked as the CLI checks its flags, in the same words.
#include <fmt/format.h>

#include <span>
#include <string>

#include "common.hpp"
#include "hydrolux/core/params.hpp"

namespace hydrolux::py_bind {

// Where a declared real's range is checked: here, as the CLI's flags check it ("rain_rate_mmh = 600 is
// outside [0, 500] mm/h"), or by the library call that follows, which reads the same range from the
// table and says it in its own words (hydrolux.lee: atmos::validate, as before the table existed).
enum class RealRanges { checked, by_library };

// One declared value from a Python object: a real, a whole number, a bool, a choice's word (str), or
// a size's, span's or colour's parts (a sequence of numbers: (1280, 720)), in its range.
inline ParamValue param_value(const Param& p, py::handle v, RealRanges ranges = RealRanges::checked) {
  const std::string name(p.name);
  switch (p.kind) {
    case ParamKind::flag:
      return {flag_arg(v, name.c_str()) ? 1.0 : 0.0};
    case ParamKind::integer:
      return {double(whole_arg(v, name.c_str(), (long long)p.lo, (long long)p.hi, std::string(p.unit).c_str()))};
    case ParamKind::choice:
      if (!PyUnicode_Check(v.ptr()))
        throw py::type_error(fmt::format("{}: expected a string ({}), got {}", name, p.form(Door::python), describe(v)));
      return p.parse_text(v.cast<std::string>(), Door::python);  // "mode 'x': expected per-pixel, ..."
    case ParamKind::real: {
      const double x = real_arg(v, name.c_str());
      if (ranges == RealRanges::checked) p.check(x);  // "rain_rate_mmh = 600 is outside [0, 500] mm/h"
      return {x};
    }
    case ParamKind::path:  // text, not a number (apply_kwargs stores it)
      throw std::logic_error("param_value: " + name + " is a path");
    default:
      break;
  }
  // The parts: a sequence (not a str, a mapping or a set) of parts() numbers, then checked as a whole.
  const auto wrong = [&] {
    return py::type_error(fmt::format("{}: expected {}, got {}", name, p.form(Door::python), describe(v)));
  };
  if (PyUnicode_Check(v.ptr()) || PyBytes_Check(v.ptr()) || !PySequence_Check(v.ptr())) throw wrong();
  const auto seq = py::reinterpret_borrow<py::sequence>(v);
  if (py::len(seq) != std::size_t(p.parts())) throw wrong();
  ParamValue value{};
  for (int i = 0; i < p.parts(); ++i) {
    const std::string part = fmt::format("{}[{}]", name, i);
    value[std::size_t(i)] = p.kind == ParamKind::size
                                ? double(whole_arg(seq[std::size_t(i)], part.c_str(), (long long)p.lo,
                                                   (long long)p.hi, std::string(p.unit).c_str()))
                                : real_arg(seq[std::size_t(i)], part.c_str());
  }
  p.check(value, Door::python);  // "curtain_distance_m (3000, 1000): expected (NEAR, FAR), ..."
  return value;
}

// Stores every keyword of `kw` that names a field (None: the default) into `request`, in the
// table's order; a pair of parameters that replace one another refused when both are given.
template <class Request>
void apply_kwargs(Request& request, const py::dict& kw, std::span<const Field<Request>> fields,
                  RealRanges ranges = RealRanges::checked) {
  const auto given = [&](std::string_view name) {
    const std::string key(name);
    return kw.contains(key) && !kw[key.c_str()].is_none();
  };
  for (const auto& f : fields)
    if (!f.param.excludes.empty() && given(f.param.name) && given(f.param.excludes))
      throw Error(fmt::format("{}: give {} or {}, not both", f.param.name, f.param.excludes, f.param.name));
  for (const auto& f : fields) {
    if (!given(f.param.name)) continue;
    const py::handle v = kw[std::string(f.param.name).c_str()];
    if (f.param.kind != ParamKind::path) {
      f.set_value(request, param_value(f.param, v, ranges));
      continue;
    }
    // A path: a str or an os.PathLike (pathlib.Path), as open() takes one.
    py::object text = py::reinterpret_steal<py::object>(PyOS_FSPath(v.ptr()));
    if (!text || !PyUnicode_Check(text.ptr())) {
      PyErr_Clear();
      throw py::type_error(fmt::format("{}: expected a path (str or os.PathLike), got {}", f.param.name, describe(v)));
    }
    f.set_text(request, text.cast<std::string>());
  }
}

}  // namespace hydrolux::py_bind
