// hydrolux gallery: the main job; renders every figure hydrolux makes from built-in data.
#include <fmt/format.h>

#include <chrono>
#include <cstdio>
#include <memory>

#include "common.hpp"
#include "hydrolux/core/error.hpp"
#include "hydrolux/gallery/gallery.hpp"
#include "image_plugin.hpp"
#include "progress.hpp"

namespace hydrolux::cli {

namespace {
struct GalleryArgs {
  std::string out = "out/gallery";
  bool quiet = false;
};

int run_gallery(const GalleryArgs& a) {
  if (a.out.empty()) throw Error("-o/--out: the output directory must not be empty");
  // The figures go into a hidden folder beside the destination, which replaces the destination's
  // figures only when every one is made: a failed or cancelled run leaves it as it was.
  io::FileSet files;
  io::OutputDirectory& dir = files.output_directory("-o", a.out);
  const ImageApi& images = image_api();
  ProgressBar bar("gallery", a.quiet);
  const auto figures = images.render_gallery(
      [&](const std::string& name, std::string_view bytes) { dir.write(name, bytes); }, bar.callback());
  files.commit();
  bar.finish();
  for (const auto& f : figures) fmt::print("{}/{}\n", printable(a.out), f.file);
  fmt::print("{}/index.html  ({} figures)\n", printable(a.out), figures.size());
  return 0;
}
}  // namespace

Command add_gallery(CLI::App& app) {
  auto args = std::make_shared<GalleryArgs>();
  auto* sub = app.add_subcommand(
      "gallery",
      "Render the gallery (index.html and its figures) from built-in data; no input files needed.");
  sub->add_option("-o,--out", args->out,
                  "Output directory (created if missing; its figures are replaced only once all are made, other "
                  "files in it are kept)")
      ->capture_default_str();
  sub->add_flag("-q,--quiet", args->quiet, "No progress on stderr");
  return {sub, [args] { return run_gallery(*args); }, {}};
}

}  // namespace hydrolux::cli
