#pragma once
// A float image: linear, scene-referred values, interleaved channels, row 0 at the top.
#include <cstddef>
#include <string>
#include <vector>

namespace hydrolux {

struct Image {
  int width = 0;
  int height = 0;
  int channels = 0;
  std::vector<float> pixels;  // width * height * channels values
  // Channel names for EXR ("R", "G", "B", "XYZ.X", ...); empty: R, G, B, A by position.
  std::vector<std::string> channel_names;
  // The values are data, not colour (a coverage mask): an 8- or 16-bit file holds them linearly
  // (a PNG with gAMA 1.0 and no sRGB chunk), every channel as it is, instead of through the sRGB
  // curve (data has 1 or 3 channels: a PNG's alpha would be read back associated). Set by
  // io::coverage_for_encoding; a decoded image never has it (io::DecodedImage::linear says what the
  // file declared), so an image made from an input does not inherit it.
  bool non_colour = false;

  Image() = default;
  Image(int w, int h, int c) : width(w), height(h), channels(c), pixels(std::size_t(w) * h * c, 0.f) {}

  float& at(int x, int y, int c) { return pixels[(std::size_t(y) * width + x) * channels + c]; }
  float at(int x, int y, int c) const { return pixels[(std::size_t(y) * width + x) * channels + c]; }
};

}  // namespace hydrolux
