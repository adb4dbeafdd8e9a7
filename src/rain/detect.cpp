#include "hydrolux/rain/detect.hpp"

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include "hydrolux/color/srgb.hpp"
#include "hydrolux/core/error.hpp"
#include "hydrolux/core/shared_params.hpp"

namespace hydrolux::rain {

namespace {

using K = ParamKind;

constexpr std::size_t kSrgbKnots = 4096;

const Field<DetectSettings> kDetect[] = {
    {choice_param("method", "--method", "detector", "garg-nayar|candidates|median",
                  "garg-nayar: candidates, photometric test and spatio-temporal correlation (Garg & Nayar 2004); "
                  "candidates: the first stage alone; median: brighter than the temporal median by --min-change-grey"),
     HYDROLUX_PARAM_MEMBER(method)},
    {{"min_change_grey", "--min-change-grey", "detector", K::real, "grey levels", 0.5, 255,
      "c: a candidate is brighter than both neighbouring frames by at least this, grey levels of 255 "
      "(Garg & Nayar 2004: 3)"},
     HYDROLUX_PARAM_MEMBER(min_change_grey)},
    {{"exposure_s", "--exposure-s", "detector", K::real, "s", 1e-5, 10,
      "T: the frames' exposure time, s; the photometric test keeps streaks with beta <= --drop-time-s / T "
      "(Garg & Nayar 2004: 0.039 at 30 ms)"},
     HYDROLUX_PARAM_MEMBER(exposure_s)},
    {{"drop_time_s", "--drop-time-s", "detector", K::real, "s", 1e-5, 1,
      "tau_max: the longest a drop covers a pixel, s (Garg & Nayar 2004: 1.18 ms)"},
     HYDROLUX_PARAM_MEMBER(drop_time_s)},
    {{"window_px", "--window-px", "detector", K::integer, "px", 3, 63,
      "The spatio-temporal correlation's window, pixels a side, odd (Garg & Nayar 2004: 11)"},
     HYDROLUX_PARAM_MEMBER(window_px)},
    {{"window_frames", "--window-frames", "detector", K::integer, "frames", 1, 300,
      "The spatio-temporal correlation's window, frames (Garg & Nayar 2004: 30)"},
     HYDROLUX_PARAM_MEMBER(window_frames)},
    {{"min_elongation", "--min-elongation", "detector", K::real, "", 0, 1,
      "The least elongation (l1 - l2) / (l1 + l2) of a pixel's correlation to count as rain (hydrolux's value, "
      "docs/rain-detection.md)"},
     HYDROLUX_PARAM_MEMBER(min_elongation)},
    {{"max_direction_spread_deg", "--max-direction-spread-deg", "detector", K::real, "deg", 0, 90,
      "The most a pixel's correlation may point away from the frame's dominant direction, degrees (hydrolux's "
      "value, docs/rain-detection.md)"},
     HYDROLUX_PARAM_MEMBER(max_direction_spread_deg)},
    {{"median_frames", "--median-frames", "detector", K::integer, "frames", 3, 99,
      "The median baseline's frames around each frame, odd (--method median)"},
     HYDROLUX_PARAM_MEMBER(median_frames)},
};

const Field<RemoveSettings> kRemove[] = {
    {choice_param("method", "--method", "removal", "garg-nayar|median|oracle",
                  "garg-nayar: the masked pixels from the neighbouring frames (Garg & Nayar 2004; needs --mask-dir); "
                  "median: every pixel the temporal median of --median-frames frames; oracle: the rain layer inverted "
                  "(needs --layer-dir: hydrolux rain's)"),
     HYDROLUX_PARAM_MEMBER(method)},
    {{"median_frames", "--median-frames", "removal", K::integer, "frames", 3, 99,
      "The median's frames around each frame, odd (--method median)"},
     HYDROLUX_PARAM_MEMBER(median_frames)},
};

const Field<EvalSettings> kEval[] = {
    {{"rain_alpha", "--rain-alpha", "truth", K::real, "", 1e-4, 1,
      "A true mask's pixel is rain where the rain's alpha reaches this (hydrolux's value: below it, 96% of the pixels "
      "of rain rendered at 8 ms change by less than 3 grey levels, docs/rain-detection.md)"},
     HYDROLUX_PARAM_MEMBER(rain_alpha)},
    {{"ignore_alpha", "--ignore-alpha", "truth", K::real, "", 0, 1,
      "Pixels with alpha from this up to --rain-alpha are faint streaks, scored neither way (the rain renderer's "
      "--min-alpha default)"},
     HYDROLUX_PARAM_MEMBER(ignore_alpha)},
};

Param path_row(std::string_view name, std::string_view flag, std::string_view what, std::string_view help,
               std::string_view short_flag = {}) {
  Param p;
  p.name = name, p.flag = flag, p.group = "paths", p.kind = ParamKind::path, p.help = help, p.words = what;
  p.short_flag = short_flag;
  return p;
}

const std::vector<Field<DetectPaths>>& detect_paths() {
  static const std::vector<Field<DetectPaths>> rows = {
      {path_row("input_dir", "--input-dir", "DIR", "A folder of frames in name order (at least 3), e.g. hydrolux rain's"),
       HYDROLUX_PARAM_PATH(input_dir)},
      {path_row("output_dir", "--output-dir", "DIR",
                "Folder for one mask per frame, <stem>.png (8-bit, 255 = rain; created; never the input folder)"),
       HYDROLUX_PARAM_PATH(output_dir)},
      {path_row("stages_dir", "--stages-dir", "DIR",
                "Folder for each stage's masks: candidates/, photometric/, correlated/ (garg-nayar)"),
       HYDROLUX_PARAM_PATH(stages_dir)},
  };
  return rows;
}

const std::vector<Field<EvalPaths>>& eval_paths() {
  static const std::vector<Field<EvalPaths>> rows = {
      {path_row("pred_dir", "--pred-dir", "DIR", "The predicted masks, one per frame (nonzero = rain), e.g. detect-rain's"),
       HYDROLUX_PARAM_PATH(pred_dir)},
      {path_row("truth_dir", "--truth-dir", "DIR",
                "The true masks of the same names: the rain's alpha, as hydrolux rain --mask-dir writes it"),
       HYDROLUX_PARAM_PATH(truth_dir)},
      {path_row("clean_dir", "--clean-dir", "DIR",
                "The clean frames (the input of hydrolux rain), for the removal's PSNR with --derained-dir"),
       HYDROLUX_PARAM_PATH(clean_dir)},
      {path_row("derained_dir", "--derained-dir", "DIR", "The frames after removal (remove-rain's), named as the clean ones"),
       HYDROLUX_PARAM_PATH(derained_dir)},
      {path_row("input_dir", "--input-dir", "DIR",
                "The rainy frames the masks were detected in: with them, each detector's precision-recall curve over "
                "--min-change-grey (garg-nayar, candidates, median)"),
       HYDROLUX_PARAM_PATH(input_dir)},
      {path_row("plots_dir", "--plots-dir", "DIR", "Folder for the scores of every frame as scores.csv, and with --input-dir the PR curves as pr.svg and pr.csv"),
       HYDROLUX_PARAM_PATH(plots_dir)},
      {path_row("output", "--output", "FILE", "Write the JSON report here too (all or nothing)", "-o"),
       HYDROLUX_PARAM_PATH(output)},
  };
  return rows;
}

const std::vector<Field<RemovePaths>>& remove_paths() {
  static const std::vector<Field<RemovePaths>> rows = {
      {path_row("input_dir", "--input-dir", "DIR", "The rainy frames, in name order (at least 3)"),
       HYDROLUX_PARAM_PATH(input_dir)},
      {path_row("mask_dir", "--mask-dir", "DIR", "The rain's masks, named as the frames (detect-rain's; nonzero = rain)"),
       HYDROLUX_PARAM_PATH(mask_dir)},
      {path_row("layer_dir", "--layer-dir", "DIR",
                "The rain layers, <stem>.exr, for --method oracle (hydrolux rain --layer-dir)"),
       HYDROLUX_PARAM_PATH(layer_dir)},
      {path_row("output_dir", "--output-dir", "DIR",
                "Folder for the frames with the rain removed, named as hydrolux rain names its outputs (created; never "
                "the input folder)"),
       HYDROLUX_PARAM_PATH(output_dir)},
  };
  return rows;
}

// The sRGB curve, interpolated linearly between kSrgbKnots + 1 knots over [0, 1] (clamped): within 0.005 grey
// levels of it (h^2 / 8 times its largest curvature, about 2400 just above 0.0031308, times 255), and a third
// of the time a pow per channel took.
double srgb_encode(float v) {
  static const std::vector<double> knots = [] {
    std::vector<double> k(kSrgbKnots + 1);
    for (std::size_t i = 0; i <= kSrgbKnots; ++i) {
      k[i] = color::srgb_encode(double(i) / double(kSrgbKnots));
    }
    return k;
  }();
  const double t = (v > 0 ? std::min(double(v), 1.0) : 0.0) * double(kSrgbKnots);  // NaN: 0
  const std::size_t i = std::min(std::size_t(t), kSrgbKnots - 1);
  const double f = t - double(i);
  return knots[i] + f * (knots[i + 1] - knots[i]);
}

void check_frames(std::span<const GreyFrame> frames) {
  if (frames.size() < 3) throw Error(fmt::format("rain detection needs at least 3 frames, got {}", frames.size()));
  for (const auto& f : frames)
    if (f.width != frames[0].width || f.height != frames[0].height)
      throw Error(fmt::format("rain detection: a frame of {}x{} among frames of {}x{}", f.width, f.height,
                              frames[0].width, frames[0].height));
}

Mask empty_mask(int width, int height) {
  return Mask{width, height, std::vector<std::uint8_t>(std::size_t(width) * std::size_t(height), 0)};
}

// The correlation's moments at zero time lag of one frame's mask, per pixel of the mask: the sum over the
// lags d (|dx|, |dy| <= r, d != 0) of b(q + d) times (1, dx^2, dy^2, dx dy).
struct SparseMoments {
  std::vector<std::size_t> index;
  std::vector<std::array<float, 4>> m;
};

SparseMoments frame_moments(const Mask& b, int r) {
  SparseMoments out;
  const int w = b.width, h = b.height;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      if (!b.on[std::size_t(y) * std::size_t(w) + std::size_t(x)]) continue;
      std::array<float, 4> m{0, 0, 0, 0};
      for (int dy = -r; dy <= r; ++dy) {
        const int yy = y + dy;
        if (yy < 0 || yy >= h) continue;
        for (int dx = -r; dx <= r; ++dx) {
          const int xx = x + dx;
          if (xx < 0 || xx >= w || (dx == 0 && dy == 0)) continue;
          if (!b.on[std::size_t(yy) * std::size_t(w) + std::size_t(xx)]) continue;
          m[0] += 1, m[1] += float(dx * dx), m[2] += float(dy * dy), m[3] += float(dx * dy);
        }
      }
      out.index.push_back(std::size_t(y) * std::size_t(w) + std::size_t(x));
      out.m.push_back(m);
    }
  return out;
}

// The window of frames around n: [first, last).
std::pair<std::size_t, std::size_t> frame_window(std::size_t frames, std::size_t n, int window_frames) {
  const std::size_t half = std::size_t(window_frames) / 2;
  std::size_t first = n >= half ? n - half : 0;
  std::size_t last = std::min(frames, first + std::size_t(window_frames));
  if (last - first < std::size_t(window_frames)) first = last >= std::size_t(window_frames) ? last - std::size_t(window_frames) : 0;
  return {first, last};
}

// Summed moments of the frames [first, last) as a 4-channel summed-area table ((w + 1) x (h + 1)).
std::vector<std::array<double, 4>> window_table(std::span<const SparseMoments> moments, std::size_t first,
                                                std::size_t last, int w, int h) {
  std::vector<std::array<double, 4>> sum(std::size_t(w) * std::size_t(h), {0, 0, 0, 0});
  for (std::size_t t = first; t < last; ++t)
    for (std::size_t k = 0; k < moments[t].index.size(); ++k)
      for (int c = 0; c < 4; ++c) sum[moments[t].index[k]][std::size_t(c)] += moments[t].m[k][std::size_t(c)];
  const std::size_t W = std::size_t(w) + 1;
  std::vector<std::array<double, 4>> table(W * (std::size_t(h) + 1), {0, 0, 0, 0});
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 4; ++c) {
        const std::size_t i = std::size_t(c);
        table[(std::size_t(y) + 1) * W + std::size_t(x) + 1][i] =
            sum[std::size_t(y) * std::size_t(w) + std::size_t(x)][i] + table[std::size_t(y) * W + std::size_t(x) + 1][i] +
            table[(std::size_t(y) + 1) * W + std::size_t(x)][i] - table[std::size_t(y) * W + std::size_t(x)][i];
      }
  return table;
}

Needle needle_from(const std::vector<std::array<double, 4>>& table, int w, int h, int x, int y, int r) {
  const std::size_t W = std::size_t(w) + 1;
  const int x0 = std::max(0, x - r), x1 = std::min(w, x + r + 1), y0 = std::max(0, y - r), y1 = std::min(h, y + r + 1);
  std::array<double, 4> m{};
  for (std::size_t c = 0; c < 4; ++c)
    m[c] = table[std::size_t(y1) * W + std::size_t(x1)][c] - table[std::size_t(y0) * W + std::size_t(x1)][c] -
           table[std::size_t(y1) * W + std::size_t(x0)][c] + table[std::size_t(y0) * W + std::size_t(x0)][c];
  Needle n;
  n.weight = m[0];
  const double trace = m[1] + m[2];
  if (!(trace > 0)) return n;
  const double diff = m[1] - m[2], cross = 2 * m[3];
  n.elongation = std::sqrt(diff * diff + cross * cross) / trace;
  double deg = 0.5 * std::atan2(cross, diff) * 180 / std::numbers::pi;
  if (deg < 0) deg += 180;
  n.direction_deg = deg >= 180 ? deg - 180 : deg;
  return n;
}

double direction_gap_deg(double a, double b) {
  const double d = std::fmod(std::abs(a - b), 180.0);
  return std::min(d, 180 - d);
}

std::vector<SparseMoments> all_moments(std::span<const Mask> masks, int r) {
  std::vector<SparseMoments> out(masks.size());
  tbb::parallel_for(std::size_t(0), masks.size(), [&](std::size_t t) { out[t] = frame_moments(masks[t], r); });
  return out;
}

Mask correlation_test_with(std::span<const Mask> masks, std::span<const SparseMoments> moments, std::size_t n,
                           const DetectSettings& s) {
  const Mask& b = masks[n];
  const int w = b.width, h = b.height, r = s.window_px / 2;
  Mask out = empty_mask(w, h);
  if (b.count() == 0) return out;
  const auto [first, last] = frame_window(masks.size(), n, s.window_frames);
  const auto table = window_table(moments, first, last, w, h);
  // The frame's needles, and its dominant direction: the mean of the doubled angles weighted by the
  // needles' weight times elongation.
  std::vector<std::pair<std::size_t, Needle>> needles;
  double sx = 0, sy = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const std::size_t i = std::size_t(y) * std::size_t(w) + std::size_t(x);
      if (!b.on[i]) continue;
      const Needle nd = needle_from(table, w, h, x, y, r);
      const double a = 2 * nd.direction_deg * std::numbers::pi / 180, wt = nd.weight * nd.elongation;
      sx += wt * std::cos(a), sy += wt * std::sin(a);
      needles.emplace_back(i, nd);
    }
  if (!(std::hypot(sx, sy) > 0)) return out;
  double dominant = 0.5 * std::atan2(sy, sx) * 180 / std::numbers::pi;
  if (dominant < 0) dominant += 180;
  for (const auto& [i, nd] : needles)
    if (nd.elongation >= s.min_elongation && direction_gap_deg(nd.direction_deg, dominant) <= s.max_direction_spread_deg)
      out.on[i] = 1;
  return out;
}

}  // namespace

std::span<const Field<DetectSettings>> detect_params() { return kDetect; }
std::span<const Field<EvalSettings>> eval_params() { return kEval; }
std::span<const Field<DetectSettings>> eval_detector_params() {
  const auto all = detect_params();
  std::size_t first = 0;
  while (first < all.size() && all[first].param.name != "exposure_s") ++first;
  return all.subspan(first);
}
std::span<const Field<DetectPaths>> detect_path_params() { return detect_paths(); }
std::span<const Field<RemoveSettings>> remove_params() { return kRemove; }
std::span<const Field<RemovePaths>> remove_path_params() { return remove_paths(); }

void validate(const RemoveSettings& s) {
  check_fields(remove_params(), s);
  if (s.median_frames % 2 == 0)
    throw ParamError(fmt::format("{{median_frames}} {}: must be odd (a window centred on its frame)", s.median_frames));
}

namespace {
void check_alike(std::span<const Image> frames) {
  for (const Image& f : frames)
    if (f.width != frames[0].width || f.height != frames[0].height || f.channels != frames[0].channels)
      throw Error(fmt::format("rain removal: a frame of {}x{} with {} channels among frames of {}x{} with {}", f.width,
                              f.height, f.channels, frames[0].width, frames[0].height, frames[0].channels));
}
}  // namespace

Image remove_from_neighbours(std::span<const Image> frames, std::span<const Mask> masks, std::size_t n) {
  check_alike(frames);
  if (masks.size() != frames.size()) throw Error(fmt::format("rain removal: {} masks for {} frames", masks.size(), frames.size()));
  for (const Mask& m : masks)
    if (m.width != frames[0].width || m.height != frames[0].height)
      throw Error(fmt::format("rain removal: a mask of {}x{} for frames of {}x{}", m.width, m.height, frames[0].width,
                              frames[0].height));
  const Image& f = frames[n];
  Image out = f;
  const std::size_t ch = std::size_t(f.channels), count = frames.size();
  const auto flagged = [&](std::size_t t, std::size_t i) { return masks[t].on[i] != 0; };
  for (std::size_t i = 0; i < masks[n].on.size(); ++i) {
    if (!flagged(n, i)) continue;
    // The usable frame on each side: the neighbour, or the one beyond it where the neighbour is rain too.
    const auto side = [&](int step) -> const Image* {
      for (int k = 1; k <= 2; ++k) {
        const long t = long(n) + step * k;
        if (t < 0 || t >= long(count)) return nullptr;
        if (!flagged(std::size_t(t), i)) return &frames[std::size_t(t)];
      }
      return nullptr;
    };
    const Image *a = side(-1), *b = side(+1);
    if (!a && !b) continue;
    for (std::size_t c = 0; c < ch; ++c) {
      const std::size_t k = i * ch + c;
      out.pixels[k] = a && b ? 0.5f * (a->pixels[k] + b->pixels[k]) : (a ? a->pixels[k] : b->pixels[k]);
    }
  }
  return out;
}

Image temporal_median(std::span<const Image> frames, std::size_t n, int median_frames) {
  check_alike(frames);
  const std::size_t window = std::min(std::size_t(median_frames), frames.size() - (frames.size() % 2 == 0 ? 1 : 0));
  const std::size_t half = window / 2;
  std::size_t first = n >= half ? n - half : 0;
  if (first + window > frames.size()) first = frames.size() - window;
  Image out = frames[n];
  std::vector<float> v(window);
  for (std::size_t k = 0; k < out.pixels.size(); ++k) {
    for (std::size_t t = 0; t < window; ++t) v[t] = frames[first + t].pixels[k];
    std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(half), v.end());
    out.pixels[k] = v[half];
  }
  return out;
}

Image invert_rain_layer(const Image& rainy, const Image& layer) {
  if (layer.channels != 4) throw Error(fmt::format("a rain layer has 4 channels (premultiplied RGBA), not {}", layer.channels));
  if (layer.width != rainy.width || layer.height != rainy.height)
    throw Error(fmt::format("a rain layer of {}x{} for a frame of {}x{}", layer.width, layer.height, rainy.width,
                            rainy.height));
  Image out = rainy;
  const std::size_t ch = std::size_t(rainy.channels), colours = std::min<std::size_t>(ch, 3);
  for (std::size_t i = 0; i < std::size_t(rainy.width) * std::size_t(rainy.height); ++i) {
    const double alpha = layer.pixels[i * 4 + 3];
    if (!(alpha < 1)) continue;
    for (std::size_t c = 0; c < colours; ++c)
      out.pixels[i * ch + c] = float((double(rainy.pixels[i * ch + c]) - double(layer.pixels[i * 4 + c])) / (1 - alpha));
  }
  return out;
}

RemovalError& RemovalError::operator+=(const RemovalError& o) {
  sum_squares_in += o.sum_squares_in, sum_squares_out += o.sum_squares_out;
  values_in += o.values_in, values_out += o.values_out;
  return *this;
}

namespace {
double psnr_of(double sum_squares, std::uint64_t values) {
  if (values == 0) return std::numeric_limits<double>::quiet_NaN();
  const double mse = sum_squares / double(values);
  return mse > 0 ? 10 * std::log10(255.0 * 255.0 / mse) : std::numeric_limits<double>::infinity();
}
}  // namespace

double RemovalError::psnr_in() const { return psnr_of(sum_squares_in, values_in); }
double RemovalError::psnr_out() const { return psnr_of(sum_squares_out, values_out); }

RemovalError removal_error(const Image& derained, const Image& clean, std::span<const float> true_alpha,
                           const EvalSettings& s) {
  if (derained.width != clean.width || derained.height != clean.height ||
      true_alpha.size() != std::size_t(clean.width) * std::size_t(clean.height))
    throw Error(fmt::format("rain-eval: a derained frame of {}x{} against a clean one of {}x{}", derained.width,
                            derained.height, clean.width, clean.height));
  const std::size_t cd = std::size_t(derained.channels), cc = std::size_t(clean.channels);
  const std::size_t colours = std::min<std::size_t>({cd, cc, 3});
  RemovalError e;
  for (std::size_t i = 0; i < true_alpha.size(); ++i) {
    const float a = true_alpha[i];
    const bool in = a >= s.rain_alpha, out = !(a > 0 && a >= s.ignore_alpha) && !in;
    if (!in && !out) continue;
    for (std::size_t c = 0; c < colours; ++c) {
      const double d = 255 * (srgb_encode(derained.pixels[i * cd + c]) - srgb_encode(clean.pixels[i * cc + c]));
      (in ? e.sum_squares_in : e.sum_squares_out) += d * d;
      (in ? e.values_in : e.values_out) += 1;
    }
  }
  return e;
}
std::span<const Field<EvalPaths>> eval_path_params() { return eval_paths(); }

double max_beta(const DetectSettings& s) { return s.drop_time_s / s.exposure_s; }

void validate(const DetectSettings& s) {
  check_fields(detect_params(), s);
  if (s.window_px % 2 == 0) throw ParamError(fmt::format("{{window_px}} {}: must be odd (a window centred on its pixel)", s.window_px));
  if (s.median_frames % 2 == 0)
    throw ParamError(fmt::format("{{median_frames}} {}: must be odd (a window centred on its frame)", s.median_frames));
}

void validate(const EvalSettings& s) {
  check_fields(eval_params(), s);
  if (s.ignore_alpha > s.rain_alpha)
    throw ParamError(fmt::format("{{ignore_alpha}} {:g}: above {{rain_alpha}} {:g}", s.ignore_alpha, s.rain_alpha));
}

GreyFrame grey_levels(const Image& linear) {
  if (linear.channels < 1) throw Error("rain detection: an image without channels");
  GreyFrame g{linear.width, linear.height, std::vector<float>(std::size_t(linear.width) * std::size_t(linear.height))};
  const auto encode = [](float v) { return srgb_encode(v); };
  const std::size_t ch = std::size_t(linear.channels);
  for (std::size_t i = 0; i < g.level.size(); ++i) {
    const float* p = &linear.pixels[i * ch];
    const double y = ch >= 3 ? 0.299 * encode(p[0]) + 0.587 * encode(p[1]) + 0.114 * encode(p[2]) : encode(p[0]);
    g.level[i] = float(255 * y);
  }
  return g;
}

void check_finite(const Image& image, std::string_view origin) {
  const std::size_t ch = std::size_t(std::max(image.channels, 1));
  for (std::size_t i = 0; i < image.pixels.size(); ++i)
    if (!std::isfinite(image.pixels[i])) {
      const std::size_t p = i / ch;
      throw Error(fmt::format("{}: a non-finite value ({}) at pixel ({}, {}), channel {}; rain detection and removal "
                              "take finite light",
                              origin, image.pixels[i], p % std::size_t(image.width), p / std::size_t(image.width),
                              i % ch));
    }
}

std::size_t Mask::count() const { return std::size_t(std::count(on.begin(), on.end(), std::uint8_t(1))); }

Mask rain_candidates(const GreyFrame& previous, const GreyFrame& frame, const GreyFrame& next, double min_change) {
  Mask m = empty_mask(frame.width, frame.height);
  for (std::size_t i = 0; i < m.on.size(); ++i)
    m.on[i] = frame.level[i] - previous.level[i] >= min_change && frame.level[i] - next.level[i] >= min_change;
  return m;
}

Mask photometric_test(const Mask& candidates, const GreyFrame& previous, const GreyFrame& frame,
                      const GreyFrame& next, double beta_max) {
  const int w = candidates.width, h = candidates.height;
  Mask out = empty_mask(w, h);
  std::vector<std::int32_t> label(candidates.on.size(), -1);
  std::vector<std::size_t> stack, members;
  for (std::size_t start = 0; start < candidates.on.size(); ++start) {
    if (!candidates.on[start] || label[start] >= 0) continue;
    // One 8-connected streak.
    members.clear();
    stack.assign(1, start);
    label[start] = 1;
    while (!stack.empty()) {
      const std::size_t i = stack.back();
      stack.pop_back();
      members.push_back(i);
      const int x = int(i % std::size_t(w)), y = int(i / std::size_t(w));
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int xx = x + dx, yy = y + dy;
          if (xx < 0 || yy < 0 || xx >= w || yy >= h) continue;
          const std::size_t j = std::size_t(yy) * std::size_t(w) + std::size_t(xx);
          if (candidates.on[j] && label[j] < 0) label[j] = 1, stack.push_back(j);
        }
    }
    // dI = alpha - beta I_bg, the background the neighbours' mean, by least squares.
    double sb = 0, sd = 0, sbb = 0, sbd = 0, lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (const std::size_t i : members) {
      const double bg = 0.5 * (double(previous.level[i]) + double(next.level[i]));
      const double d = double(frame.level[i]) - bg;
      sb += bg, sd += d, sbb += bg * bg, sbd += bg * d;
      lo = std::min(lo, bg), hi = std::max(hi, bg);
    }
    const double n = double(members.size());
    const double var = sbb - sb * sb / n, cov = sbd - sb * sd / n;
    // A streak over a background that varies less than a grey level cannot test the slope: kept.
    const bool testable = members.size() >= 3 && hi - lo >= 1 && var > 0;
    const bool keep = !testable || -cov / var <= beta_max;
    if (keep)
      for (const std::size_t i : members) out.on[i] = 1;
  }
  return out;
}

Mask correlation_test(std::span<const Mask> masks, std::size_t n, const DetectSettings& s) {
  const auto moments = all_moments(masks, s.window_px / 2);
  return correlation_test_with(masks, moments, n, s);
}

Needle correlation_needle(std::span<const Mask> masks, std::size_t n, int x, int y, const DetectSettings& s) {
  const auto moments = all_moments(masks, s.window_px / 2);
  const auto [first, last] = frame_window(masks.size(), n, s.window_frames);
  const auto table = window_table(moments, first, last, masks[n].width, masks[n].height);
  return needle_from(table, masks[n].width, masks[n].height, x, y, s.window_px / 2);
}

Mask median_residual(std::span<const GreyFrame> frames, std::size_t n, int median_frames, double min_change) {
  const GreyFrame& f = frames[n];
  Mask m = empty_mask(f.width, f.height);
  const std::size_t window = std::size_t(median_frames), half = window / 2;
  if (frames.size() < window) return m;
  std::size_t first = n >= half ? n - half : 0;
  if (first + window > frames.size()) first = frames.size() - window;
  std::vector<float> v(window);
  for (std::size_t i = 0; i < m.on.size(); ++i) {
    for (std::size_t k = 0; k < v.size(); ++k) v[k] = frames[first + k].level[i];
    std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(half), v.end());
    m.on[i] = f.level[i] - v[half] >= min_change;
  }
  return m;
}

Detection detect_rain(std::span<const GreyFrame> frames, const DetectSettings& s, const ProgressFn& progress) {
  validate(s);
  check_frames(frames);
  const std::size_t count = frames.size();
  const int w = frames[0].width, h = frames[0].height;
  Detection d;
  // Progress: the per-frame stages, then the correlation (about as costly).
  const double stages = s.method == DetectMethod::garg_nayar ? 2.0 : 1.0;
  const auto report = [&](double done, std::string_view what) {
    if (progress) progress(done / (stages * double(count)), what);
  };
  if (s.method == DetectMethod::median) {
    if (std::size_t(s.median_frames) > count)
      throw ParamError(fmt::format("{{median_frames}} {}: more than the {} frames", s.median_frames, count));
    d.result.resize(count);
    for (std::size_t n = 0; n < count; ++n) {
      d.result[n] = median_residual(frames, n, s.median_frames, s.min_change_grey);
      report(double(n + 1), fmt::format("median residual: {} of {} frames", n + 1, count));
    }
    return d;
  }
  d.candidates.resize(count);
  d.photometric.resize(count);
  for (std::size_t n = 0; n < count; ++n) {
    if (n == 0 || n + 1 == count) {
      d.candidates[n] = empty_mask(w, h);
      d.photometric[n] = empty_mask(w, h);
    } else {
      d.candidates[n] = rain_candidates(frames[n - 1], frames[n], frames[n + 1], s.min_change_grey);
      if (s.method == DetectMethod::garg_nayar)
        d.photometric[n] = photometric_test(d.candidates[n], frames[n - 1], frames[n], frames[n + 1], max_beta(s));
    }
    report(double(n + 1), fmt::format("candidates and photometric test: {} of {} frames", n + 1, count));
  }
  if (s.method == DetectMethod::candidates) {
    d.result = d.candidates;
    d.photometric.clear();
    return d;
  }
  const auto moments = all_moments(d.photometric, s.window_px / 2);
  d.correlated.resize(count);
  for (std::size_t n = 0; n < count; ++n) {
    d.correlated[n] = correlation_test_with(d.photometric, moments, n, s);
    report(double(count + n + 1), fmt::format("spatio-temporal correlation: {} of {} frames", n + 1, count));
  }
  d.result = d.correlated;
  return d;
}

std::vector<PrPoint> pr_curve(std::span<const GreyFrame> frames, std::span<const std::vector<float>> true_alpha,
                              const DetectSettings& s, const EvalSettings& e, std::span<const double> thresholds,
                              const ProgressFn& progress) {
  validate(e);
  if (true_alpha.size() != frames.size())
    throw Error(fmt::format("pr_curve: {} true masks for {} frames", true_alpha.size(), frames.size()));
  std::vector<PrPoint> out;
  for (std::size_t k = 0; k < thresholds.size(); ++k) {
    DetectSettings at = s;
    at.min_change_grey = thresholds[k];
    const Detection d = detect_rain(frames, at, [&](double f, std::string_view what) {
      if (progress)
        progress((double(k) + f) / double(thresholds.size()), fmt::format("c = {:g}: {}", thresholds[k], what));
    });
    PrPoint p{thresholds[k], {}};
    for (std::size_t n = 0; n < frames.size(); ++n) p.scores += score_mask(d.result[n].on, true_alpha[n], e);
    out.push_back(p);
  }
  return out;
}

Confusion& Confusion::operator+=(const Confusion& o) {
  true_positive += o.true_positive, false_positive += o.false_positive, false_negative += o.false_negative;
  true_negative += o.true_negative, ignored += o.ignored;
  return *this;
}

double Confusion::precision() const {
  const double p = double(true_positive + false_positive);
  return p > 0 ? double(true_positive) / p : std::numeric_limits<double>::quiet_NaN();
}
double Confusion::recall() const {
  const double t = double(true_positive + false_negative);
  return t > 0 ? double(true_positive) / t : std::numeric_limits<double>::quiet_NaN();
}
double Confusion::f1() const {
  const double d = double(2 * true_positive + false_positive + false_negative);
  return d > 0 ? 2 * double(true_positive) / d : std::numeric_limits<double>::quiet_NaN();
}
double Confusion::iou() const {
  const double d = double(true_positive + false_positive + false_negative);
  return d > 0 ? double(true_positive) / d : std::numeric_limits<double>::quiet_NaN();
}

Confusion score_mask(std::span<const std::uint8_t> predicted, std::span<const float> true_alpha,
                     const EvalSettings& s) {
  if (predicted.size() != true_alpha.size())
    throw Error(fmt::format("rain-eval: a predicted mask of {} pixels against a true one of {}", predicted.size(),
                            true_alpha.size()));
  Confusion c;
  for (std::size_t i = 0; i < predicted.size(); ++i) {
    const float a = true_alpha[i];
    const bool p = predicted[i] != 0;
    if (a >= s.rain_alpha) (p ? c.true_positive : c.false_negative) += 1;
    else if (a > 0 && a >= s.ignore_alpha) c.ignored += 1;  // a faint streak
    else (p ? c.false_positive : c.true_negative) += 1;
  }
  return c;
}

}  // namespace hydrolux::rain
