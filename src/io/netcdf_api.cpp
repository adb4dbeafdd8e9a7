// Loading the NetCDF plugin: see hydrolux/io/netcdf.hpp. The implementation is netcdf.cpp, built
// apart (the object library hydrolux_netcdf) so that hydrolux_io does not link libnetcdf.
#include "hydrolux/io/netcdf.hpp"

#include "hydrolux/io/plugin.hpp"

namespace hydrolux::io {

const NetcdfApi& netcdf_api() {
  // A failed load throws and is retried on the next call.
  static const NetcdfApi& api =
      *reinterpret_cast<const NetcdfApi* (*)()>(plugin_entry(kNetcdfPluginFile, kNetcdfPluginSymbol, "NetCDF"))();
  return api;
}

}  // namespace hydrolux::io
