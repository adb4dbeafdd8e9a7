#pragma once
// The gallery: `hydrolux gallery` (and `make demo`) renders every figure hydrolux can make without
// input files, plus an index.html that shows them with captions. Each capability adds its figures
// here.
#include <filesystem>
#include <functional>
#include <string_view>
#include <string>
#include <vector>

#include "hydrolux/core/progress.hpp"

namespace hydrolux::gallery {

struct Figure {
  std::string file;     // file name inside the gallery directory
  std::string title;
  std::string caption;  // HTML-safe plain text
};

// Receives each file of the gallery: its name and its bytes.
using FigureSink = std::function<void(const std::string& name, std::string_view bytes)>;

// Renders every figure and then index.html, handing each to `sink` as it is made. Returns the
// figures in gallery order.
std::vector<Figure> render_gallery(const FigureSink& sink, const ProgressFn& progress = {});

// Writes the gallery into `dir` (parents created if needed) through an io::OutputDirectory: the
// figures go into a temporary folder beside it, which replaces `dir`'s figures only once all are
// made, so an interrupted run leaves `dir` as it was. Throws hydrolux::Error (IoError, IoFailure).
std::vector<Figure> write_gallery(const std::filesystem::path& dir, const ProgressFn& progress = {});

}  // namespace hydrolux::gallery
