#include "hydrolux/io/npy.hpp"

#include <bit>
#include <cstdint>
#include <cstring>

#include "hydrolux/core/error.hpp"

namespace hydrolux::io {

std::string npy_header_f8(std::span<const std::size_t> shape) {
  if (shape.empty()) throw Error("npy_header_f8: an array needs at least one dimension");
  std::string dict = "{'descr': '<f8', 'fortran_order': False, 'shape': (";
  for (std::size_t i = 0; i < shape.size(); ++i) {
    dict += std::to_string(shape[i]);
    dict += (shape.size() == 1 || i + 1 < shape.size()) ? ", " : "";
  }
  if (shape.size() == 1) dict.pop_back();  // "(n,)" for one dimension
  dict += "), }";
  // Magic (6) + version (2) + header length (2) + dict + spaces + '\n', a multiple of 64.
  const std::size_t unpadded = 10 + dict.size() + 1;
  const std::size_t total = (unpadded + 63) / 64 * 64;
  dict.append(total - unpadded, ' ');
  dict += '\n';
  if (dict.size() > 65535) throw Error("npy_header_f8: too many dimensions for a version 1.0 header");
  std::string out = "\x93NUMPY";
  out += '\x01';
  out += '\x00';
  out += static_cast<char>(dict.size() & 0xff);
  out += static_cast<char>((dict.size() >> 8) & 0xff);
  out += dict;
  return out;
}

void append_f8_le(std::string& out, std::span<const double> values) {
  const std::size_t start = out.size();
  out.resize(start + 8 * values.size());
  char* p = out.data() + start;
  if constexpr (std::endian::native == std::endian::little) {
    std::memcpy(p, values.data(), 8 * values.size());
  } else {
    for (const double v : values) {
      const auto bits = std::bit_cast<std::uint64_t>(v);
      for (int b = 0; b < 8; ++b) *p++ = static_cast<char>((bits >> (8 * b)) & 0xff);
    }
  }
}

}  // namespace hydrolux::io
