#pragma once
// NumPy's .npy format (version 1.0, numpy/lib/format.py and NEP 1): a 10-byte preamble, a Python
// dict literal naming the dtype, the order and the shape, padded with spaces and a newline so the
// data start on a 64-byte boundary, then the array's bytes in C order. hydrolux writes float64
// arrays ('<f8', little-endian), which numpy.load reads without copying.
#include <cstddef>
#include <span>
#include <string>

namespace hydrolux::io {

// The preamble and header of a C-order little-endian float64 array of `shape` (at least one
// dimension). The data, prod(shape) doubles, follow it.
std::string npy_header_f8(std::span<const std::size_t> shape);

// Appends `values` to `out` as little-endian float64 bytes (the .npy data), whatever the host's
// byte order.
void append_f8_le(std::string& out, std::span<const double> values);

}  // namespace hydrolux::io
