#include "hydrolux/rain/frame_paths.hpp"

#include <vector>

namespace hydrolux::rain {

namespace {

// How an effect words its files: the whole help of the paths whose text differs between effects.
struct Words {
  std::string_view image = "Input photograph (PNG, JPEG, EXR, TIFF, ...)";
  std::string_view folder = "A folder of frames in name order";
  std::string_view video = "Input video (MP4, MOV, MKV, ...); frame rate and count are kept";
  std::string_view mask;
  std::string_view stats;
};

// The rows of an effect: its words, whether it takes depth maps and whether a rain layer.
std::vector<Field<FramePaths>> rows(const Words& w, bool depth, bool layer) {
  constexpr std::string_view kFile = "FILE", kDir = "DIR", kGroup = "paths";
  const auto row = [&](std::string_view name, std::string_view flag, std::string_view what, std::string_view help) {
    Param p;
    p.name = name, p.flag = flag, p.group = kGroup, p.kind = ParamKind::path, p.help = help, p.words = what;
    return p;
  };
  std::vector<Field<FramePaths>> out = {
      {row("image", "--image", kFile, w.image), HYDROLUX_PARAM_PATH(image)},
      {row("input_dir", "--input-dir", kDir, w.folder), HYDROLUX_PARAM_PATH(input_dir)},
      {row("video", "--video", kFile, w.video), HYDROLUX_PARAM_PATH(video)},
      {row("output", "--output", kFile, "Output: .png/.exr with --image, .mp4/.mov/.mkv with --video"),
       HYDROLUX_PARAM_PATH(output)},
      {row("output_dir", "--output-dir", kDir, "Output folder for --input-dir (created; never the input folder)"),
       HYDROLUX_PARAM_PATH(output_dir)}};
  out[3].param.short_flag = "-o";
  if (depth) {
    out.push_back({row("depth", "--depth", kFile,
                       "Depth map for --image: camera z in metres (EXR), or a 16-bit PNG times --depth-scale-m; 0/inf = sky"),
                   HYDROLUX_PARAM_PATH(depth)});
    out.push_back({row("depth_dir", "--depth-dir", kDir,
                       "Depth maps for --input-dir: each frame's stem as .exr or .png (as --depth)"),
                   HYDROLUX_PARAM_PATH(depth_dir)});
  }
  out.push_back({row("mask_out", "--mask-out", kFile, w.mask), HYDROLUX_PARAM_PATH(mask_out)});
  out.push_back({row("mask_dir", "--mask-dir", kDir, "Folder for the masks of --input-dir (same names as the frames)"),
                 HYDROLUX_PARAM_PATH(mask_dir)});
  if (layer) {
    out.push_back({row("layer_out", "--layer-out", kFile,
                       "The rain layer for --image as a premultiplied RGBA .exr (linear)"),
                   HYDROLUX_PARAM_PATH(layer_out)});
    out.push_back({row("layer_dir", "--layer-dir", kDir,
                       "Folder for the rain layers of --input-dir, <stem>.exr, premultiplied RGBA (linear)"),
                   HYDROLUX_PARAM_PATH(layer_dir)});
  }
  out.push_back({row("stats_json", "--stats-json", kFile, w.stats), HYDROLUX_PARAM_PATH(stats_json)});
  return out;
}

}  // namespace

std::span<const Field<FramePaths>> rain_path_params() {
  static const auto table = rows(
      {.image = "Input photograph (PNG, JPEG, EXR, TIFF, ...), or 'builtin' for the built-in street scene",
       .folder = "A folder of frames in name order: one rain field across them",
       .mask = "The rain's alpha for --image: .png (16-bit linear) or .exr; rainy = clear (1 - alpha) + layer",
       .stats = "Parameters, seed, the field and per-frame statistics as JSON"},
      true, true);
  return table;
}

std::span<const Field<FramePaths>> fog_path_params() {
  static const auto table = rows(
      {.folder = "A folder of frames in name order (one sky colour, from the first)",
       .video = "Input video (MP4, MOV, MKV, ...); frame rate and count are kept, one sky colour from the first frame",
       .mask = "The fog's coverage 1 - t for --image: .png (16-bit linear) or .exr; foggy = clear t + sky (1 - t) + glow",
       .stats = "The fog's optics, the camera and per-frame statistics as JSON"},
      true, false);
  return table;
}

std::span<const Field<FramePaths>> lens_drops_path_params() {
  static const auto table = rows(
      {.folder = "A folder of frames in name order (frame k: the drops of --seed + k)",
       .video = "Input video (MP4, MOV, MKV, ...); frame rate and count are kept (frame k: the drops of --seed + k)",
       .mask = "The drops' defocused coverage for --image: .png (16-bit linear) or .exr; out = clean (1 - mask) + drops",
       .stats = "The drops' settings and per-frame statistics as JSON"},
      false, false);
  return table;
}

}  // namespace hydrolux::rain
