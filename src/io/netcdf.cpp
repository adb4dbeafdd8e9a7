// NetCDF-4 files in memory through the netCDF C library (nc_create_mem / nc_close_memio, and
// nc_open_mem to read them back): see hydrolux/io/netcdf.hpp. The object library hydrolux_netcdf,
// linked into the CLI's plugin libhydrolux_netcdf_plugin.so and into the tests.
#include "hydrolux/io/netcdf.hpp"

#include <fmt/format.h>
#include <netcdf.h>
#include <netcdf_mem.h>

#include <cstdlib>
#include <cstring>
#include <memory>
#include <mutex>
#include <vector>

#include "hydrolux/core/error.hpp"

namespace hydrolux::io {

namespace {

// The netCDF C library keeps global state and is not thread-safe: one call into it at a time.
std::mutex& library_mutex() {
  static std::mutex m;
  return m;
}

void check(int status, std::string_view what) {
  if (status != NC_NOERR) throw Error(fmt::format("NetCDF: {}: {}", what, nc_strerror(status)));
}

// Closes a file left open by an error.
struct OpenFile {
  int id = -1;
  ~OpenFile() {
    if (id >= 0) nc_close(id);
  }
};

void put_attribute(int file, int var, const Attribute& a) {
  if (const auto* s = std::get_if<std::string>(&a.value)) {
    check(nc_put_att_text(file, var, a.name.c_str(), s->size(), s->data()), "attribute " + a.name);
  } else if (const auto* d = std::get_if<std::vector<double>>(&a.value)) {
    check(nc_put_att_double(file, var, a.name.c_str(), NC_DOUBLE, d->size(), d->data()), "attribute " + a.name);
  } else {
    const auto& i = std::get<std::vector<std::int64_t>>(a.value);
    std::vector<long long> ll(i.begin(), i.end());
    check(nc_put_att_longlong(file, var, a.name.c_str(), NC_INT64, ll.size(), ll.data()), "attribute " + a.name);
  }
}

nc_type type_of(const VariableData& data) {
  switch (data.index()) {
    case 0: return NC_DOUBLE;
    case 1: return NC_FLOAT;
    case 2: return NC_INT;
    default: return NC_STRING;
  }
}

std::string encode(const Dataset& ds) {
  ds.check();
  std::lock_guard lock(library_mutex());
  OpenFile f;
  // The name is the HDF5 core driver's label only: nothing is written to disk.
  check(nc_create_mem("hydrolux.nc", NC_NETCDF4 | NC_CLOBBER, 1 << 16, &f.id), "creating the file in memory");
  std::vector<int> dim_ids;
  for (const auto& [name, size] : ds.dims) {
    int id = 0;
    check(nc_def_dim(f.id, name.c_str(), size, &id), "dimension " + name);
    dim_ids.push_back(id);
  }
  const auto dim_id = [&](const std::string& name) {
    for (std::size_t i = 0; i < ds.dims.size(); ++i)
      if (ds.dims[i].first == name) return dim_ids[i];
    return -1;  // ds.check() rules this out
  };
  std::vector<int> var_ids;
  for (const auto& v : ds.variables) {
    std::vector<int> dims;
    for (const auto& d : v.dims) dims.push_back(dim_id(d));
    int id = 0;
    const nc_type type = type_of(v.data);
    check(nc_def_var(f.id, v.name.c_str(), type, int(dims.size()), dims.data(), &id), "variable " + v.name);
    if (type != NC_STRING) {
      check(nc_def_var_fill(f.id, id, NC_NOFILL, nullptr), "variable " + v.name);
      if (!dims.empty()) check(nc_def_var_deflate(f.id, id, 1, 1, 1), "compressing " + v.name);
    }
    for (const auto& a : v.attrs.items()) put_attribute(f.id, id, a);
    var_ids.push_back(id);
  }
  for (const auto& a : ds.attrs.items()) put_attribute(f.id, NC_GLOBAL, a);
  check(nc_enddef(f.id), "defining the file");
  for (std::size_t i = 0; i < ds.variables.size(); ++i) {
    const auto& v = ds.variables[i];
    const std::string what = "writing " + v.name;
    if (value_count(v.data) == 0) continue;
    if (const auto* d = std::get_if<std::vector<double>>(&v.data)) {
      check(nc_put_var_double(f.id, var_ids[i], d->data()), what);
    } else if (const auto* fl = std::get_if<std::vector<float>>(&v.data)) {
      check(nc_put_var_float(f.id, var_ids[i], fl->data()), what);
    } else if (const auto* in = std::get_if<std::vector<std::int32_t>>(&v.data)) {
      check(nc_put_var_int(f.id, var_ids[i], in->data()), what);
    } else {
      const auto& s = std::get<std::vector<std::string>>(v.data);
      std::vector<const char*> p;
      for (const auto& e : s) p.push_back(e.c_str());
      check(nc_put_var_string(f.id, var_ids[i], p.data()), what);
    }
  }
  NC_memio memio{};
  const int id = f.id;
  f.id = -1;  // nc_close_memio closes it, whatever it returns
  check(nc_close_memio(id, &memio), "closing the file");
  std::unique_ptr<void, decltype(&std::free)> owned(memio.memory, &std::free);
  return std::string(static_cast<const char*>(memio.memory), memio.size);
}

AttributeValue read_attribute(int file, int var, const char* name) {
  nc_type type = 0;
  std::size_t len = 0;
  check(nc_inq_att(file, var, name, &type, &len), std::string("attribute ") + name);
  if (type == NC_CHAR) {
    std::string s(len, '\0');
    if (len) check(nc_get_att_text(file, var, name, s.data()), std::string("attribute ") + name);
    return s;
  }
  if (type == NC_STRING) {
    std::vector<char*> p(len);
    check(nc_get_att_string(file, var, name, p.data()), std::string("attribute ") + name);
    std::string s = len ? std::string(p[0] ? p[0] : "") : std::string();
    nc_free_string(len, p.data());
    return s;
  }
  if (type == NC_INT64 || type == NC_UINT64 || type == NC_INT || type == NC_UINT || type == NC_SHORT ||
      type == NC_USHORT || type == NC_BYTE || type == NC_UBYTE) {
    std::vector<long long> v(len);
    check(nc_get_att_longlong(file, var, name, v.data()), std::string("attribute ") + name);
    return std::vector<std::int64_t>(v.begin(), v.end());
  }
  std::vector<double> v(len);
  check(nc_get_att_double(file, var, name, v.data()), std::string("attribute ") + name);
  return v;
}

Attributes read_attributes(int file, int var, int count) {
  Attributes out;
  for (int i = 0; i < count; ++i) {
    char name[NC_MAX_NAME + 1] = {};
    check(nc_inq_attname(file, var, i, name), "attribute name");
    out.set(name, read_attribute(file, var, name));
  }
  return out;
}

Dataset decode(std::string_view bytes) {
  std::lock_guard lock(library_mutex());
  // nc_open_mem does not write to the memory with NC_NOWRITE, but takes a non-const pointer.
  std::string copy(bytes);
  OpenFile f;
  check(nc_open_mem("hydrolux.nc", NC_NOWRITE, copy.size(), copy.data(), &f.id), "opening");
  int ndims = 0, nvars = 0, natts = 0, unlimited = 0;
  check(nc_inq(f.id, &ndims, &nvars, &natts, &unlimited), "reading the header");
  Dataset ds;
  std::vector<int> dim_ids(static_cast<std::size_t>(ndims));
  check(nc_inq_dimids(f.id, &ndims, dim_ids.data(), 0), "dimensions");
  std::vector<std::string> dim_names;
  for (int id : dim_ids) {
    char name[NC_MAX_NAME + 1] = {};
    std::size_t len = 0;
    check(nc_inq_dim(f.id, id, name, &len), "dimension");
    ds.dim(name, len);
    dim_names.emplace_back(name);
  }
  const auto name_of = [&](int id) {
    for (std::size_t i = 0; i < dim_ids.size(); ++i)
      if (dim_ids[i] == id) return dim_names[i];
    throw Error("NetCDF: a variable over an unknown dimension");
  };
  for (int v = 0; v < nvars; ++v) {
    char name[NC_MAX_NAME + 1] = {};
    nc_type type = 0;
    int nd = 0, na = 0;
    check(nc_inq_var(f.id, v, name, &type, &nd, nullptr, &na), "variable");
    std::vector<int> ids(static_cast<std::size_t>(nd));
    check(nc_inq_vardimid(f.id, v, ids.data()), std::string("variable ") + name);
    std::vector<std::string> dims;
    std::size_t n = 1;
    for (int id : ids) {
      dims.push_back(name_of(id));
      std::size_t len = 0;
      check(nc_inq_dimlen(f.id, id, &len), "dimension");
      n *= len;
    }
    const std::string what = std::string("reading ") + name;
    VariableData data;
    if (type == NC_DOUBLE) {
      std::vector<double> d(n);
      if (n) check(nc_get_var_double(f.id, v, d.data()), what);
      data = std::move(d);
    } else if (type == NC_FLOAT) {
      std::vector<float> d(n);
      if (n) check(nc_get_var_float(f.id, v, d.data()), what);
      data = std::move(d);
    } else if (type == NC_INT || type == NC_SHORT || type == NC_BYTE) {
      std::vector<std::int32_t> d(n);
      if (n) check(nc_get_var_int(f.id, v, d.data()), what);
      data = std::move(d);
    } else if (type == NC_STRING) {
      std::vector<char*> p(n);
      if (n) check(nc_get_var_string(f.id, v, p.data()), what);
      std::vector<std::string> d;
      for (char* s : p) d.emplace_back(s ? s : "");
      if (n) nc_free_string(n, p.data());
      data = std::move(d);
    } else {
      throw Error(fmt::format("NetCDF: variable {} is of a type this reader does not take ({})", name, int(type)));
    }
    Variable& var = ds.add(name, std::move(dims), std::move(data));
    var.attrs = read_attributes(f.id, v, na);
  }
  ds.attrs = read_attributes(f.id, NC_GLOBAL, natts);
  return ds;
}

std::string library_version() { return nc_inq_libvers(); }

}  // namespace

}  // namespace hydrolux::io

extern "C" __attribute__((visibility("default"))) const hydrolux::io::NetcdfApi* hydrolux_netcdf_api_v1() {
  static const hydrolux::io::NetcdfApi api{&hydrolux::io::encode, &hydrolux::io::decode,
                                           &hydrolux::io::library_version};
  return &api;
}
