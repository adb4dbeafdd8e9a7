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

  Image() = default;
  Image(int w, int h, int c) : width(w), height(h), channels(c), pixels(std::size_t(w) * h * c, 0.f) {}

  float& at(int x, int y, int c) { return pixels[(std::size_t(y) * width + x) * channels + c]; }
  float at(int x, int y, int c) const { return pixels[(std::size_t(y) * width + x) * channels + c]; }
};

}  // namespace hydrolux
