#pragma once
// The gallery's figures, shared between the files that define them (internal to the gallery).
#include <filesystem>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "hydrolux/gallery/gallery.hpp"

namespace hydrolux::gallery::detail {

struct Entry {
  Entry() = default;
  Entry(Figure f, std::function<std::string()> svg) : figure(std::move(f)), render(std::move(svg)) {}

  Figure figure;
  std::function<std::string()> render;                          // SVG text, or
  std::function<void(const std::filesystem::path& file)> write;  // writes the file itself (images)
};

// The rain drop's figures (issue #4): rendered pictures, the exact tracer beside the model, the
// undistorted view, Beard & Chuang's shapes.
std::vector<Entry> drop_entries();

}  // namespace hydrolux::gallery::detail
