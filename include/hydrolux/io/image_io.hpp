#pragma once
// Image files through OpenImageIO. Two formats are written:
//   .exr  linear float (scene-referred), written as 32-bit float
//   .png  display-referred: the sRGB curve is applied and values are quantised to 8 or 16 bits
// Reading returns linear values: EXR as stored; 8/16-bit formats (PNG, JPEG, TIFF, ...) are
// assumed sRGB-encoded and decoded. Errors (missing or unreadable file, unknown extension) throw
// IoError with the path in the message.
#include <filesystem>

#include "hydrolux/core/image.hpp"

namespace hydrolux::io {

struct PngOptions {
  int bits = 8;  // 8 or 16
};

Image read_image(const std::filesystem::path& path);

// Writes by extension (.exr or .png), atomically (see files.hpp).
void write_image(const std::filesystem::path& path, const Image& image, PngOptions png = {});

}  // namespace hydrolux::io
