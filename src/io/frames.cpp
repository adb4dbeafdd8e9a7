#include "hydrolux/io/frames.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <map>
#include <utility>

#include "hydrolux/core/error.hpp"
#include "hydrolux/io/files.hpp"

namespace hydrolux::io {

namespace fs = std::filesystem;

namespace {

std::string joined(const std::vector<std::string>& items) {
  std::string list;
  for (const auto& k : items) list += (list.empty() ? "" : ", ") + k;
  return list;
}

// What an entry is when it is not a regular file (through links).
const char* not_regular_kind(const fs::file_status& st) {
  return !fs::exists(st)                                        ? "dangling link"
         : fs::is_directory(st)                                 ? "folder"
         : fs::is_fifo(st)                                      ? "FIFO"
         : fs::is_socket(st)                                    ? "socket"
         : fs::is_block_file(st) || fs::is_character_file(st) ? "device"
                                                                : "not a regular file";
}

}  // namespace

bool is_frame_file(const fs::path& path) {
  const std::string e = lower_extension(path);
  return std::any_of(std::begin(kFrameExtensions), std::end(kFrameExtensions), [&](const char* x) { return e == x; });
}

std::string FrameFolder::skipped_warning(const std::string& input_dir) const {
  if (skipped.empty()) return {};
  return fmt::format("--input-dir {}: skipped {} entr{} that {} not regular files: {}", input_dir, skipped.size(),
                     skipped.size() == 1 ? "y" : "ies", skipped.size() == 1 ? "is" : "are", joined(skipped));
}

FrameFolder plan_frame_folder(const FrameFolderRequest& r) {
  FrameFolder plan;
  const fs::path in_dir(r.input_dir);
  std::error_code ec;
  if (!fs::is_directory(in_dir, ec)) throw Error(fmt::format("--input-dir {}: not a folder", r.input_dir));
  for (const auto& e : fs::directory_iterator(in_dir, ec)) {
    const std::string name = e.path().filename().string();
    if (!is_frame_file(e.path()) || name.front() == '.') continue;
    std::error_code kind_ec;
    const fs::file_status st = fs::status(e.path(), kind_ec);
    if (fs::is_regular_file(st))
      plan.frames.push_back(e.path());
    else
      plan.skipped.push_back(fmt::format("{} ({})", name, not_regular_kind(st)));
  }
  if (ec) throw Error(fmt::format("--input-dir {}: cannot list: {}", r.input_dir, ec.message()));
  std::sort(plan.frames.begin(), plan.frames.end());
  std::sort(plan.skipped.begin(), plan.skipped.end());
  if (plan.frames.empty())
    throw Error(fmt::format("--input-dir {}: no image files (png, jpg, exr, tif, hdr, ppm, pfm)", r.input_dir));

  // Each frame's output name (its own, as .exr or .png); two frames may not share one. Frames of a
  // high-dynamic-range format (EXR, Radiance HDR, PFM: float light, possibly above 1) stay floats in an
  // EXR; the others (8/16-bit codes) become PNGs.
  std::map<fs::path, fs::path> seen;
  for (const auto& f : plan.frames) {
    fs::path name = f.filename();
    const std::string ext = lower_extension(f);
    name.replace_extension(ext == ".exr" || ext == ".hdr" || ext == ".pfm" ? ".exr" : ".png");
    const auto [it, fresh] = seen.emplace(name, f.filename());
    if (!fresh)
      throw Error(fmt::format("--input-dir {}: {} and {} would both be written as {}", r.input_dir,
                              it->second.string(), f.filename().string(), name.string()));
    plan.outputs.push_back(name);
  }
  // Each frame's depth map, of the frame's stem as .exr or .png, found before any work.
  if (r.depth_dir) {
    if (!fs::is_directory(*r.depth_dir, ec)) throw Error(fmt::format("--depth-dir {}: not a folder", *r.depth_dir));
    for (const auto& f : plan.frames) {
      fs::path found;
      for (const char* ext : {".exr", ".png"}) {
        const fs::path candidate = fs::path(*r.depth_dir) / (f.stem().string() + ext);
        if (!fs::exists(fs::symlink_status(candidate, ec))) continue;
        // Two maps for one frame: which one is meant cannot be guessed.
        if (!found.empty())
          throw Error(fmt::format("--depth-dir {}: both {} and {} are depth maps for {}; keep one", *r.depth_dir,
                                  found.filename().string(), candidate.filename().string(), f.filename().string()));
        found = candidate;
      }
      if (found.empty())
        throw Error(fmt::format("--depth-dir {}: no depth map for {} ({}.exr or {}.png)", *r.depth_dir,
                                f.filename().string(), f.stem().string(), f.stem().string()));
      plan.depth_maps.push_back(found);
    }
  }
  for (const auto& [flag, dir] : {std::pair<const char*, std::optional<std::string>>{"--output-dir", r.output_dir},
                                  {"--mask-dir", r.mask_dir}}) {
    if (!dir) continue;
    if (fs::exists(*dir, ec) && same_file(*dir, in_dir))
      throw Error(fmt::format("{} {}: is the input folder; the frames would replace their inputs", flag, *dir));
    if (r.depth_dir && fs::exists(*dir, ec) && same_file(*dir, *r.depth_dir))
      throw Error(fmt::format("{} {}: is --depth-dir; the outputs could replace depth maps", flag, *dir));
    if (fs::exists(*dir, ec) && !fs::is_directory(*dir, ec))
      throw Error(fmt::format("{} {}: exists and is not a folder", flag, *dir));
  }
  if (r.mask_dir && same_file(*r.mask_dir, r.output_dir))
    throw Error(fmt::format("--mask-dir {}: is --output-dir; masks and frames share names", *r.mask_dir));
  return plan;
}

void declare_frame_folder(FileSet& files, const FrameFolder& plan, const FrameFolderRequest& request) {
  for (const auto& f : plan.frames) files.input("--input-dir", f);
  for (const auto& d : plan.depth_maps) files.input("--depth-dir", d);
  for (const auto& n : plan.outputs) files.planned_output("--output-dir", fs::path(request.output_dir) / n);
  if (request.mask_dir)
    for (const auto& n : plan.outputs) files.planned_output("--mask-dir", fs::path(*request.mask_dir) / n);
}

void create_output_folders(const FrameFolderRequest& request) {
  for (const auto& [flag, dir] : {std::pair<const char*, std::optional<std::string>>{"--output-dir", request.output_dir},
                                  {"--mask-dir", request.mask_dir}}) {
    std::error_code ec;
    if (dir) fs::create_directories(*dir, ec);
    if (ec) throw IoError(fmt::format("{} {}: cannot create: {}", flag, *dir, ec.message()));
  }
}

}  // namespace hydrolux::io
