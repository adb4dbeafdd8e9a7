# Every dependency is a Debian 12 package installed by scripts/install-deps.
find_package(PkgConfig REQUIRED)
# {fmt} 9.1 (libfmt-dev), used header-only: Debian ships its compiled part only as libfmt.so, which
# would cost every CLI start a library load and bring the shared libstdc++ back into a CLI linked
# with a static one (tools/hydrolux/CMakeLists.txt). The package's own fmt::fmt-header-only target
# (FMT_HEADER_ONLY: the same code, compiled into each user) stands in for fmt::fmt everywhere.
find_package(fmt REQUIRED)
add_library(hydrolux_fmt INTERFACE)
target_link_libraries(hydrolux_fmt INTERFACE fmt::fmt-header-only)
find_package(CLI11 REQUIRED)
find_package(nlohmann_json REQUIRED)
find_package(glm REQUIRED)
find_package(TBB REQUIRED)   # oneTBB: parallel loops over angles, sizes, wavelengths
find_package(hwy REQUIRED)   # Google Highway: portable SIMD with runtime dispatch
# Highway's headers: hydrolux chooses the SIMD target itself (src/core/simd.cpp), because loading
# libhwy.so calibrates a timer in a static initialiser that costs ~3.5 ms per process. The library
# stays on the link line for builds with Highway's debug assertions (Debug, Sanitize), whose
# handler lives there; --as-needed drops it from Release binaries, which reference nothing in it
# (tests/cli/test_cli.cpp checks that the CLI does not load it).
add_library(hydrolux_highway_headers INTERFACE)
target_include_directories(hydrolux_highway_headers SYSTEM INTERFACE
  $<TARGET_PROPERTY:hwy::hwy,INTERFACE_INCLUDE_DIRECTORIES>)
target_link_libraries(hydrolux_highway_headers INTERFACE hwy::hwy)

# OpenImageIO 2.4's CMake config references tools and include dirs that Debian does not ship
# (see ../shared/TOOLCHAIN.md); its pkg-config file is clean, so use that.
pkg_check_modules(OIIO REQUIRED IMPORTED_TARGET GLOBAL OpenImageIO)

# The Python package: Debian's interpreter (/usr/bin/python3 sees Debian's numpy; a pyenv or other
# python3 first on PATH may not: ../shared/TOOLCHAIN.md), pybind11 from Debian.
if(HYDROLUX_BUILD_PYTHON)
  if(NOT DEFINED Python3_EXECUTABLE AND EXISTS /usr/bin/python3)
    set(Python3_EXECUTABLE /usr/bin/python3 CACHE FILEPATH "The Python the package is built for")
  endif()
  find_package(Python3 REQUIRED COMPONENTS Interpreter Development.Module)
  set(PYBIND11_FINDPYTHON ON)
  find_package(pybind11 CONFIG REQUIRED)
endif()

if(HYDROLUX_BUILD_TESTS)
  find_package(GTest REQUIRED)
endif()
if(HYDROLUX_BUILD_BENCH)
  find_package(benchmark REQUIRED)
endif()
