// Holds the test programs' precompiled headers (tests/CMakeLists.txt, HYDROLUX_PCH): the headers are
// compiled once for this target, and every test program reuses them.
