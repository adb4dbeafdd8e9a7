// A fog run over files (fog_job.hpp): the photograph and folder modes of `hydrolux fog`.
#include "hydrolux/io/fog_job.hpp"

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "hydrolux/core/error.hpp"
#include "hydrolux/io/files.hpp"
#include "hydrolux/io/frames.hpp"
#include "hydrolux/rain/rain.hpp"

namespace hydrolux::io {

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

struct Run {
  const FogJob& a;
  const FogJobHooks& h;
  Clock::time_point start = Clock::now();

  void warn(const std::string& text) const {
    if (h.warn) h.warn(text);
  }
  // A frame; one too large for the memory left is refused from its header, before its pixels are
  // decoded, naming what would fit.
  Image read_image(const std::string& flag, const std::string& path) const {
    const std::string bytes = read_file(path, ImageLimits{}.max_file_bytes, flag);
    const std::string origin = fmt::format("{} {}", flag, path);
    ImageLimits limits;
    limits.before_pixels = [&](std::int64_t width, std::int64_t height, std::int64_t channels) {
      rain::check_fog_memory(origin, int(width), int(height), int(channels), a.options.settings.glow);
    };
    auto decoded = h.codec.decode(bytes, origin, limits);
    for (const auto& w : decoded.warnings) warn(fmt::format("{}: {}", origin, w));
    return std::move(decoded.image);
  }
  Image read_depth(const std::string& flag, const std::string& path, int width, int height) const {
    const std::string bytes = read_file(path, ImageLimits{}.max_file_bytes, flag);
    const std::string origin = fmt::format("{} {}", flag, path);
    const auto format = sniff_image_format(bytes);
    if (format == ImageFormat::jpeg) throw Error(origin + kJpegDepthRefusal);
    if (a.depth_scale_given && (format == ImageFormat::exr || format == ImageFormat::hdr))
      throw Error(fmt::format("--depth-scale-m: scales the codes of a PNG depth map; {} holds metres already", origin));
    auto decoded = h.codec.decode(bytes, origin, ImageLimits{});
    for (const auto& w : decoded.warnings) warn(fmt::format("{}: {}", origin, w));
    return depth_from_decoded(decoded, a.files.depth_scale_m, width, height, origin);
  }
  PngOptions png(int bits) const { return PngOptions{bits, a.files.png_compression}; }
};

// The library's quantity names -> the flags (a DomainError from validate() names the quantity).
rain::FogOptics optics_for(const FogJob& a) {
  const auto& s = a.options.settings;
  if (!s.visibility_m && !s.lwc_g_m3)
    throw Error("--visibility-m: give the fog's visibility in metres (Koschmieder), or --lwc-g-m3 for Mie over the droplets");
  return rain::fog_optics(s);
}

rain::FogFrame render(const Image& frame, const Image* depth, const rain::RainCamera& cam, const FogJob& a,
                      const rain::FogOptics& optics, const std::optional<Vec3>& sky, const std::string& origin) {
  try {
    return rain::render_fog(frame, depth, cam, a.options.settings, optics, sky);
  } catch (const DomainError&) {
    throw;
  } catch (const Error& e) {
    throw Error(fmt::format("{}: {}", origin, e.what()));
  }
}

nlohmann::json stats_json(const rain::FogStats& st) {
  return {{"transmittance", {{"mean", st.transmittance_mean}, {"min", st.transmittance_min}, {"max", st.transmittance_max}}},
          {"range_m_median", st.range_m_median},
          {"sky_fraction", st.sky_fraction},
          {"sky_rgb", {st.sky[0], st.sky[1], st.sky[2]}},
          {"glow_luminance_mean", st.glow_mean},
          {"glow_source_fraction", st.glow_source_fraction},
          {"negative_values_clamped", st.negative_values_clamped}};
}

nlohmann::json run_json(const FogJob& a, const rain::FogOptics& o, const rain::RainCamera& cam) {
  const auto& s = a.options.settings;
  const auto num = [](double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); };
  return {{"fog",
           {{"route", s.visibility_m ? "koschmieder" : "mie"},
            {"beta_per_m", o.beta_per_m},
            {"visibility_m", o.visibility_m},
            {"lwc_g_m3", num(o.lwc_g_m3)},
            {"number_per_cm3", num(o.number_per_cm3)},
            {"mode_radius_um", s.mode_radius_um},
            {"size_alpha", s.size_alpha},
            {"effective_radius_um", o.effective_radius_um},
            {"asymmetry_g", o.g},
            {"wavelength_nm", s.wavelength_nm},
            {"glow", s.glow}}},
          {"camera",
           {{"width", cam.width},
            {"height", cam.height},
            {"focal_mm", cam.focal_mm},
            {"sensor_width_mm", cam.sensor_width_mm},
            {"height_m", cam.height_m},
            {"pitch_deg", cam.pitch_deg}}},
          {"depth", a.depth ? *a.depth : a.depth_dir ? *a.depth_dir : fmt::format("ground plane, backdrop {:g} m", s.backdrop_m)}};
}

struct ImageOut {
  OutputFile* file;
  ImageFormat format;
};
ImageOut declare_image(FileSet& files, const std::string& flag, const std::string& path) {
  const ImageFormat format = output_image_format(path, flag);
  return {&files.output(flag, path), format};
}

FogJobResult run_image(const Run& run) {
  const FogJob& a = run.a;
  if (a.depth_scale_given && !a.depth) throw Error("--depth-scale-m: scales a PNG --depth map; none is given");
  FileSet files;
  files.input("--image", *a.image);
  if (a.depth) files.input("--depth", *a.depth);
  if (!a.output) throw Error("-o: give the output image (.png or .exr)");
  const ImageOut out = declare_image(files, "-o", *a.output);
  std::optional<ImageOut> mask;
  if (a.mask_out) mask = declare_image(files, "--mask-out", *a.mask_out);
  OutputFile* stats = a.stats_json ? &files.output("--stats-json", *a.stats_json) : nullptr;
  const rain::FogOptics optics = optics_for(a);
  const Image frame = run.read_image("--image", *a.image);
  const rain::RainCamera cam = rain::fog_camera_for(a.options, frame.width, frame.height);
  std::optional<Image> depth;
  if (a.depth) depth = run.read_depth("--depth", *a.depth, frame.width, frame.height);
  const rain::FogFrame result = render(frame, depth ? &*depth : nullptr, cam, a, optics, std::nullopt, "--image " + *a.image);
  if (result.stats.negative_values_clamped > 0)
    run.warn(fmt::format("--image {}: {} negative values read as 0 (light cannot be negative)", *a.image,
                         result.stats.negative_values_clamped));
  if (mask)
    mask->file->write(run.h.codec.encode(coverage_for_encoding(result.alpha, mask->format), mask->format, run.png(16)));
  out.file->write(run.h.codec.encode(result.image, out.format, run.png(8)));
  if (stats) {
    auto j = run_json(a, optics, cam);
    j["input"] = *a.image;
    j["frames"] = nlohmann::json::array({stats_json(result.stats)});
    stats->write(j.dump(2) + "\n");
  }
  files.commit();
  FogJobResult r;
  r.frames = r.frames_total = 1;
  r.optics = optics;
  r.last = result.stats;
  r.seconds = std::chrono::duration<double>(Clock::now() - run.start).count();
  return r;
}

FogJobResult run_folder(const Run& run) {
  const FogJob& a = run.a;
  if (a.output) throw Error("-o: with --input-dir the frames go to --output-dir");
  if (!a.output_dir) throw Error("--output-dir: give the folder for the foggy frames (with --input-dir)");
  if (a.depth) throw Error("--depth: one depth map serves one --image; give a folder's maps with --depth-dir");
  if (a.mask_out) throw Error("--mask-out: with --input-dir give --mask-dir for the masks");
  if (a.depth_scale_given && !a.depth_dir) throw Error("--depth-scale-m: scales PNG maps of --depth-dir; none is given");
  const FrameFolderRequest request{*a.input_dir, *a.output_dir, a.mask_dir, a.depth_dir};
  const FrameFolder plan = plan_frame_folder(request);
  if (!plan.skipped.empty()) run.warn(plan.skipped_warning(*a.input_dir));
  const fs::path out_dir(*a.output_dir);
  const auto& frames = plan.frames;
  FileSet files;
  declare_frame_folder(files, plan, request);
  OutputFile* stats = a.stats_json ? &files.output("--stats-json", *a.stats_json) : nullptr;
  const rain::FogOptics optics = optics_for(a);
  create_output_folders(request);
  // A frame that cannot be used is named and left out once one frame is written (as rain does); the
  // first frame's failure is bad input, nothing written.
  FogJobResult r;
  r.optics = optics;
  r.frames_total = frames.size();
  std::optional<Vec3> sky;
  std::optional<rain::RainCamera> cam;
  nlohmann::json per_frame = nlohmann::json::array();
  for (std::size_t k = 0; k < frames.size(); ++k) {
    const std::string name = frames[k].string();
    try {
      const Image frame = run.read_image("--input-dir", name);
      if (!cam) {
        cam = rain::fog_camera_for(a.options, frame.width, frame.height);
      } else if (frame.width != cam->width || frame.height != cam->height) {
        throw IoError(fmt::format("--input-dir {}: is {}x{}, unlike the first frame ({}x{}); one sequence has one size", name,
                                  frame.width, frame.height, cam->width, cam->height));
      }
      std::optional<Image> depth;
      if (a.depth_dir) depth = run.read_depth("--depth-dir", plan.depth_maps[k].string(), frame.width, frame.height);
      const rain::FogFrame result = render(frame, depth ? &*depth : nullptr, *cam, a, optics, sky, "--input-dir " + name);
      if (!sky) sky = result.stats.sky;  // one sky for the sequence: no flicker from frame to frame
      const fs::path& out_name = plan.outputs[k];
      const auto format = out_name.extension() == ".exr" ? ImageFormat::exr : ImageFormat::png;
      write_file(out_dir / out_name, run.h.codec.encode(result.image, format, run.png(8)), "--output-dir");
      if (a.mask_dir)
        write_file(fs::path(*a.mask_dir) / out_name,
                   run.h.codec.encode(coverage_for_encoding(result.alpha, format), format, run.png(16)), "--mask-dir");
      ++r.frames;
      r.last = result.stats;
      if (stats) {
        auto j = stats_json(result.stats);
        j["input"] = frames[k].filename().string();
        per_frame.push_back(std::move(j));
      }
    } catch (const IoFailure&) {
      throw;
    } catch (const Error& e) {
      if (r.frames == 0) throw;
      run.warn(fmt::format("{} (left out)", e.what()));
      r.left_out.push_back(frames[k].filename().string());
    }
    if (run.h.progress) run.h.progress(double(k + 1) / double(frames.size()), fmt::format("frame {}/{}", k + 1, frames.size()));
  }
  if (run.h.finish_progress) run.h.finish_progress();
  if (stats && cam) {
    auto j = run_json(a, optics, *cam);
    j["input_dir"] = *a.input_dir;
    j["frames"] = std::move(per_frame);
    stats->write(j.dump(2) + "\n");
  }
  files.commit();
  r.seconds = std::chrono::duration<double>(Clock::now() - run.start).count();
  return r;
}

}  // namespace

FogJobResult run_fog_job(const FogJob& a, const FogJobHooks& hooks) {
  if (int(a.image.has_value()) + int(a.input_dir.has_value()) != 1) throw Error("give exactly one of --image and --input-dir");
  if (a.output_dir && !a.input_dir) throw Error("--output-dir: goes with --input-dir");
  if (a.mask_dir && !a.input_dir) throw Error("--mask-dir: goes with --input-dir (use --mask-out with --image)");
  if (a.depth_dir && !a.input_dir) throw Error("--depth-dir: goes with --input-dir (use --depth with --image)");
  rain::fog_param("png_compression").check(double(a.files.png_compression));
  const Run run{a, hooks, Clock::now()};
  return a.image ? run_image(run) : run_folder(run);
}

std::string fog_summary(const FogJobResult& r) {
  const auto& st = r.last;
  return fmt::format(
      "fog: {} frame{}; beta {:.4g} /m (visibility {:.4g} m); transmittance mean {:.3f} (min {:.3f}); sky ({:.3g}, {:.3g}, "
      "{:.3g}); glow {:.3g} mean luminance; {:.2f} s",
      r.frames, r.frames == 1 ? "" : "s", r.optics.beta_per_m, r.optics.visibility_m, st.transmittance_mean,
      st.transmittance_min, st.sky[0], st.sky[1], st.sky[2], st.glow_mean, r.seconds);
}

}  // namespace hydrolux::io
