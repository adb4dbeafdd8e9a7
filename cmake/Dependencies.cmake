# Every dependency is a Debian 12 package installed by scripts/install-deps.
find_package(PkgConfig REQUIRED)
# {fmt} 9.1 (libfmt-dev): Debian ships its compiled part only as libfmt.so, which would cost every
# CLI start a library load and bring the shared libstdc++ back into a CLI linked with a static one
# (tools/hydrolux/CMakeLists.txt). hydrolux_fmt is that part built here from the installed headers
# (cmake/fmt_compiled.cpp) as a static library, for every target that formats. FMT_SHARED stays
# defined for the users, as the package's shared target defines it: on ELF it only gives fmt's API
# default visibility, so every object compiles as it did against libfmt.so.
find_package(fmt REQUIRED)   # the headers (and the version check below)
if(NOT fmt_VERSION VERSION_GREATER_EQUAL 9 OR fmt_VERSION VERSION_GREATER_EQUAL 10)
  message(FATAL_ERROR "cmake/fmt_compiled.cpp is fmt 9's compiled part; found fmt ${fmt_VERSION}")
endif()
add_library(hydrolux_fmt STATIC ${CMAKE_CURRENT_LIST_DIR}/fmt_compiled.cpp)
target_include_directories(hydrolux_fmt SYSTEM PUBLIC
  $<TARGET_PROPERTY:fmt::fmt-header-only,INTERFACE_INCLUDE_DIRECTORIES>)
target_compile_definitions(hydrolux_fmt PUBLIC FMT_SHARED)
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
