#pragma once
// Rain detection in a sequence of frames (hydrolux detect-rain; docs/rain-detection.md) after Garg &
// Nayar, "Detection and Removal of Rain from Videos" (CVPR 2004), and the scores of a detector's masks
// against the true ones (hydrolux rain-eval). Image processing only: the frames come in as grey levels,
// the masks go out as bytes; reading and writing files is io/detect_job.hpp's.
//
// The stages, each a mask per frame:
//   candidates   a pixel brighter than both neighbouring frames by at least c grey levels: a drop
//                passes a pixel within one frame's exposure (it crosses it in under 1.18 ms, and frames
//                are tens of ms apart), and a drop is brighter than what it hides (seed 000, Figure 7).
//   photometric  each connected streak of candidates (8-connected) whose change against its background,
//                fitted as dI = alpha - beta I_bg by least squares, has beta <= tau_max / T: a drop that
//                covers a pixel for tau of the exposure T changes it by tau (E_drop - E_bg), so the slope
//                is -tau / T (Garg & Nayar: beta <= 0.039 at T = 30 ms). Streaks whose background varies
//                too little (spread below 1 grey level) cannot be tested and are kept.
//   correlated   the pixels of the photometric mask whose spatio-temporal correlation (the mask's
//                autocorrelation at zero time lag, over a window of 11 x 11 pixels and 30 frames, lags up
//                to half the window) is elongated along the common direction of the rain: drops fall
//                nearly parallel, so the correlation of rain is a needle along their direction. The
//                needle's direction and elongation are the correlation's second moments' (hydrolux's
//                measure of the paper's needle map); a pixel is kept where the elongation reaches
//                min_elongation and the direction lies within max_direction_spread_deg of the frame's
//                dominant one (the elongation-weighted mean over the frame's pixels).
// Two baselines: the candidates alone, and a temporal median's residual (brighter than the median of
// the median_frames frames around by at least c).
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "hydrolux/core/image.hpp"
#include "hydrolux/core/params.hpp"
#include "hydrolux/core/progress.hpp"

namespace hydrolux::rain {

// Which detector: Garg & Nayar's three stages, their first alone, or the temporal median's residual.
enum class DetectMethod { garg_nayar = 0, candidates = 1, median = 2 };

struct DetectSettings {
  DetectMethod method = DetectMethod::garg_nayar;
  double min_change_grey = 3;          // c: grey levels of 255 (Garg & Nayar 2004)
  double exposure_s = 0.030;           // T: the frames' exposure time (Garg & Nayar's video: 30 ms)
  double drop_time_s = 1.18e-3;        // tau_max: the longest a drop covers a pixel (Garg & Nayar 2004)
  int window_px = 11;                  // the correlation's window, pixels a side (odd; Garg & Nayar 2004)
  int window_frames = 30;              // and frames (Garg & Nayar 2004)
  double min_elongation = 0.25;        // hydrolux's: (l1 - l2) / (l1 + l2) of the correlation's moments
  double max_direction_spread_deg = 20;  // hydrolux's: from the frame's dominant direction
  int median_frames = 5;               // the median baseline's frames (odd)
};

std::span<const Field<DetectSettings>> detect_params();
// beta's bound, tau_max / T.
double max_beta(const DetectSettings& s);
// Throws ParamError naming the field for a value out of its range or an even window.
void validate(const DetectSettings& s);

// A frame's grey levels, 0-255: Rec. 601 luma of the sRGB-encoded values (what a video's Y plane
// holds, the scale of Garg & Nayar's c), from a linear RGB (or one-channel) image.
struct GreyFrame {
  int width = 0, height = 0;
  std::vector<float> level;  // width * height, row-major
};
GreyFrame grey_levels(const Image& linear);
// Throws Error "<origin>: a non-finite value (nan) at pixel (x, y), channel c; ..." for the first NaN or
// infinity in row order: detection, removal and scores take finite light only (as hydrolux rain does).
void check_finite(const Image& image, std::string_view origin);

// One mask per frame: 1 where rain is detected, else 0; width * height bytes.
struct Mask {
  int width = 0, height = 0;
  std::vector<std::uint8_t> on;
  std::size_t count() const;
};

// Stage by stage (each a subset of the one before for Garg & Nayar; empty where the method has none).
struct Detection {
  std::vector<Mask> candidates, photometric, correlated;
  std::vector<Mask> result;  // the method's: correlated, candidates or the median's
};

// The stages for every frame of `frames` (all of one size; at least 3). The first and last frames
// have one neighbour and get empty masks (the median's window is moved inside the sequence instead, and it
// needs at least median_frames frames).
// Throws Error for frames of different sizes or fewer than 3.
Detection detect_rain(std::span<const GreyFrame> frames, const DetectSettings& s, const ProgressFn& progress = {});

// The candidates of frame n from its neighbours; the photometric test of those; the correlation test
// of frame n's photometric mask within `masks` (every frame's); the median residual of frame n. The
// steps of detect_rain, for tests and for a caller that streams.
Mask rain_candidates(const GreyFrame& previous, const GreyFrame& frame, const GreyFrame& next, double min_change);
Mask photometric_test(const Mask& candidates, const GreyFrame& previous, const GreyFrame& frame,
                      const GreyFrame& next, double max_beta);
Mask correlation_test(std::span<const Mask> masks, std::size_t n, const DetectSettings& s);
// The median's window: median_frames frames centred on n, moved inside the sequence at its ends.
Mask median_residual(std::span<const GreyFrame> frames, std::size_t n, int median_frames, double min_change);

// The correlation's needle at one pixel of frame n: its direction (degrees from the image's x axis
// toward +y, i.e. downward, in [0, 180)), its elongation in [0, 1] and its weight (the sum of the
// correlation over the lags). For tests and the docs.
struct Needle {
  double direction_deg = 0, elongation = 0, weight = 0;
};
Needle correlation_needle(std::span<const Mask> masks, std::size_t n, int x, int y, const DetectSettings& s);

// The files of hydrolux detect-rain and rain-eval, declared as path parameters (the CLI's flags, the docs);
// io/detect_job.hpp reads and writes them.
struct DetectPaths {
  std::string input_dir, output_dir;
  std::optional<std::string> stages_dir;
};
std::span<const Field<DetectPaths>> detect_path_params();
struct EvalPaths {
  std::string pred_dir, truth_dir;
  std::optional<std::string> clean_dir, derained_dir;  // with both: the removal's PSNR in and out of the rain
  std::optional<std::string> input_dir;   // the rainy frames: the detectors' PR curves over their threshold
  std::optional<std::string> plots_dir;   // scores.csv per frame; the PR curves as SVG and CSV
  std::optional<std::string> output;  // the JSON report, besides stdout with --json
};
std::span<const Field<EvalPaths>> eval_path_params();

// ---- removal (hydrolux remove-rain) ------------------------------------------------------------------

// garg-nayar: the detected pixels from the neighbouring frames (Garg & Nayar 2004); median: every pixel the
// temporal median of the frames around (no mask); oracle: the renderer's own rain layer inverted, the upper
// bound of any removal.
enum class RemoveMethod { garg_nayar = 0, median = 1, oracle = 2 };
struct RemoveSettings {
  RemoveMethod method = RemoveMethod::garg_nayar;
  int median_frames = 5;  // the median's frames around each frame (odd)
};
std::span<const Field<RemoveSettings>> remove_params();
void validate(const RemoveSettings& s);

struct RemovePaths {
  std::string input_dir, output_dir;
  std::optional<std::string> mask_dir, layer_dir;
};
std::span<const Field<RemovePaths>> remove_path_params();

// Frame `n` of `frames` (linear, of one size; `masks` one per frame, nonzero = rain) with each pixel of its
// mask replaced by the mean of frames n - 1 and n + 1, per channel; a neighbour flagged there in its own mask
// is replaced by the frame beyond it (n - 2, n + 2) where that is not flagged; a side with no usable frame is
// left out, and a pixel with none on either side is kept.
Image remove_from_neighbours(std::span<const Image> frames, std::span<const Mask> masks, std::size_t n);
// Frame n with every pixel the median of frames n - half .. n + half (half = median_frames / 2, the window
// moved inside the sequence at its ends), per channel.
Image temporal_median(std::span<const Image> frames, std::size_t n, int median_frames);
// The clear frame under a rain layer: rainy = clear (1 - alpha) + layer (premultiplied RGBA, alpha in its
// last channel), so clear = (rainy - layer) / (1 - alpha); where alpha is 1 (nothing of the scene left) the
// rainy pixel is kept. Error for sizes that differ or a layer without 4 channels.
Image invert_rain_layer(const Image& rainy, const Image& layer);

// ---- scores against the true masks (hydrolux rain-eval) ----------------------------------------------

// What counts as rain in a true mask: a pixel whose rain alpha reaches rain_alpha; pixels between
// ignore_alpha and rain_alpha are faint streaks, scored neither way.
struct EvalSettings {
  double rain_alpha = 0.05;    // hydrolux's: below it, 96% of rendered rain's pixels change by < 3 grey levels
  double ignore_alpha = 0.01;  // the rain renderer's --min-alpha default
};
std::span<const Field<EvalSettings>> eval_params();
// The detector's settings rain-eval takes for its PR curves: detect_params() from exposure_s on (the method
// and c are swept).
std::span<const Field<DetectSettings>> eval_detector_params();
void validate(const EvalSettings& s);

// Pixel counts of one frame or of many summed.
struct Confusion {
  std::uint64_t true_positive = 0, false_positive = 0, false_negative = 0, true_negative = 0, ignored = 0;
  Confusion& operator+=(const Confusion& o);
  // NaN where undefined (no predicted pixel for the precision, no true one for the recall).
  double precision() const;
  double recall() const;
  double f1() const;
  double iou() const;
};

// A removal's error against the clean frame, in and out of the true rain (alpha >= rain_alpha; out: below
// ignore_alpha, the faint streaks in neither), on the sRGB codes 0-255 of every colour channel.
struct RemovalError {
  double sum_squares_in = 0, sum_squares_out = 0;
  std::uint64_t values_in = 0, values_out = 0;
  RemovalError& operator+=(const RemovalError& o);
  // 10 log10(255^2 / mean square); +inf where equal, NaN where no value.
  double psnr_in() const;
  double psnr_out() const;
};
RemovalError removal_error(const Image& derained, const Image& clean, std::span<const float> true_alpha,
                           const EvalSettings& s);

// Predicted (nonzero: rain) against the true rain alpha (one value per pixel, in [0, 1]); the two of one
// size, else Error.
Confusion score_mask(std::span<const std::uint8_t> predicted, std::span<const float> true_alpha,
                     const EvalSettings& s);

// The precision-recall curve of a detector over its threshold c (min_change_grey): detect_rain at each of
// `thresholds` with the other settings of `s`, scored against the true alpha of every frame (one vector of
// width * height values per frame), summed over the frames.
struct PrPoint {
  double min_change_grey = 0;
  Confusion scores;
};
// The thresholds a curve takes by default, grey levels: from below Garg & Nayar's 3 to where only bright
// streaks pass.
inline constexpr double kPrThresholds[] = {1, 1.5, 2, 3, 4, 6, 8, 12, 16};
std::vector<PrPoint> pr_curve(std::span<const GreyFrame> frames, std::span<const std::vector<float>> true_alpha,
                              const DetectSettings& s, const EvalSettings& e, std::span<const double> thresholds,
                              const ProgressFn& progress = {});

}  // namespace hydrolux::rain
