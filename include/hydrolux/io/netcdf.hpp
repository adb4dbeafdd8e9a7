#pragma once
// NetCDF-4 files of a Dataset (core/dataset.hpp), through the netCDF C library (Unidata, Debian's
// libnetcdf), built in memory: the bytes go to the caller's output (io::OutputFile, written whole or
// not at all) like every other file hydrolux writes. xarray.open_dataset and ncdump read them.
//
// libnetcdf brings ~45 shared libraries (HDF5, curl, ...) that every process would load at start:
// the CLI loads them with libhydrolux_netcdf_plugin.so beside its executable (netcdf_api() below), as
// it does its image and video plugins, only when a command writes NetCDF. Tests link the object
// library hydrolux_netcdf and call hydrolux_netcdf_api_v1() directly.
#include <string>
#include <string_view>

#include "hydrolux/core/dataset.hpp"

namespace hydrolux::io {

struct NetcdfApi {
  // The bytes of a NetCDF-4 (HDF5-based) file holding `ds`: its dimensions, its variables as NetCDF
  // doubles, floats, ints or strings, numeric arrays deflated (level 1, shuffled) and stored without
  // fill values, text attributes as NC_CHAR, numbers as doubles or 64-bit integers. ds.check()
  // first; Error on any failure of the library (with its message).
  std::string (*encode)(const Dataset& ds);
  // A NetCDF file's content read back from its bytes (netCDF-3 or netCDF-4 files of double, float,
  // int, short, byte or string variables): what encode wrote, for tests and checks. Error naming
  // what could not be read.
  Dataset (*decode)(std::string_view bytes);
  // The netCDF C library's version text (nc_inq_libvers).
  std::string (*library_version)();
};

inline constexpr const char* kNetcdfPluginSymbol = "hydrolux_netcdf_api_v1";
inline constexpr const char* kNetcdfPluginFile = "libhydrolux_netcdf_plugin.so";

// Loads the plugin (once; thread-safe) from the directory of the running executable (io/plugin.hpp).
// Throws hydrolux::Error naming the file and the loader's reason if it cannot.
const NetcdfApi& netcdf_api();

}  // namespace hydrolux::io

// The implementation itself, for code that links the object library hydrolux_netcdf instead of
// loading the plugin.
extern "C" const hydrolux::io::NetcdfApi* hydrolux_netcdf_api_v1();
