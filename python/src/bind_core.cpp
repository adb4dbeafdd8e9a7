// hydrolux._core: the process and the batch helpers: threads, files (io/files.hpp), memory
// (core/memory.hpp), the CLI's number parsers (core/parse.hpp) and its message helpers.
#include <tbb/global_control.h>

#include <cmath>
#include <cstddef>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

#include "bindings.hpp"
#include "hydrolux/core/error.hpp"
#include "hydrolux/core/memory.hpp"
#include "hydrolux/core/params.hpp"
#include "hydrolux/core/parse.hpp"  // batch: the CLI's number parsers (parse_number, parse_integer)
#include "hydrolux/io/files.hpp"
#include "hydrolux/io/frames.hpp"
#include "hydrolux/jobs.hpp"
#include "hydrolux/rain/rain.hpp"

namespace hydrolux::py_bind {
namespace {

// ---- files ----------------------------------------------------------------------------------

// At most n threads for every parallel loop of this process from now on (0: every core again).
void set_threads(py::handle threads) {
  const int n = int(whole_arg(threads, "threads", 0, kMaxThreads));
  static std::unique_ptr<tbb::global_control> limit;
  limit.reset();
  if (n > 0) limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, std::size_t(n));
}

void write_file(const std::string& path, const py::bytes& data, const std::string& label) {
  std::string bytes = data;
  py::gil_scoped_release release;
  io::write_file(path, bytes, label);
}

py::object attribute_value(const AttributeValue& v) {
  if (const auto* s = std::get_if<std::string>(&v)) return py::str(*s);
  if (const auto* d = std::get_if<std::vector<double>>(&v)) {
    if (d->size() == 1) return py::float_((*d)[0]);
    return py::array_t<double>(py::ssize_t(d->size()), d->data());
  }
  const auto& i = std::get<std::vector<std::int64_t>>(v);
  if (i.size() == 1) return py::int_(i[0]);
  return py::array_t<std::int64_t>(py::ssize_t(i.size()), i.data());
}

py::dict attribute_dict(const Attributes& attrs) {
  py::dict d;
  for (const auto& a : attrs.items()) d[py::str(a.name)] = attribute_value(a.value);
  return d;
}

}  // namespace

py::dict dataset_dict(const Dataset& ds) {
  py::list dims, variables;
  for (const auto& [name, size] : ds.dims) dims.append(py::make_tuple(name, size));
  for (const auto& v : ds.variables) {
    std::vector<py::ssize_t> shape;
    for (const auto& d : v.dims) shape.push_back(py::ssize_t(ds.dim_size(d)));
    py::object array = std::visit(
        [&](const auto& data) -> py::object {
          using T = typename std::decay_t<decltype(data)>::value_type;
          if constexpr (std::is_same_v<T, std::string>) {
            py::list items;
            for (const auto& e : data) items.append(py::str(e));
            return py::module_::import("numpy").attr("array")(items, py::arg("dtype") = "object").attr("reshape")(
                py::cast(shape));
          } else {
            py::array_t<T> a(shape);
            std::copy(data.begin(), data.end(), a.mutable_data());
            return a;
          }
        },
        v.data);
    py::tuple var_dims(v.dims.size());
    for (std::size_t i = 0; i < v.dims.size(); ++i) var_dims[i] = py::str(v.dims[i]);
    variables.append(py::make_tuple(v.name, var_dims, array, attribute_dict(v.attrs)));
  }
  py::dict out;
  out["dims"] = dims, out["attrs"] = attribute_dict(ds.attrs), out["variables"] = variables;
  return out;
}

namespace {

// A job's declared parameters as dicts (_core.params): name, flag, kind, range, help, default, ...
py::list params_of(const std::string& job) {
  py::list out;
  for (const auto& info : hydrolux::job_spec(job).params) {
    const Param& p = *info.param;
    py::dict d;
    d["name"] = std::string(p.name), d["flag"] = std::string(p.flag), d["group"] = std::string(p.group);
    d["short_flag"] = std::string(p.short_flag);  // "-o" for --output; "" for none
    d["kind"] = std::string(kind_name(p.kind));
    // A choice's words, or the names of a size's, span's or colour's parts ("W", "H"); empty otherwise.
    py::list words;
    for (const auto w : p.word_list()) words.append(std::string(w));
    d["words"] = words;
    d["unit"] = std::string(p.unit), d["lo"] = p.lo, d["hi"] = p.hi;
    // How Python takes a value: "[0, 500] mm/h", "physical or whitepaper", "(W, H), each a whole number in ...".
    d["form"] = p.form(Door::python);
    d["range"] = p.range_text(), d["help"] = std::string(p.help), d["excludes"] = std::string(p.excludes);
    // The name it had before (taken for one release with a warning), or None.
    d["deprecated"] = p.deprecated.empty() ? py::object(py::none()) : py::object(py::str(std::string(p.deprecated)));
    // Where it has an effect (Param::only_with, not_with: words between '|'; "" where always).
    d["only_with"] = std::string(p.only_with), d["not_with"] = std::string(p.not_with);
    d["default_text"] = info.default_text();
    if (p.kind == ParamKind::path)  // a file's or a folder's name, or None
      d["default"] = info.default_path.empty() ? py::object(py::none()) : py::object(py::str(info.default_path));
    else if (std::isnan(info.default_value)) d["default"] = py::none();
    else if (p.kind == ParamKind::real) d["default"] = info.default_value;
    else if (p.kind == ParamKind::integer) d["default"] = (long long)info.default_value;
    else if (p.kind == ParamKind::flag) d["default"] = info.default_value != 0;
    else if (p.kind == ParamKind::choice) d["default"] = p.value_text(info.default_value);
    else {  // a tuple of the parts, as Python takes them: (1280, 720)
      py::list parts;
      for (int i = 0; i < p.parts(); ++i) {
        const double v = info.default_parts[std::size_t(i)];
        if (p.kind == ParamKind::size) parts.append((long long)v);
        else parts.append(v);
      }
      d["default"] = py::tuple(parts);
    }
    out.append(d);
  }
  return out;
}

}  // namespace

void bind_core(py::module_& m) {
  // A CF history line, "<UTC time> hydrolux <version>: <call>" (core/dataset.hpp): the CLI's NetCDF
  // files and the package's to_xarray() state their origin alike.
  m.def("history_line", [](const std::string& call) { return hydrolux::history_line(call); }, py::arg("call"));
  m.def("set_threads", &set_threads, py::arg("threads"));
  m.def("write_file", &write_file, py::arg("path"), py::arg("data"), py::arg("label"));
  // ---- batch: the CLI's own number parsers (python/hydrolux/batch parses every numeric flag with them) ----
  // parse_number: a finite decimal number, the whole text or None; parse_integer: a whole number
  // within +-2^53, also in exponent form ("1e3"), or None. Exactly what the CLI's flags accept.
  m.def("parse_number", [](const std::string& text) { return hydrolux::parse::number(text); }, py::arg("text"));
  m.def("parse_integer", [](const std::string& text) { return hydrolux::parse::integer(text); }, py::arg("text"));
  // parse_pair: two numbers joined by `separator` ("1:2" with ':'), as a tuple, or None (parse::pair:
  // what the CLI's span flags, e.g. hydrolux lee --radius-um A:B, accept).
  m.def(
      "parse_pair",
      [](const std::string& text, char separator) -> std::optional<std::pair<double, double>> {
        const auto p = hydrolux::parse::pair(text, separator);
        if (!p) return std::nullopt;
        return std::pair<double, double>{(*p)[0], (*p)[1]};
      },
      py::arg("text"), py::arg("separator"));
  // The largest seed every door accepts (rain::kMaxSeed, 2^53).
  m.attr("kMaxSeed") = py::int_(hydrolux::rain::kMaxSeed);
  // The files of one run declared as the CLI declares them (io::FileSet): each input must be a regular
  // file; each planned output must not be an input or another output (through links too), a folder or a
  // device. OSError (the library's IoError) naming both files otherwise. Pairs are (label, path).
  m.def(
      "check_files",
      [](const std::vector<std::pair<std::string, std::string>>& inputs,
         const std::vector<std::pair<std::string, std::string>>& outputs) {
        hydrolux::io::FileSet files;
        for (const auto& [label, path] : inputs) files.input(label, path);
        for (const auto& [label, path] : outputs) files.planned_output(label, path);
      },
      py::arg("inputs"), py::arg("outputs"));
  // A value as an error message shows it (short, never an array's contents): the bindings' own words.
  m.def("describe", [](py::handle v) { return describe(v); }, py::arg("value"));
  // A text as hydrolux prints it in a message: one line that cannot drive the terminal.
  m.def("printable", [](const std::string& text) { return hydrolux::printable(text); }, py::arg("text"));
  // The memory this process can still expect to get, in bytes (core/memory.hpp).
  m.def("available_memory_bytes", [] { return hydrolux::available_memory_bytes(); });
  // ---- end batch ----

  // A job's declared parameters (hydrolux/jobs.hpp), the one table every door reads: the Python
  // functions' keywords and signatures, the batch jobs' argparse options, the docs' reference.
  m.def("params", &params_of, py::arg("job"));
  // The library's one refusal of a parameter given where the run leaves it unused (ParamUse::report_unused,
  // by the table's conditions), in the batch jobs' words (flags): `given` maps names to the values as
  // written, `held` lists the states the run is in ("video", "depth_dir"). ValueError "--crf 20: ...".
  m.def(
      "report_unused",
      [](const std::string& job, const std::map<std::string, std::string>& given, const std::vector<std::string>& held) {
        ParamUse use(Door::cli);
        for (const auto& info : hydrolux::job_spec(job).params) {
          const auto it = given.find(std::string(info.param->name));
          if (it == given.end()) use.declare(*info.param);
          else use.give(*info.param, info.param->kind == ParamKind::flag ? std::string() : it->second);
        }
        for (const auto& state : held) use.hold(state);
        use.report_unused();
      },
      py::arg("job"), py::arg("given"), py::arg("held"));
  // The warning for a deprecated spelling `old` of `now` (a quantity in `unit`), in the library's words
  // (Param::deprecation_warning): the keywords and the batch flags say it as the CLI does.
  m.def(
      "deprecation_warning",
      [](const std::string& old, const std::string& now, const std::string& unit) {
        Param p;
        p.unit = unit;
        return p.deprecation_warning(old, now);
      },
      py::arg("old"), py::arg("now"), py::arg("unit"));
  // A folder of frames as a sequence (io/frames.hpp): the frames, their outputs and depth maps, the
  // entries skipped, the folders checked; one definition with hydrolux rain --input-dir.
  m.def(
      "plan_frame_folder",
      [](const std::string& input_dir, const std::string& output_dir, std::optional<std::string> mask_dir,
         std::optional<std::string> depth_dir) {
        const auto plan = hydrolux::io::plan_frame_folder({input_dir, output_dir, mask_dir, depth_dir});
        // Names as Python holds the file system's (os.fsdecode: a byte that is not UTF-8 as a surrogate
        // escape), so that a frame named so is planned, read and written as the CLI does it.
        const auto fs_text = [](const std::string& bytes) {
          PyObject* o = PyUnicode_DecodeFSDefaultAndSize(bytes.data(), py::ssize_t(bytes.size()));
          if (!o) throw py::error_already_set();
          return py::reinterpret_steal<py::str>(o);
        };
        const auto names = [&](const std::vector<std::filesystem::path>& v) {
          py::list out;
          for (const auto& p : v) out.append(fs_text(p.filename().string()));
          return out;
        };
        py::dict d;
        d["frames"] = names(plan.frames), d["outputs"] = names(plan.outputs), d["depth_maps"] = names(plan.depth_maps);
        py::list skipped;
        for (const auto& k : plan.skipped) skipped.append(fs_text(k));
        d["skipped"] = skipped;
        d["skipped_warning"] = fs_text(plan.skipped_warning(input_dir));
        return d;
      },
      py::arg("input_dir"), py::arg("output_dir"), py::arg("mask_dir") = py::none(),
      py::arg("depth_dir") = py::none());
  m.def("jobs", [] {
    py::list out;
    for (const auto& j : hydrolux::job_specs()) out.append(std::string(j.name));
    return out;
  });
  // A job's command, one-line summary and the Python calls that take its parameters (the docs' tables).
  m.def(
      "job_info",
      [](const std::string& job) {
        const auto& j = hydrolux::job_spec(job);
        py::dict d;
        d["name"] = std::string(j.name), d["command"] = std::string(j.command);
        d["summary"] = std::string(j.summary), d["python"] = std::string(j.python);
        return d;
      },
      py::arg("job"));
}

}  // namespace hydrolux::py_bind
