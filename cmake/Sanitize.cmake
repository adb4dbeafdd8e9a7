# The sanitizer build (make test-sanitize, make fuzz; build-sanitize/, clang-16):
#   HYDROLUX_SANITIZE  AddressSanitizer + UndefinedBehaviorSanitizer on all our code; any report
#                      stops the program (-fno-sanitize-recover), so a test that triggers one fails.
#   HYDROLUX_FUZZ      also libFuzzer's coverage instrumentation (-fsanitize=fuzzer-no-link) and the
#                      fuzz targets in fuzz/. One build serves both: the tests and the fuzzers share
#                      every object file, which saves a full build in CI.
# System libraries (OpenImageIO, oneTBB, Highway) stay uninstrumented.
option(HYDROLUX_SANITIZE "Build with AddressSanitizer and UndefinedBehaviorSanitizer" OFF)
option(HYDROLUX_FUZZ "Build the libFuzzer targets in fuzz/ (clang only; implies HYDROLUX_SANITIZE)" OFF)

if(HYDROLUX_FUZZ)
  set(HYDROLUX_SANITIZE ON)
  if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
    message(FATAL_ERROR "HYDROLUX_FUZZ needs clang (libFuzzer): configure with CXX=clang++-16")
  endif()
endif()

# Line tables only (-gline-tables-only): the reports' stack traces keep file and line; variables and
# types are left out, which saves about a sixth of the build (debug in a Debug build instead).
# The tests' own code (tests/CMakeLists.txt) is compiled at -O0 (but for the physics tests whose samplers
# and quadratures run in the test itself) and without the fuzzers' coverage:
# it drives the library and the CLI, which are what the sanitizers and the fuzzers are for, and it is
# half the build's objects (about 2.5x faster to compile at -O0 than at -O1 under the sanitizers).
if(HYDROLUX_SANITIZE)
  set(HYDROLUX_SANITIZER_FLAGS -fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer)
  add_compile_options(${HYDROLUX_SANITIZER_FLAGS} -gline-tables-only)
  add_link_options(${HYDROLUX_SANITIZER_FLAGS})
  if(HYDROLUX_FUZZ)
    set(HYDROLUX_FUZZ_COVERAGE_FLAGS -fsanitize=fuzzer-no-link)
    add_compile_options(${HYDROLUX_FUZZ_COVERAGE_FLAGS})
  endif()
endif()
