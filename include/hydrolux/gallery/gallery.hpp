#pragma once
// The gallery: `hydrolux gallery` (and `make demo`) renders every figure hydrolux can make without
// input files, plus an index.html that shows them with captions. Each capability adds its figures
// here.
#include <filesystem>
#include <string>
#include <vector>

#include "hydrolux/core/progress.hpp"

namespace hydrolux::gallery {

struct Figure {
  std::string file;     // file name inside the gallery directory
  std::string title;
  std::string caption;  // HTML-safe plain text
};

// Writes every figure and index.html into `dir` (created if needed); each file atomically.
// Returns the figures in gallery order. Throws hydrolux::Error (IoError on write failure).
std::vector<Figure> write_gallery(const std::filesystem::path& dir, const ProgressFn& progress = {});

}  // namespace hydrolux::gallery
