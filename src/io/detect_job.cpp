#include "hydrolux/io/detect_job.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <optional>
#include <nlohmann/json.hpp>

#include "hydrolux/core/error.hpp"
#include "hydrolux/core/memory.hpp"
#include "hydrolux/io/files.hpp"
#include "hydrolux/io/frames.hpp"
#include "hydrolux/io/svg_plot.hpp"

namespace hydrolux::io {

namespace fs = std::filesystem;

namespace {

// Whether two folders are one, existing or not (the paths made absolute and resolved as far as they exist).
bool same_folder(const std::string& a, const std::string& b) {
  std::error_code ec;
  const fs::path ca = fs::weakly_canonical(fs::absolute(a), ec), cb = fs::weakly_canonical(fs::absolute(b), ec);
  return ca == cb || (fs::exists(a, ec) && fs::exists(b, ec) && same_file(a, b));
}

// A decoded image's pixels checked finite, named by flag and file.
Image finite_image(const ImageCodec& codec, std::string_view flag, const fs::path& path) {
  Image img = read_decoded(codec, flag, path, [](const std::string&) {}).image;
  rain::check_finite(img, fmt::format("{} {}", flag, path.string()));
  return img;
}

// The image files of a folder by name (frames.hpp's extensions, no hidden ones), or Error naming the flag.
std::map<std::string, fs::path> masks_in(const std::string& dir, std::string_view flag) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) throw Error(fmt::format("{} {}: not a folder", flag, dir));
  std::map<std::string, fs::path> out;
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    const std::string name = e.path().filename().string();
    if (!is_frame_file(e.path()) || name.front() == '.' || !fs::is_regular_file(e.path(), ec)) continue;
    const auto [it, fresh] = out.emplace(e.path().stem().string(), e.path());
    if (!fresh)
      throw Error(fmt::format("{} {}: both {} and {} are named {}; keep one", flag, dir, it->second.filename().string(),
                              name, it->first));
  }
  if (ec) throw Error(fmt::format("{} {}: cannot list: {}", flag, dir, ec.message()));
  if (out.empty()) throw Error(fmt::format("{} {}: no image files (png, jpg, exr, tif, hdr, ppm, pfm)", flag, dir));
  return out;
}

Image mask_image(const rain::Mask& m) {
  Image img(m.width, m.height, 1);
  for (std::size_t i = 0; i < m.on.size(); ++i) img.pixels[i] = m.on[i] ? 1.f : 0.f;
  img.non_colour = true;
  return img;
}

nlohmann::ordered_json scores(const rain::Confusion& c) {
  const auto ratio = [](double v) { return std::isnan(v) ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(v); };
  return {{"precision", ratio(c.precision())}, {"recall", ratio(c.recall())}, {"f1", ratio(c.f1())},
          {"iou", ratio(c.iou())},           {"true_positive", c.true_positive}, {"false_positive", c.false_positive},
          {"false_negative", c.false_negative}, {"true_negative", c.true_negative}, {"ignored", c.ignored}};
}

}  // namespace

DetectReport run_detect_job(const DetectJob& job, const DetectHooks& hooks) {
  rain::validate(job.settings);
  if (job.input_dir.empty()) throw Error("--input-dir is required");
  if (job.output_dir.empty()) throw Error("--output-dir is required");
  const FrameFolder plan = plan_frame_folder({job.input_dir, job.output_dir, std::nullopt, std::nullopt});
  std::error_code ec;
  if (job.stages_dir) {
    if (job.settings.method == rain::DetectMethod::median)
      throw Error(fmt::format("--stages-dir {}: the median baseline has no stages (--method garg-nayar or candidates)",
                              *job.stages_dir));
    if (same_folder(*job.stages_dir, job.input_dir))
      throw Error(fmt::format("--stages-dir {}: is the input folder", *job.stages_dir));
    if (same_folder(*job.stages_dir, job.output_dir))
      throw Error(fmt::format("--stages-dir {}: is --output-dir; give the stages their own folder", *job.stages_dir));
  }
  if (plan.frames.size() < 3)
    throw Error(fmt::format("--input-dir {}: {} frame{}; rain detection compares each frame with the ones before and "
                            "after it, so it needs at least 3",
                            job.input_dir, plan.frames.size(), plan.frames.size() == 1 ? "" : "s"));
  DetectReport report;
  std::map<std::string, std::string> names;  // mask name -> frame
  for (const auto& f : plan.frames) {
    const std::string name = f.stem().string() + ".png";
    const auto [it, fresh] = names.emplace(name, f.filename().string());
    if (!fresh)
      throw Error(fmt::format("--input-dir {}: {} and {} would both have the mask {}", job.input_dir, it->second,
                              f.filename().string(), name));
    report.frames.push_back(name);
  }
  // Every frame's grey levels and masks are held: refuse what would not fit, from the first frame's size.
  std::vector<rain::GreyFrame> grey;
  grey.reserve(plan.frames.size());
  const auto warn_none = [](const std::string&) {};
  for (std::size_t k = 0; k < plan.frames.size(); ++k) {
    const DecodedImage d = read_decoded(hooks.codec, "--input-dir", plan.frames[k], warn_none);
    rain::check_finite(d.image, "--input-dir " + plan.frames[k].string());
    if (k == 0) {
      report.width = d.image.width, report.height = d.image.height;
      // Grey levels (4 bytes), the stages' masks (3 bytes), the correlation's table (32 bytes, one frame).
      const double bytes = double(plan.frames.size()) * double(d.image.width) * double(d.image.height) * 8.0 +
                           double(d.image.width + 1) * double(d.image.height + 1) * 64.0;
      if (bytes > 0.8 * double(available_memory_bytes()))
        throw Error(fmt::format("--input-dir {}: {} frames of {}x{} need about {} to detect rain in, more than the {} "
                                "available; split the folder",
                                job.input_dir, plan.frames.size(), d.image.width, d.image.height, format_bytes(bytes),
                                format_bytes(double(available_memory_bytes()))));
    }
    if (d.image.width != report.width || d.image.height != report.height)
      throw Error(fmt::format("--input-dir {}: {} is {}x{}, the first frame {}x{}", job.input_dir,
                              plan.frames[k].filename().string(), d.image.width, d.image.height, report.width,
                              report.height));
    grey.push_back(rain::grey_levels(d.image));
    if (hooks.progress)
      hooks.progress(0.2 * double(k + 1) / double(plan.frames.size()),
                     fmt::format("reading {} of {} frames", k + 1, plan.frames.size()));
  }
  const rain::Detection det = rain::detect_rain(grey, job.settings, [&](double f, std::string_view what) {
    if (hooks.progress) hooks.progress(0.2 + 0.7 * f, what);
  });

  OutputDirectory out(job.output_dir, "--output-dir");
  std::optional<OutputDirectory> stages;
  if (job.stages_dir) stages.emplace(*job.stages_dir, "--stages-dir");
  const PngOptions png{8, kDefaultPngCompression};
  for (std::size_t k = 0; k < det.result.size(); ++k) {
    out.write(report.frames[k], hooks.codec.encode(coverage_for_encoding(mask_image(det.result[k]), ImageFormat::png),
                                                   ImageFormat::png, png));
    report.detected.push_back(det.result[k].count());
    if (stages)
      for (const auto& [folder, masks] : {std::pair{"candidates", &det.candidates}, {"photometric", &det.photometric},
                                          {"correlated", &det.correlated}})
        if (!masks->empty())
          stages->write(fmt::format("{}/{}", folder, report.frames[k]),
                        hooks.codec.encode(coverage_for_encoding(mask_image((*masks)[k]), ImageFormat::png),
                                           ImageFormat::png, png));
    if (!det.candidates.empty()) report.candidates += det.candidates[k].count();
    if (!det.photometric.empty()) report.photometric += det.photometric[k].count();
    if (!det.correlated.empty()) report.correlated += det.correlated[k].count();
    if (hooks.progress)
      hooks.progress(0.9 + 0.1 * double(k + 1) / double(det.result.size()),
                     fmt::format("writing {} of {} masks", k + 1, det.result.size()));
  }
  if (stages) stages->commit();
  out.commit();
  return report;
}

RemoveReport run_remove_job(const RemoveJob& job, const DetectHooks& hooks) {
  rain::validate(job.settings);
  if (job.input_dir.empty()) throw Error("--input-dir is required");
  if (job.output_dir.empty()) throw Error("--output-dir is required");
  const auto method = job.settings.method;
  if (method == rain::RemoveMethod::garg_nayar && !job.mask_dir)
    throw Error("--mask-dir: --method garg-nayar replaces the masked pixels; give the masks (detect-rain's)");
  if (method == rain::RemoveMethod::oracle && !job.layer_dir)
    throw Error("--layer-dir: --method oracle inverts the rain layers; give them (hydrolux rain --layer-dir)");
  if (method != rain::RemoveMethod::garg_nayar && job.mask_dir)
    throw Error(fmt::format("--mask-dir {}: used only with --method garg-nayar", *job.mask_dir));
  if (method != rain::RemoveMethod::oracle && job.layer_dir)
    throw Error(fmt::format("--layer-dir {}: used only with --method oracle", *job.layer_dir));
  for (const auto& [flag, dir] : {std::pair{"--mask-dir", job.mask_dir}, {"--layer-dir", job.layer_dir}})
    if (dir && same_folder(*dir, job.output_dir))
      throw Error(fmt::format("--output-dir {}: is {}; the frames would replace its files", job.output_dir, flag));
  const FrameFolder plan = plan_frame_folder({job.input_dir, job.output_dir, std::nullopt, std::nullopt});
  if (plan.frames.size() < 3 && method != rain::RemoveMethod::oracle)
    throw Error(fmt::format("--input-dir {}: {} frame{}; removal from the neighbouring frames needs at least 3",
                            job.input_dir, plan.frames.size(), plan.frames.size() == 1 ? "" : "s"));
  // Each frame's mask or layer, by its stem, found before any work.
  const std::optional<std::map<std::string, fs::path>> masks =
      job.mask_dir ? std::optional(masks_in(*job.mask_dir, "--mask-dir")) : std::nullopt;
  const std::optional<std::map<std::string, fs::path>> layers =
      job.layer_dir ? std::optional(masks_in(*job.layer_dir, "--layer-dir")) : std::nullopt;
  const auto companion = [](const std::optional<std::map<std::string, fs::path>>& m, const std::string& dir,
                            std::string_view flag, const fs::path& frame) {
    const auto it = m->find(frame.stem().string());
    if (it == m->end())
      throw Error(fmt::format("{} {}: nothing named {} for the frame {}", flag, dir, frame.stem().string(),
                              frame.filename().string()));
    return it->second;
  };
  RemoveReport report;
  report.frames = plan.frames.size();
  std::vector<Image> frames;
  std::vector<rain::Mask> frame_masks;
  const auto warn_none = [](const std::string&) {};
  for (std::size_t k = 0; k < plan.frames.size(); ++k) {
    Image f = finite_image(hooks.codec, "--input-dir", plan.frames[k]);
    if (k == 0) {
      report.width = f.width, report.height = f.height;
      const double bytes = double(plan.frames.size()) * double(f.width) * double(f.height) * (4.0 * f.channels + 1);
      if (bytes > 0.8 * double(available_memory_bytes()))
        throw Error(fmt::format("--input-dir {}: {} frames of {}x{} need about {} to remove rain from, more than the {} "
                                "available; split the folder",
                                job.input_dir, plan.frames.size(), f.width, f.height, format_bytes(bytes),
                                format_bytes(double(available_memory_bytes()))));
    } else if (f.width != report.width || f.height != report.height || f.channels != frames[0].channels) {
      throw Error(fmt::format("--input-dir {}: {} is {}x{} with {} channels, the first frame {}x{} with {}", job.input_dir,
                              plan.frames[k].filename().string(), f.width, f.height, f.channels, report.width,
                              report.height, frames[0].channels));
    }
    if (masks) {
      const fs::path mp = companion(masks, *job.mask_dir, "--mask-dir", plan.frames[k]);
      const Image m = read_decoded(hooks.codec, "--mask-dir", mp, warn_none).image;
      if (m.width != f.width || m.height != f.height)
        throw Error(fmt::format("--mask-dir {}: {} is {}x{}, its frame {}x{}", *job.mask_dir, mp.filename().string(),
                                m.width, m.height, f.width, f.height));
      rain::Mask mk{m.width, m.height, std::vector<std::uint8_t>(std::size_t(m.width) * std::size_t(m.height))};
      for (std::size_t i = 0; i < mk.on.size(); ++i) mk.on[i] = m.pixels[i * std::size_t(m.channels)] > 0;
      frame_masks.push_back(std::move(mk));
    }
    frames.push_back(std::move(f));
    if (hooks.progress)
      hooks.progress(0.4 * double(k + 1) / double(plan.frames.size()),
                     fmt::format("reading {} of {} frames", k + 1, plan.frames.size()));
  }
  OutputDirectory out(job.output_dir, "--output-dir");
  const PngOptions png{8, job.png_compression};
  for (std::size_t k = 0; k < frames.size(); ++k) {
    Image clear;
    if (method == rain::RemoveMethod::garg_nayar) {
      clear = rain::remove_from_neighbours(frames, frame_masks, k);
    } else if (method == rain::RemoveMethod::median) {
      clear = rain::temporal_median(frames, k, job.settings.median_frames);
    } else {
      const fs::path lp = companion(layers, *job.layer_dir, "--layer-dir", plan.frames[k]);
      const Image layer = finite_image(hooks.codec, "--layer-dir", lp);
      if (layer.channels != 4 || layer.width != frames[k].width || layer.height != frames[k].height)
        throw Error(fmt::format("--layer-dir {}: {} is {}x{} with {} channels; its frame's layer is {}x{} premultiplied "
                                "RGBA (hydrolux rain --layer-dir)",
                                *job.layer_dir, lp.filename().string(), layer.width, layer.height, layer.channels,
                                frames[k].width, frames[k].height));
      clear = rain::invert_rain_layer(frames[k], layer);
    }
    for (std::size_t i = 0; i < clear.pixels.size(); ++i) report.replaced += clear.pixels[i] != frames[k].pixels[i];
    const fs::path& name = plan.outputs[k];
    const auto format = name.extension() == ".exr" ? ImageFormat::exr : ImageFormat::png;
    out.write(name.string(), hooks.codec.encode(clear, format, png));
    if (hooks.progress)
      hooks.progress(0.4 + 0.6 * double(k + 1) / double(frames.size()),
                     fmt::format("removing and writing {} of {} frames", k + 1, frames.size()));
  }
  out.commit();
  return report;
}

std::string remove_summary(const RemoveJob& job, const RemoveReport& r) {
  const char* method = job.settings.method == rain::RemoveMethod::garg_nayar ? "garg-nayar"
                       : job.settings.method == rain::RemoveMethod::median   ? "median"
                                                                             : "oracle";
  return fmt::format("remove-rain: {} frames of {}x{} in {} ({}): {} values changed", r.frames, r.width, r.height,
                     job.output_dir, method, r.replaced);
}

std::string detect_summary(const DetectJob& job, const DetectReport& r) {
  std::size_t total = 0;
  for (const std::size_t n : r.detected) total += n;
  const double pixels = double(r.width) * double(r.height) * double(r.frames.size());
  std::string s = fmt::format("detect-rain: {} masks of {}x{} in {}: {:.3f}% of the pixels rain ({})", r.frames.size(),
                              r.width, r.height, job.output_dir, 100 * double(total) / pixels,
                              job.settings.method == rain::DetectMethod::garg_nayar   ? "garg-nayar"
                              : job.settings.method == rain::DetectMethod::candidates ? "candidates"
                                                                                      : "median");
  if (job.settings.method == rain::DetectMethod::garg_nayar)
    s += fmt::format("; candidates {:.3f}%, after the photometric test {:.3f}%, after the correlation {:.3f}%",
                     100 * double(r.candidates) / pixels, 100 * double(r.photometric) / pixels,
                     100 * double(r.correlated) / pixels);
  return s;
}

namespace {

// The PR curves of the three detectors over kPrThresholds on the frames of job.input_dir, against the true
// masks of their stems; with plots_dir, pr.svg and pr.csv there.
void add_pr_curves(const EvalJob& job, const ImageCodec& codec, const std::map<std::string, fs::path>& truth,
                   EvalReport& report, const std::function<void(double, std::string_view)>& progress) {
  const FrameFolder plan = plan_frame_folder({*job.input_dir, std::string(), std::nullopt, std::nullopt});
  const auto warn_none = [](const std::string&) {};
  std::vector<rain::GreyFrame> grey;
  std::vector<std::vector<float>> alpha;
  for (const auto& f : plan.frames) {
    const auto t = truth.find(f.stem().string());
    if (t == truth.end())
      throw Error(fmt::format("--truth-dir {}: no true mask for the frame {} of --input-dir", job.truth_dir,
                              f.filename().string()));
    grey.push_back(rain::grey_levels(finite_image(codec, "--input-dir", f)));
    if (grey.back().width != grey.front().width || grey.back().height != grey.front().height)
      throw Error(fmt::format("--input-dir {}: {} is {}x{}, the first frame {}x{}", *job.input_dir,
                              f.filename().string(), grey.back().width, grey.back().height, grey.front().width,
                              grey.front().height));
    const Image a = read_decoded(codec, "--truth-dir", t->second, warn_none).image;
    if (a.width != grey.back().width || a.height != grey.back().height)
      throw Error(fmt::format("--truth-dir {}: {} is {}x{}, its frame {}x{}", job.truth_dir, t->second.filename().string(),
                              a.width, a.height, grey.back().width, grey.back().height));
    std::vector<float> v(std::size_t(a.width) * std::size_t(a.height));
    for (std::size_t i = 0; i < v.size(); ++i) v[i] = a.pixels[i * std::size_t(a.channels)];
    alpha.push_back(std::move(v));
  }
  if (grey.size() < 3)
    throw Error(fmt::format("--input-dir {}: {} frame{}; the detectors compare each frame with its neighbours, so the PR "
                            "curves need at least 3",
                            *job.input_dir, grey.size(), grey.size() == 1 ? "" : "s"));
  const std::pair<const char*, rain::DetectMethod> methods[] = {{"garg-nayar", rain::DetectMethod::garg_nayar},
                                                                {"candidates", rain::DetectMethod::candidates},
                                                                {"median", rain::DetectMethod::median}};
  for (std::size_t m = 0; m < std::size(methods); ++m) {
    rain::DetectSettings s = job.detector;
    s.method = methods[m].second;
    report.pr.emplace_back(methods[m].first,
                           rain::pr_curve(grey, alpha, s, job.settings, rain::kPrThresholds, [&](double f, std::string_view w) {
                             if (progress) progress((double(m) + f) / 3.0, fmt::format("{}: {}", methods[m].first, w));
                           }));
  }
}

}  // namespace

EvalReport run_eval_job(const EvalJob& job, const ImageCodec& codec,
                        const std::function<void(double, std::string_view)>& progress) {
  rain::validate(job.settings);
  if (job.pred_dir.empty()) throw Error("--pred-dir is required");
  if (job.truth_dir.empty()) throw Error("--truth-dir is required");
  // The report's file reserved before any work (files.hpp), and JSON by its name.
  std::optional<OutputFile> report_file;
  if (job.output) {
    if (lower_extension(*job.output) != ".json")
      throw Error(fmt::format("--output {}: the report is JSON; name it .json", *job.output));
    report_file.emplace(*job.output, "--output");
  }
  if (job.clean_dir.has_value() != job.derained_dir.has_value())
    throw Error(job.clean_dir ? "--clean-dir: goes with --derained-dir (the frames after removal)"
                              : "--derained-dir: goes with --clean-dir (the frames before the rain)");
  rain::validate(job.detector);
  std::optional<OutputDirectory> plots;
  if (job.plots_dir) {
    std::error_code ec;
    if (fs::exists(*job.plots_dir, ec) && !fs::is_directory(*job.plots_dir, ec))
      throw Error(fmt::format("--plots-dir {}: exists and is not a folder", *job.plots_dir));
    for (const auto& [flag, dir] : {std::pair{"--input-dir", job.input_dir.value_or("")}, {"--pred-dir", job.pred_dir},
                                    {"--truth-dir", job.truth_dir}})
      if (!dir.empty() && fs::exists(*job.plots_dir, ec) && same_file(*job.plots_dir, dir))
        throw Error(fmt::format("--plots-dir {}: is {}; give the plots their own folder", *job.plots_dir, flag));
  }
  const auto pred = masks_in(job.pred_dir, "--pred-dir");
  const std::optional<std::map<std::string, fs::path>> clean =
      job.clean_dir ? std::optional(masks_in(*job.clean_dir, "--clean-dir")) : std::nullopt;
  const std::optional<std::map<std::string, fs::path>> derained =
      job.derained_dir ? std::optional(masks_in(*job.derained_dir, "--derained-dir")) : std::nullopt;
  const auto truth = masks_in(job.truth_dir, "--truth-dir");
  EvalReport report;
  const auto warn_none = [](const std::string&) {};
  for (const auto& [stem, path] : pred) {
    const auto t = truth.find(stem);
    if (t == truth.end()) {
      report.unmatched.push_back(path.filename().string());
      continue;
    }
    const DecodedImage p = read_decoded(codec, "--pred-dir", path, warn_none);
    const DecodedImage a = read_decoded(codec, "--truth-dir", t->second, warn_none);
    if (p.image.width != a.image.width || p.image.height != a.image.height)
      throw Error(fmt::format("--pred-dir {}: {} is {}x{}, its true mask {}x{}", job.pred_dir, path.filename().string(),
                              p.image.width, p.image.height, a.image.width, a.image.height));
    const std::size_t n = std::size_t(p.image.width) * std::size_t(p.image.height);
    std::vector<std::uint8_t> on(n);
    std::vector<float> alpha(n);
    for (std::size_t i = 0; i < n; ++i) {
      on[i] = p.image.pixels[i * std::size_t(p.image.channels)] > 0;
      alpha[i] = a.image.pixels[i * std::size_t(a.image.channels)];
    }
    const rain::Confusion c = rain::score_mask(on, alpha, job.settings);
    report.frames.emplace_back(path.filename().string(), c);
    report.overall += c;
    if (clean) {
      const auto frame = [&](const std::map<std::string, fs::path>& m, const std::string& dir, std::string_view flag) {
        const auto it = m.find(stem);
        if (it == m.end()) throw Error(fmt::format("{} {}: no frame named {}", flag, dir, stem));
        Image img = finite_image(codec, flag, it->second);
        if (img.width != p.image.width || img.height != p.image.height)
          throw Error(fmt::format("{} {}: {} is {}x{}, its mask {}x{}", flag, dir, it->second.filename().string(),
                                  img.width, img.height, p.image.width, p.image.height));
        return img;
      };
      const rain::RemovalError e =
          rain::removal_error(frame(*derained, *job.derained_dir, "--derained-dir"),
                              frame(*clean, *job.clean_dir, "--clean-dir"), alpha, job.settings);
      report.removal.push_back(e);
      if (!report.removal_overall) report.removal_overall.emplace();
      *report.removal_overall += e;
    }
  }
  if (report.frames.empty())
    throw Error(fmt::format("--pred-dir {}: no mask has a namesake in --truth-dir {}", job.pred_dir, job.truth_dir));
  if (job.plots_dir) {
    // The scores of every frame as CSV (undefined ratios empty), and the PR curves below where computed.
    plots.emplace(*job.plots_dir, "--plots-dir");
    const auto num = [](double v) { return std::isfinite(v) ? fmt::format("{:.6g}", v) : std::string(); };
    std::string csv = "name,precision,recall,f1,iou,true_positive,false_positive,false_negative,true_negative,ignored,"
                      "psnr_in_mask,psnr_out_mask\n";
    for (std::size_t k = 0; k <= report.frames.size(); ++k) {
      const bool all = k == report.frames.size();
      const rain::Confusion& c = all ? report.overall : report.frames[k].second;
      const rain::RemovalError* e = all ? (report.removal_overall ? &*report.removal_overall : nullptr)
                                        : (k < report.removal.size() ? &report.removal[k] : nullptr);
      csv += fmt::format("{},{},{},{},{},{},{},{},{},{},{},{}\n", all ? "overall" : report.frames[k].first,
                         num(c.precision()), num(c.recall()), num(c.f1()), num(c.iou()), c.true_positive,
                         c.false_positive, c.false_negative, c.true_negative, c.ignored,
                         e ? num(e->psnr_in()) : std::string(), e ? num(e->psnr_out()) : std::string());
    }
    plots->write("scores.csv", csv);
  }
  if (job.input_dir) {
    add_pr_curves(job, codec, masks_in(job.truth_dir, "--truth-dir"), report, progress);
    if (job.plots_dir) {
      std::string csv = "method,min_change_grey,precision,recall,f1,iou,true_positive,false_positive,false_negative\n";
      Plot plot;
      plot.title = "Rain detection over its threshold c (1 to 16 grey levels)";
      plot.x_label = "recall";
      plot.y_label = "precision";
      plot.x_tick = plot.y_tick = 0.1;
      plot.legend = LegendCorner::BottomLeft;
      const char* colours[] = {"#1f77b4", "#d62728", "#2ca02c"};
      double x_max = 0;
      for (std::size_t m = 0; m < report.pr.size(); ++m) {
        PlotSeries series{report.pr[m].first, {}, {}, colours[m % 3], m == 1};
        for (const auto& p : report.pr[m].second) {
          const auto& c = p.scores;
          csv += fmt::format("{},{:g},{:.6g},{:.6g},{:.6g},{:.6g},{},{},{}\n", report.pr[m].first, p.min_change_grey,
                             c.precision(), c.recall(), c.f1(), c.iou(), c.true_positive, c.false_positive,
                             c.false_negative);
          if (std::isnan(c.precision()) || std::isnan(c.recall())) continue;
          series.x.push_back(c.recall());
          series.y.push_back(c.precision());
          x_max = std::max(x_max, c.recall());
        }
        plot.series.push_back(std::move(series));
      }
      plot.x_max = std::max(0.05, std::ceil(x_max * 20 + 1e-9) / 20);
      plot.x_tick = plot.x_max <= 0.5 ? 0.05 : 0.1;
      plots->write("pr.svg", render_svg(plot));
      plots->write("pr.csv", csv);
    }
  }
  if (report_file) {
    report_file->write(eval_json(job, report));
    report_file->commit();
  }
  if (plots) plots->commit();
  return report;
}

std::string eval_json(const EvalJob& job, const EvalReport& r) {
  nlohmann::ordered_json j = {{"format", "hydrolux-rain-eval"},
                              {"format_version", 1},
                              {"rain_alpha", job.settings.rain_alpha},
                              {"ignore_alpha", job.settings.ignore_alpha},
                              {"overall", scores(r.overall)}};
  const auto psnr = [](double v) {
    return std::isnan(v) ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(std::isinf(v) ? 1e308 : v);
  };
  if (r.removal_overall) {
    j["overall"]["psnr_in_mask"] = psnr(r.removal_overall->psnr_in());
    j["overall"]["psnr_out_mask"] = psnr(r.removal_overall->psnr_out());
  }
  nlohmann::ordered_json frames = nlohmann::ordered_json::array();
  for (std::size_t k = 0; k < r.frames.size(); ++k) {
    nlohmann::ordered_json f = {{"name", r.frames[k].first}};
    f.update(scores(r.frames[k].second));
    if (k < r.removal.size()) {
      f["psnr_in_mask"] = psnr(r.removal[k].psnr_in());
      f["psnr_out_mask"] = psnr(r.removal[k].psnr_out());
    }
    frames.push_back(f);
  }
  j["frames"] = frames;
  j["unmatched"] = r.unmatched;
  if (!r.pr.empty()) {
    nlohmann::ordered_json curves = nlohmann::ordered_json::object();
    for (const auto& [method, points] : r.pr) {
      nlohmann::ordered_json list = nlohmann::ordered_json::array();
      for (const auto& p : points) {
        nlohmann::ordered_json q = {{"min_change_grey", p.min_change_grey}};
        q.update(scores(p.scores));
        list.push_back(q);
      }
      curves[method] = list;
    }
    j["pr_curve"] = curves;
  }
  return j.dump(1) + "\n";
}

}  // namespace hydrolux::io
