#pragma once
// A folder of frames as a sequence: which entries are frames, in which order, what each one's
// output and depth map are called, and the guards that keep a run's outputs off its inputs. One
// definition for every door that renders a folder (hydrolux rain --input-dir, the batch job).
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace hydrolux::io {

// The extensions of the image files a folder of frames may hold (lower case, with the dot).
inline constexpr const char* kFrameExtensions[] = {".png", ".jpg", ".jpeg", ".exr", ".tif",
                                                   ".tiff", ".hdr", ".ppm", ".pfm"};
// Whether `path` has one of them (in any case).
bool is_frame_file(const std::filesystem::path& path);

// The folders of a run over a folder of frames, as the user named them (messages quote them so).
struct FrameFolderRequest {
  std::string input_dir;
  std::string output_dir;
  std::optional<std::string> mask_dir;
  std::optional<std::string> depth_dir;
};

struct FrameFolder {
  std::vector<std::filesystem::path> frames;      // the frames' paths, in name order
  std::vector<std::filesystem::path> outputs;     // each frame's output name: its stem as .exr (EXR) or .png
  std::vector<std::filesystem::path> depth_maps;  // with a depth folder: each frame's map (stem.exr or .png)
  // Entries with a frame's name that are not regular files (a FIFO, a device, a folder, a dangling
  // link), "name (what)", left out; the caller says so (skipped_warning).
  std::vector<std::string> skipped;
  std::string skipped_warning(const std::string& input_dir) const;  // empty when none
};

// Lists and names a run's frames and checks its folders before any work: Error naming the flag
// (--input-dir, --output-dir, --mask-dir, --depth-dir) for a folder that is not one, no frames,
// two frames with one output name, a frame without a depth map, or an output folder that is the
// input folder, the depth folder, or (masks) the output folder.
FrameFolder plan_frame_folder(const FrameFolderRequest& request);

class FileSet;
// Declares in `files` every file of a run over `plan`, before any work: its frames and depth maps
// read, each frame's output in request.output_dir and (with request.mask_dir) its mask planned.
void declare_frame_folder(FileSet& files, const FrameFolder& plan, const FrameFolderRequest& request);
// Makes the output and mask folders; IoError naming the flag.
void create_output_folders(const FrameFolderRequest& request);

}  // namespace hydrolux::io
