// hydrolux rain: physically based rain streaks over a photograph, a folder of frames or a video
// (rain/rain.hpp; docs/rain.md).
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "common.hpp"
#include "hydrolux/color/srgb.hpp"
#include "hydrolux/core/error.hpp"
#include "hydrolux/rain/rain.hpp"
#include "image_plugin.hpp"
#include "progress.hpp"
#include "video_plugin.hpp"

namespace hydrolux::cli {

namespace {

namespace fs = std::filesystem;

struct RainArgs {
  std::optional<std::string> image, input_dir, video, depth, depth_dir, output, output_dir, mask_out, mask_dir,
      layer_out, stats_json;
  double depth_scale_m = 0.001;
  std::optional<std::string> size;  // of --image builtin
  rain::RainSettings s;
  rain::RainCamera c;
  std::optional<double> fov_deg, fps, pixel_pitch_um;
  long long frame_index = 0;
  int crf = 18;
  bool no_unresolved = false;
  bool quiet = false;
};

std::string lower_extension(const fs::path& p) {
  std::string e = p.extension().string();
  std::transform(e.begin(), e.end(), e.begin(), [](unsigned char ch) { return char(std::tolower(ch)); });
  return e;
}

// Image files a folder of frames may hold, by extension.
bool is_frame_file(const fs::path& p) {
  const std::string e = lower_extension(p);
  return e == ".png" || e == ".jpg" || e == ".jpeg" || e == ".exr" || e == ".tif" || e == ".tiff" || e == ".hdr" ||
         e == ".ppm" || e == ".pfm";
}

// A depth map (io::depth_from_decoded), the JPEG refused before it is decoded.
Image read_depth(const std::string& flag, const std::string& path, double scale_m, int width, int height) {
  const ImageApi& images = image_api();
  const std::string bytes = io::read_file(path, io::ImageLimits{}.max_file_bytes, flag);
  const std::string origin = fmt::format("{} {}", flag, path);
  if (io::sniff_image_format(bytes) == io::ImageFormat::jpeg) throw Error(origin + io::kJpegDepthRefusal);
  auto decoded = images.decode_image(bytes, origin, io::ImageLimits{});
  for (const auto& w : decoded.warnings) warn(fmt::format("{}: {}", origin, w));
  return io::depth_from_decoded(decoded, scale_m, width, height, origin);
}

nlohmann::json stats_json(const rain::RainStats& s) {
  return {{"drops_total", s.drops_total},
          {"drops_in_view", s.drops_in_view},
          {"drops_visible", s.drops_visible},
          {"streak_length_px", {{"mean", s.streak_length_px_mean}, {"p50", s.streak_length_px_p50},
                                {"p95", s.streak_length_px_p95}, {"max", s.streak_length_px_max}}},
          {"streak_width_px", {{"mean", s.streak_width_px_mean}, {"max", s.streak_width_px_max}}},
          {"drop_luminance_mean", s.drop_luminance_mean},
          {"background_luminance_under_streaks", s.background_luminance_mean},
          {"streak_luminance_gain", s.streak_luminance_gain},
          {"streak_pixel_fraction", s.streak_pixel_fraction},
          {"alpha_mean", s.alpha_mean},
          {"unresolved_transmittance_mean", s.unresolved_transmittance_mean}};
}

nlohmann::json run_json(const RainArgs& a, const rain::RainField& field) {
  const auto& s = field.settings();
  const auto& c = field.camera();
  nlohmann::json classes = nlohmann::json::array();
  for (const auto& rc : field.classes())
    classes.push_back({{"radius_mm", {rc.radius_lo_m * 1e3, rc.radius_hi_m * 1e3}},
                       {"number_per_m3", rc.number_per_m3},
                       {"beta_per_m", rc.beta_per_m},
                       {"resolved_to_m", rc.resolved_to_m},
                       {"drops", rc.count}});
  return {{"program", "hydrolux rain"},
          {"seed", s.seed},
          {"rain", {{"rate_mmh", s.rate_mmh}, {"wind_mps", s.wind_mps}, {"wind_dir_deg", s.wind_dir_deg},
                    {"near_m", s.near_m}, {"far_m", s.far_m}, {"min_radius_mm", s.min_radius_mm},
                    {"max_radius_mm", s.max_radius_mm}, {"min_alpha", s.min_alpha}, {"extent_m", s.extent_m}, {"backdrop_m", s.backdrop_m},
                    {"oscillation", s.oscillation}, {"refractive_index", s.refractive_index},
                    {"unresolved", s.unresolved}, {"radius_classes", s.radius_classes}}},
          {"camera", {{"width", c.width}, {"height", c.height}, {"focal_mm", c.focal_mm},
                      {"sensor_width_mm", c.sensor_width_mm}, {"focal_px", c.focal_px()},
                      {"pixel_pitch_um", c.pixel_pitch_m() * 1e6}, {"f_number", c.f_number}, {"focus_m", c.focus_m},
                      {"exposure_s", c.exposure_s}, {"fps", c.fps}, {"height_m", c.height_m},
                      {"pitch_deg", c.pitch_deg}}},
          {"depth", a.depth       ? nlohmann::json(*a.depth)
                    : a.depth_dir ? nlohmann::json(*a.depth_dir)
                                  : nlohmann::json("ground plane")},
          {"field", {{"drops", field.drop_count()}, {"beta_total_per_m", field.beta_total_per_m()},
                     {"classes", classes}}}};
}

// 8-bit video frames <-> linear float images through the library's tables.
struct SrgbTables {
  color::Srgb8Tables tables;
  void to_linear(const VideoFrame& f, Image& img) const {
    if (img.width != f.width || img.height != f.height || img.channels != 3) img = Image(f.width, f.height, 3);
    tables.to_linear(f.rgb.data(), std::size_t(f.width) * f.height, img.pixels.data());
  }
  void to_srgb(const Image& img, VideoFrame& f) const {
    f.width = img.width;
    f.height = img.height;
    f.rgb.resize(std::size_t(img.width) * img.height * 3);
    tables.to_srgb8(img.pixels.data(), std::size_t(img.width) * img.height, img.channels, f.rgb.data());
  }
};

// The field, with the library's "too many drops" said in the CLI's flags.
rain::RainField make_field(const rain::RainSettings& s, const rain::RainCamera& c, bool ground_plane) {
  try {
    return rain::RainField(s, c, ground_plane);
  } catch (const rain::TooManyDrops& e) {
    throw Error(fmt::format("--min-alpha {:g}: the rain field would hold {:.3g} drops, more than the limit of {:.3g}; "
                            "raise --min-alpha, --near-m or --min-radius-mm, or lower --far-m or --rate-mmh",
                            s.min_alpha, e.drops(), double(rain::RainField::kMaxDrops)));
  }
}

rain::RainCamera camera_for(const RainArgs& a, int width, int height, std::optional<double> fps) {
  rain::RainCamera c = a.c;
  c.width = width;
  c.height = height;
  if (a.pixel_pitch_um) c.sensor_width_mm = *a.pixel_pitch_um * 1e-3 * width;
  if (a.fov_deg) c.focal_mm = rain::focal_mm_from_fov(*a.fov_deg, c.sensor_width_mm);
  if (fps) c.fps = *fps;
  // A long exposure for the default frame rate: never longer than the frame interval.
  return c;
}

void print_summary(const RainArgs& a, const rain::RainField& f, const rain::RainStats& st, std::size_t frames,
                   double seconds) {
  if (a.quiet) return;
  fmt::print(stderr,
             "rain: {} frame{} at {:g} mm/h; {} drops in the field, {} streaks in view (length p50 {:.1f} px, p95 "
             "{:.1f} px); drops {:.2f}x the luminance under them; {:.2f} s ({:.1f} frames/s)\n",
             frames, frames == 1 ? "" : "s", f.settings().rate_mmh, f.drop_count(), st.drops_in_view,
             st.streak_length_px_p50, st.streak_length_px_p95,
             st.background_luminance_mean > 0 ? st.drop_luminance_mean / st.background_luminance_mean : 0.0, seconds,
             seconds > 0 ? double(frames) / seconds : 0.0);
}

int run_image(const RainArgs& a) {
  io::FileSet files;
  const bool builtin = *a.image == "builtin";
  if (!builtin) files.input("--image", *a.image);
  if (a.size && !builtin) throw Error("--size: goes with --image builtin (a photograph has its own size)");
  if (a.depth) files.input("--depth", *a.depth);
  if (!a.output) throw Error("-o: give the output image (.png or .exr)");
  const ImageOutput out = declare_output_image(files, "-o", *a.output);
  std::optional<ImageOutput> mask, layer;
  if (a.mask_out) mask = declare_output_image(files, "--mask-out", *a.mask_out);
  if (a.layer_out) {
    layer = declare_output_image(files, "--layer-out", *a.layer_out);
    if (layer->format != io::ImageFormat::exr)
      throw Error(fmt::format("--layer-out {}: the rain layer is linear light; give an .exr file", *a.layer_out));
  }
  io::OutputFile* stats = a.stats_json ? &files.output("--stats-json", *a.stats_json) : nullptr;

  const auto start = std::chrono::steady_clock::now();
  Image frame;
  if (builtin) {
    const auto wh = parse_size(a.size.value_or("1280x720"));  // checked by the option's validator
    frame = rain::builtin_scene(camera_for(a, (*wh)[0], (*wh)[1], a.fps));
  } else {
    frame = read_input_image("--image", *a.image);
  }
  const rain::RainCamera cam = camera_for(a, frame.width, frame.height, a.fps);
  std::optional<Image> depth;
  if (a.depth) depth = read_depth("--depth", *a.depth, a.depth_scale_m, frame.width, frame.height);
  rain::RainSettings s = a.s;
  s.unresolved = !a.no_unresolved;
  rain::RainRenderer renderer(make_field(s, cam, !depth));
  rain::RainFrame result = renderer.render(frame, depth ? &*depth : nullptr, a.frame_index, layer.has_value());
  // The optional outputs first: a failure (a full disk) is then reported under their own flag.
  if (layer) write_output_image(*layer, result.layer);
  if (mask) mask->file->write(image_api().encode_image(io::coverage_for_encoding(result.alpha, mask->format), mask->format, io::PngOptions{16}));
  write_output_image(out, result.image);
  if (stats) {
    auto j = run_json(a, renderer.field());
    j["input"] = *a.image;
    j["frames"] = nlohmann::json::array({stats_json(result.stats)});
    j["frames"][0]["frame_index"] = a.frame_index;
    stats->write(j.dump(2) + "\n");
  }
  files.commit();
  print_summary(a, renderer.field(), result.stats, 1,
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  return 0;
}

int run_folder(const RainArgs& a) {
  if (a.output) throw Error("-o: with --input-dir the frames go to --output-dir");
  if (!a.output_dir) throw Error("--output-dir: give the folder for the rainy frames (with --input-dir)");
  if (a.depth) throw Error("--depth: one depth map serves one --image; give a folder's maps with --depth-dir");
  if (a.mask_out) throw Error("--mask-out: with --input-dir give --mask-dir for the masks");
  if (a.layer_out) throw Error("--layer-out: available with --image");
  const fs::path in_dir(*a.input_dir), out_dir(*a.output_dir);
  std::error_code ec;
  if (!fs::is_directory(in_dir, ec)) throw Error(fmt::format("--input-dir {}: not a folder", *a.input_dir));
  std::vector<fs::path> frames;
  for (const auto& e : fs::directory_iterator(in_dir, ec))
    if (e.is_regular_file() && is_frame_file(e.path()) && e.path().filename().string().front() != '.')
      frames.push_back(e.path());
  if (ec) throw Error(fmt::format("--input-dir {}: cannot list: {}", *a.input_dir, ec.message()));
  std::sort(frames.begin(), frames.end());
  if (frames.empty())
    throw Error(fmt::format("--input-dir {}: no image files (png, jpg, exr, tif, hdr, ppm, pfm)", *a.input_dir));
  // Each frame's output name (its own, as .exr or .png); two frames may not share one.
  std::vector<fs::path> out_names;
  {
    std::map<fs::path, fs::path> seen;
    for (const auto& f : frames) {
      fs::path name = f.filename();
      name.replace_extension(lower_extension(f) == ".exr" ? ".exr" : ".png");
      const auto [it, fresh] = seen.emplace(name, f.filename());
      if (!fresh)
        throw Error(fmt::format("--input-dir {}: {} and {} would both be written as {}", *a.input_dir,
                                it->second.string(), f.filename().string(), name.string()));
      out_names.push_back(name);
    }
  }
  // With --depth-dir: each frame's depth map, of the frame's stem as .exr or .png, found before any work.
  std::vector<fs::path> depth_files;
  if (a.depth_dir) {
    if (!fs::is_directory(*a.depth_dir, ec)) throw Error(fmt::format("--depth-dir {}: not a folder", *a.depth_dir));
    for (const auto& f : frames) {
      fs::path found;
      for (const char* ext : {".exr", ".png"}) {
        const fs::path candidate = fs::path(*a.depth_dir) / (f.stem().string() + ext);
        if (fs::exists(candidate, ec)) {
          found = candidate;
          break;
        }
      }
      if (found.empty())
        throw Error(fmt::format("--depth-dir {}: no depth map for {} ({}.exr or {}.png)", *a.depth_dir,
                                f.filename().string(), f.stem().string(), f.stem().string()));
      io::check_input_file(found, "--depth-dir");
      depth_files.push_back(found);
    }
  }
  for (const auto& [flag, dir] : {std::pair<const char*, std::optional<std::string>>{"--output-dir", a.output_dir},
                                  {"--mask-dir", a.mask_dir}}) {
    if (!dir) continue;
    if (fs::exists(*dir, ec) && io::same_file(*dir, in_dir))
      throw Error(fmt::format("{} {}: is the input folder; the frames would replace their inputs", flag, *dir));
    if (a.depth_dir && fs::exists(*dir, ec) && io::same_file(*dir, *a.depth_dir))
      throw Error(fmt::format("{} {}: is --depth-dir; the outputs could replace depth maps", flag, *dir));
    if (fs::exists(*dir, ec) && !fs::is_directory(*dir, ec))
      throw Error(fmt::format("{} {}: exists and is not a folder", flag, *dir));
  }
  if (a.mask_dir && io::same_file(*a.mask_dir, out_dir))
    throw Error(fmt::format("--mask-dir {}: is --output-dir; masks and frames share names", *a.mask_dir));
  io::FileSet files;
  io::OutputFile* stats = a.stats_json ? &files.output("--stats-json", *a.stats_json) : nullptr;
  fs::create_directories(out_dir, ec);
  if (ec) throw IoError(fmt::format("--output-dir {}: cannot create: {}", *a.output_dir, ec.message()));
  if (a.mask_dir) {
    fs::create_directories(*a.mask_dir, ec);
    if (ec) throw IoError(fmt::format("--mask-dir {}: cannot create: {}", *a.mask_dir, ec.message()));
  }

  const auto start = std::chrono::steady_clock::now();
  ProgressBar bar("rain", a.quiet);
  std::optional<rain::RainRenderer> renderer;
  rain::RainFrame result;
  nlohmann::json per_frame = nlohmann::json::array();
  const ImageApi& images = image_api();
  for (std::size_t k = 0; k < frames.size(); ++k) {
    const std::string name = frames[k].string();
    const Image frame = read_input_image("--input-dir", name);
    if (!renderer) {
      rain::RainSettings s = a.s;
      s.unresolved = !a.no_unresolved;
      renderer.emplace(make_field(s, camera_for(a, frame.width, frame.height, a.fps), !a.depth_dir));
    } else if (frame.width != renderer->field().camera().width || frame.height != renderer->field().camera().height) {
      throw Error(fmt::format("--input-dir: {} is {}x{}, unlike the first frame ({}x{}); one sequence has one size",
                              name, frame.width, frame.height, renderer->field().camera().width,
                              renderer->field().camera().height));
    }
    std::optional<Image> depth;
    if (a.depth_dir)
      depth = read_depth("--depth-dir", depth_files[k].string(), a.depth_scale_m, frame.width, frame.height);
    renderer->render_into(frame, depth ? &*depth : nullptr, a.frame_index + std::int64_t(k), false, result);
    const fs::path& out_name = out_names[k];
    const auto format = out_name.extension() == ".exr" ? io::ImageFormat::exr : io::ImageFormat::png;
    io::write_file(out_dir / out_name, images.encode_image(result.image, format, io::PngOptions{}), "--output-dir");
    if (a.mask_dir) {
      io::write_file(fs::path(*a.mask_dir) / out_name, images.encode_image(io::coverage_for_encoding(result.alpha, format), format,
                                                                    io::PngOptions{16}),
                     "--mask-dir");
    }
    if (stats) {
      auto j = stats_json(result.stats);
      j["frame_index"] = a.frame_index + std::int64_t(k);
      j["input"] = frames[k].filename().string();
      per_frame.push_back(std::move(j));
    }
    bar.update(double(k + 1) / double(frames.size()), fmt::format("frame {}/{}", k + 1, frames.size()));
  }
  bar.finish();
  if (stats) {
    auto j = run_json(a, renderer->field());
    j["input"] = *a.input_dir;
    j["frames"] = std::move(per_frame);
    stats->write(j.dump(2) + "\n");
  }
  files.commit();
  print_summary(a, renderer->field(), result.stats, frames.size(),
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  return 0;
}

int run_video(const RainArgs& a) {
  if (!a.output) throw Error("-o: give the output video (.mp4, .mov or .mkv)");
  if (a.depth || a.depth_dir) throw Error("--depth: depth maps are for --image and --input-dir; video frames use the ground plane");
  if (a.mask_out || a.mask_dir || a.layer_out || a.output_dir)
    throw Error("--video writes one video (-o) and optionally --stats-json; masks are for --image and --input-dir");
  if (a.fps) throw Error("--fps: a video's frame rate is its own");
  const std::string ext = lower_extension(*a.output);
  if (std::find(std::begin(kVideoExtensions), std::end(kVideoExtensions), ext) == std::end(kVideoExtensions))
    throw Error(fmt::format("-o {}: expected a .mp4, .mov or .mkv file", *a.output));
  io::FileSet files;
  files.input("--video", *a.video);
  io::OutputFile& out = files.output("-o", *a.output);
  io::OutputFile* stats = a.stats_json ? &files.output("--stats-json", *a.stats_json) : nullptr;
  const VideoApi& api = video_api();
  const io::InputFile input(*a.video, "--video");

  const auto start = std::chrono::steady_clock::now();
  auto reader = api.open_reader([&input](std::uint64_t off, char* buf, std::size_t n) { return input.read_at(off, buf, n); },
                                input.size(), fmt::format("--video {}", *a.video), VideoLimits{});
  const VideoInfo info = reader->info();
  rain::RainSettings s = a.s;
  s.unresolved = !a.no_unresolved;
  rain::RainRenderer renderer(make_field(s, camera_for(a, info.width, info.height, info.fps()), true));
  auto writer = api.open_writer([&out](std::uint64_t off, std::string_view bytes) { out.write_at(off, bytes); }, ext,
                                info, a.crf, fmt::format("-o {}", *a.output));
  const SrgbTables tables;
  ProgressBar bar("rain", a.quiet);
  VideoFrame in_frame, out_frame;
  Image linear;
  rain::RainFrame result;
  nlohmann::json per_frame = nlohmann::json::array();
  std::int64_t k = 0;
  // The frame count for the progress: the container's, else the duration times the rate (Matroska).
  const std::int64_t expected = info.frame_count > 0 ? info.frame_count
                                : info.duration_s > 0 ? std::llround(info.duration_s * info.fps())
                                                      : -1;
  while (reader->read(in_frame)) {
    tables.to_linear(in_frame, linear);
    renderer.render_into(linear, nullptr, a.frame_index + k, false, result);
    tables.to_srgb(result.image, out_frame);
    writer->write(out_frame);
    if (stats) {
      auto j = stats_json(result.stats);
      j["frame_index"] = a.frame_index + k;
      per_frame.push_back(std::move(j));
    }
    ++k;
    if (expected > 0)
      bar.update(std::min(1.0, double(k) / double(expected)), fmt::format("frame {}/{}", k, expected));
  }
  writer->finish();
  bar.finish();
  if (stats) {
    auto j = run_json(a, renderer.field());
    j["input"] = *a.video;
    j["video"] = {{"codec", info.codec}, {"fps_num", info.fps_num}, {"fps_den", info.fps_den}, {"frames", k},
                  {"crf", a.crf}};
    j["frames"] = std::move(per_frame);
    stats->write(j.dump(2) + "\n");
  }
  files.commit();
  print_summary(a, renderer.field(), result.stats, std::size_t(k),
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  return 0;
}

int run_rain(const RainArgs& a) {
  const int modes = int(a.image.has_value()) + int(a.input_dir.has_value()) + int(a.video.has_value());
  if (modes != 1) throw Error("give exactly one of --image, --input-dir and --video");
  if (a.output_dir && !a.input_dir) throw Error("--output-dir: goes with --input-dir");
  if (a.mask_dir && !a.input_dir) throw Error("--mask-dir: goes with --input-dir (use --mask-out with --image)");
  if (a.depth_dir && !a.input_dir) throw Error("--depth-dir: goes with --input-dir (use --depth with --image)");
  if (a.image) return run_image(a);
  if (a.input_dir) return run_folder(a);
  return run_video(a);
}

}  // namespace

Command add_rain(CLI::App& app) {
  auto a = std::make_shared<RainArgs>();
  auto* sub = app.add_subcommand(
      "rain",
      "Rain over a photograph, a folder of frames or a video: drops drawn from Marshall-Palmer for the rain rate, "
      "falling at their terminal velocity with the wind, each seen through Garg & Nayar's drop model lit by the frame "
      "itself and smeared by the exposure into a streak; hidden behind nearer scene geometry (--depth, else a ground "
      "plane); unresolved distant rain as extinction and airlight. Deterministic for a --seed (docs/rain.md).");
  auto& s = a->s;
  auto& c = a->c;
  sub->add_option("--image", a->image, "Input photograph (PNG, JPEG, EXR, TIFF, ...), or 'builtin' for the built-in street scene");
  sub->add_option("--size", a->size, "Size WxH of --image builtin [1280x720]")->check(size_validator());
  sub->add_option("--input-dir", a->input_dir, "A folder of frames in name order: one rain field across them");
  sub->add_option("--video", a->video, "Input video (MP4, MOV, MKV, ...); frame rate and count are kept");
  sub->add_option("-o,--output", a->output, "Output: .png/.exr with --image, .mp4/.mov/.mkv with --video");
  sub->add_option("--output-dir", a->output_dir, "Output folder for --input-dir (created; never the input folder)");
  sub->add_option("--depth", a->depth, "Depth map for --image: camera z in metres (EXR), or a 16-bit PNG times --depth-scale-m; 0/inf = sky");
  sub->add_option("--depth-dir", a->depth_dir, "Depth maps for --input-dir: each frame's stem as .exr or .png (as --depth)");
  sub->add_option("--depth-scale-m", a->depth_scale_m, "Metres per code of a PNG depth map")
      ->check(number_in(1e-6, 1e3, "m"))->capture_default_str();
  sub->add_option("--mask-out", a->mask_out, "The rain's alpha for --image: .png (16-bit linear) or .exr; rainy = clear (1 - alpha) + layer");
  sub->add_option("--mask-dir", a->mask_dir, "Folder for the masks of --input-dir (same names as the frames)");
  sub->add_option("--layer-out", a->layer_out, "The rain layer for --image as a premultiplied RGBA .exr (linear)");
  sub->add_option("--stats-json", a->stats_json, "Parameters, seed, the field and per-frame statistics as JSON");
  sub->add_option("--rate-mmh", s.rate_mmh, "Rain rate, mm/h")->check(number_in(0, 500, "mm/h"))->capture_default_str();
  sub->add_option("--wind-mps", s.wind_mps, "Horizontal wind speed, m/s (drops move with it)")
      ->check(number_in(0, 50, "m/s"))->capture_default_str();
  sub->add_option("--wind-dir-deg", s.wind_dir_deg, "Where the wind blows to: 0 away from the camera, 90 to its right")
      ->check(number_in(-360, 360, "deg"))->capture_default_str();
  sub->add_option("--exposure-s", c.exposure_s, "Exposure time, s (at most 1 / fps)")
      ->check(number_in(1e-6, 1, "s"))->capture_default_str();
  auto* focal = sub->add_option("--focal-mm", c.focal_mm, "Focal length, mm")->check(number_in(1, 2000, "mm"))->capture_default_str();
  sub->add_option("--fov-deg", a->fov_deg, "Horizontal field of view, degrees (instead of --focal-mm)")
      ->check(number_in(1, 170, "deg"))->excludes(focal);
  auto* sensor = sub->add_option("--sensor-width-mm", c.sensor_width_mm, "Sensor width, mm (pixel pitch = width / image width)")
      ->check(number_in(1, 100, "mm"))->capture_default_str();
  sub->add_option("--pixel-pitch-um", a->pixel_pitch_um, "Pixel pitch, um (instead of --sensor-width-mm)")
      ->check(number_in(0.1, 1000, "um"))->excludes(sensor);
  sub->add_option("--f-number", c.f_number, "Aperture f-number for defocus of near drops; 0 = pinhole (all sharp)")
      ->check(number_in(0, 64))->capture_default_str();
  sub->add_option("--focus-m", c.focus_m, "Focus distance, m (with --f-number)")->check(number_in(0.01, 1e4, "m"))->capture_default_str();
  sub->add_option("--fps", a->fps, "Frame rate of --image / --input-dir frames (frame k is exposed from k / fps) [25]")
      ->check(number_in(1, 1000, "1/s"));
  sub->add_option("--frame-index", a->frame_index, "Index of the first frame in the rain field's time")
      ->transform(integer_in(0, 1000000000))->capture_default_str();
  sub->add_option("--camera-height-m", c.height_m, "Camera height above the ground plane, m")
      ->check(number_in(0, 1000, "m"))->capture_default_str();
  sub->add_option("--pitch-deg", c.pitch_deg, "Camera pitch above the horizon, degrees")
      ->check(number_in(-80, 80, "deg"))->capture_default_str();
  sub->add_option("--near-m", s.near_m, "No drop nearer than this, m")->check(number_in(0.05, 100, "m"))->capture_default_str();
  sub->add_option("--far-m", s.far_m, "No drop drawn beyond this, m (farther rain is unresolved)")
      ->check(number_in(0.1, 1e4, "m"))->capture_default_str();
  sub->add_option("--min-radius-mm", s.min_radius_mm, "Smaller drops count only as unresolved rain, mm")
      ->check(number_in(0.04, 2.9, "mm"))->capture_default_str();
  sub->add_option("--max-radius-mm", s.max_radius_mm, "Largest drop radius, mm (larger drops break up)")
      ->check(number_in(0.04, 2.9, "mm"))->capture_default_str();
  sub->add_option("--min-alpha", s.min_alpha, "A drop is drawn while its streak's peak coverage reaches this; fainter rain is unresolved")
      ->check(number_in(1e-5, 0.5))->capture_default_str();
  sub->add_option("--extent-m", s.extent_m, "Depth of the rain where the depth map has none (sky), m")
      ->check(number_in(0, 1e5, "m"))->capture_default_str();
  sub->add_option("--backdrop-m", s.backdrop_m, "Without --depth: the scene is the ground plane up to a backdrop this far, m")
      ->check(number_in(1, 1e5, "m"))->capture_default_str();
  sub->add_option("--oscillation", s.oscillation, "Relative amplitude of the drops' shape oscillation (Rayleigh mode 2); 0 off")
      ->check(number_in(0, 0.5))->capture_default_str();
  sub->add_flag("--no-unresolved", a->no_unresolved, "Leave out the unresolved rain's extinction and airlight (streaks only)");
  sub->add_option("--seed", s.seed, "Random seed: the same seed gives the same rain, bytes for bytes")
      ->transform(integer_in(0, 1LL << 53))->capture_default_str();
  sub->add_option("--crf", a->crf, "H.264 quality of --video's output (0 lossless .. 51; 18 visually lossless)")
      ->transform(integer_in(0, 51))->capture_default_str();
  sub->add_flag("-q,--quiet", a->quiet, "No progress or summary on stderr");
  return {sub,
          [a] { return run_rain(*a); },
          {{"rate_mmh", "--rate-mmh"},
           {"wind_mps", "--wind-mps"},
           {"wind_dir_deg", "--wind-dir-deg"},
           {"near_m", "--near-m"},
           {"far_m", "--far-m"},
           {"min_radius_mm", "--min-radius-mm"},
           {"max_radius_mm", "--max-radius-mm"},
           {"min_alpha", "--min-alpha"},
           {"extent_m", "--extent-m"},
           {"backdrop_m", "--backdrop-m"},
           {"oscillation", "--oscillation"},
           {"width", "the input's width"},
           {"height", "the input's height"},
           {"focal_mm", "--focal-mm"},
           {"fov_deg", "--fov-deg"},
           {"sensor_width_mm", "--sensor-width-mm (or --pixel-pitch-um x the image width)"},
           {"f_number", "--f-number"},
           {"focus_m", "--focus-m"},
           {"fps", "--fps"},
           {"exposure_s", "--exposure-s"},
           {"height_m", "--camera-height-m"},
           {"pitch_deg", "--pitch-deg"}}};
}

}  // namespace hydrolux::cli
