#include "hydrolux/io/frame_paths.hpp"

namespace hydrolux::io {

std::vector<FramePathParam> frame_path_params(const EffectTraits& traits) {
  const FramePathWords& w = traits.words;
  const auto text = [](std::string_view common, std::string_view own) { return std::string(common) + std::string(own); };
  std::vector<FramePathParam> out = {
      {"--image", &FramePaths::image, text("Input photograph (PNG, JPEG, EXR, TIFF, ...)", w.image)},
      {"--input-dir", &FramePaths::input_dir, text("A folder of frames in name order", w.folder)},
      {"--video", &FramePaths::video, text("Input video (MP4, MOV, MKV, ...); frame rate and count are kept", w.video)},
      {"-o,--output", &FramePaths::output, "Output: .png/.exr with --image, .mp4/.mov/.mkv with --video"},
      {"--output-dir", &FramePaths::output_dir, "Output folder for --input-dir (created; never the input folder)"}};
  if (traits.depth) {
    out.push_back({"--depth", &FramePaths::depth,
                   "Depth map for --image: camera z in metres (EXR), or a 16-bit PNG times --depth-scale-m; 0/inf = sky"});
    out.push_back({"--depth-dir", &FramePaths::depth_dir,
                   "Depth maps for --input-dir: each frame's stem as .exr or .png (as --depth)"});
  }
  out.push_back({"--mask-out", &FramePaths::mask_out, std::string(w.mask)});
  out.push_back({"--mask-dir", &FramePaths::mask_dir, "Folder for the masks of --input-dir (same names as the frames)"});
  if (traits.layer)
    out.push_back({"--layer-out", &FramePaths::layer_out, "The rain layer for --image as a premultiplied RGBA .exr (linear)"});
  out.push_back({"--stats-json", &FramePaths::stats_json, std::string(w.stats)});
  return out;
}

}  // namespace hydrolux::io
