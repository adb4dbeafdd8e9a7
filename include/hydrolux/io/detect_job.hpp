#pragma once
// hydrolux detect-rain and hydrolux rain-eval over files (rain/detect.hpp has the detector and the
// scores): a folder of frames in, one mask per frame out; folders of predicted and true masks in, the
// scores out as JSON. The CLI registers the declared paths and settings and calls these.
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "hydrolux/core/params.hpp"
#include "hydrolux/io/image_io.hpp"
#include "hydrolux/rain/detect.hpp"

namespace hydrolux::io {

struct DetectJob : rain::DetectPaths {
  rain::DetectSettings settings;
};

struct DetectHooks {
  ImageCodec codec;
  std::function<void(double, std::string_view)> progress;
};

struct DetectReport {
  std::vector<std::string> frames;  // the masks' names, in frame order
  // Pixels detected per frame: the method's masks, and per stage where written.
  std::vector<std::size_t> detected;
  std::size_t candidates = 0, photometric = 0, correlated = 0;  // summed over the frames
  int width = 0, height = 0;
};

// Reads every frame of input_dir (name order; io/frames.hpp's frame files), detects, and writes one mask
// per frame into output_dir as <stem>.png (8-bit, 255 where rain is detected, linear), with stages_dir
// the stages' masks as candidates/<stem>.png, photometric/<stem>.png, correlated/<stem>.png. Both folders
// are written whole at the end or not at all (files.hpp's OutputDirectory). Error naming the flag for a
// folder that is the input folder, too few frames, frames of different sizes, or frames that would not fit
// in memory (the estimate and what is available).
DetectReport run_detect_job(const DetectJob& job, const DetectHooks& hooks);
std::string detect_summary(const DetectJob& job, const DetectReport& report);

struct RemoveJob : rain::RemovePaths {
  rain::RemoveSettings settings;
  int png_compression = kDefaultPngCompression;
};

struct RemoveReport {
  std::size_t frames = 0;
  std::size_t replaced = 0;  // pixels changed (garg-nayar: the masks' pixels that had a usable neighbour)
  int width = 0, height = 0;
};

// Reads the frames of input_dir in name order (and each frame's mask or layer of its stem), removes the rain
// by settings.method and writes each frame to output_dir under the name hydrolux rain gives its output
// (<stem>.png, or .exr for EXR, HDR and PFM frames); the folder is written whole at the end or not at all.
// Error naming the flag for a missing mask or layer, a folder that is the input folder, too few frames,
// frames or masks of different sizes, a method without the folder it needs (--mask-dir for garg-nayar,
// --layer-dir for oracle) or a folder the method does not read.
RemoveReport run_remove_job(const RemoveJob& job, const DetectHooks& hooks);
std::string remove_summary(const RemoveJob& job, const RemoveReport& report);

struct EvalJob : rain::EvalPaths {
  rain::EvalSettings settings;
  rain::DetectSettings detector;  // the PR curves' detectors (with --input-dir): all but method and c
};


struct EvalReport {
  std::vector<std::pair<std::string, rain::Confusion>> frames;  // by the masks' names, in name order
  rain::Confusion overall;
  // With --clean-dir and --derained-dir: each scored frame's removal error, and overall.
  std::vector<rain::RemovalError> removal;
  std::optional<rain::RemovalError> removal_overall;
  // With --input-dir: per detector ("garg-nayar", "candidates", "median") its curve over kPrThresholds.
  std::vector<std::pair<std::string, std::vector<rain::PrPoint>>> pr;
  std::vector<std::string> unmatched;  // predicted masks with no true mask of their name
};

// Scores each mask of pred_dir (nonzero: rain) against the true mask of its name in truth_dir (the rain's
// alpha, as hydrolux rain --mask-dir writes it). Error naming the flag for a folder without masks, no
// name in common, or masks of different sizes.
EvalReport run_eval_job(const EvalJob& job, const ImageCodec& codec,
                        const std::function<void(double, std::string_view)>& progress = {});
// {"format": "hydrolux-rain-eval", "format_version": 1, "rain_alpha", "ignore_alpha", "overall": {"precision",
// "recall", "f1", "iou", "true_positive", "false_positive", "false_negative", "true_negative", "ignored"},
// "frames": [{"name", ...the same}], "unmatched": [...]}; undefined ratios as null. With the removal's frames,
// "psnr_in_mask" and "psnr_out_mask" (dB on the sRGB codes 0-255; null where undefined, a very large value
// as 1e308 where equal) overall and per frame. With --input-dir, "pr_curve": {"garg-nayar": [{"min_change_grey",
// "precision", "recall", "f1", "iou"}, ...], "candidates": ..., "median": ...}.
std::string eval_json(const EvalJob& job, const EvalReport& report);

}  // namespace hydrolux::io
