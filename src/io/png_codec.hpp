#pragma once
// PNG files written, and the common ones read, with libdeflate: whole-buffer DEFLATE, about twice
// zlib's speed both ways on camera frames (BENCHMARKS.md, "Rain over a folder of frames"). Internal
// to the image library (image_io.cpp): callers use io::encode_image / io::decode_image.
//
// The writer takes every PNG hydrolux writes (8 or 16 bits, 1 to 4 channels). The reader takes the
// plain case a camera or a renderer writes, 8- or 16-bit grey or RGB without interlacing or
// transparency; anything else (palettes, alpha, low bit depths, Adam7, a bad checksum, a deflate
// stream that does not give exactly the rows) is left to OpenImageIO's reader, which then gives
// the image or its error as before.

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace hydrolux::io::png {

// Samples in PNG order (rows top to bottom, channels interleaved, 16-bit samples big-endian) as a
// PNG file with the sRGB, gAMA and cHRM chunks of an sRGB image or, with `linear` (data that is not
// colour: a coverage mask), a gAMA of 1.0 (100000) and no sRGB or cHRM chunk, which says that the
// codes are linear (declares_linear). `level`: 0 stores the rows
// unfiltered; 1-2 filter every row with Up; 3-9 choose each row's filter by the PNG
// specification's heuristic (the least sum of absolute differences); the level is libdeflate's.
std::string encode(const std::uint8_t* samples, int width, int height, int channels, int bits, int level,
                   bool linear = false);

// Whether a PNG declares its codes linear: a gAMA chunk of 1.0 (100000) before the image data and
// no sRGB or iCCP chunk (which would take precedence over gAMA). Every other PNG is read as sRGB.
// The file's chunk structure must have been walked already (png_structure_problem).
bool declares_linear(std::string_view file);

struct Header {
  int width = 0, height = 0, channels = 0, bits = 0;
  bool linear = false;  // declares_linear: the codes are linear, not sRGB
};

// The header of a PNG the fast reader takes, or nullopt. The file's chunk structure must have been
// walked already (image_format.cpp's png_structure_problem).
std::optional<Header> plain_header(std::string_view file);

// The unfiltered samples (height rows of width * channels * bits / 8 bytes, no filter bytes) of a
// file plain_header took, or false (nothing to trust in `samples`) where a chunk's CRC, the
// deflate stream or a filter byte is bad, or the stream does not end with the last row.
bool read_samples(std::string_view file, const Header& h, std::vector<std::uint8_t>& samples);

}  // namespace hydrolux::io::png
