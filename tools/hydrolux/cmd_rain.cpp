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
#include "hydrolux/core/memory.hpp"
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
  // Flags whose defaults mean nothing in some modes: given by the user, they must be used.
  bool crf_given = false, depth_scale_given = false;
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

// A depth map (io::depth_from_decoded), the JPEG refused before it is decoded. --depth-scale-m, if
// given, must have a coded map (PNG, TIFF, PNM) to scale: an EXR holds metres.
Image read_depth(const RainArgs& a, const std::string& flag, const std::string& path, int width, int height) {
  const ImageApi& images = image_api();
  const std::string bytes = io::read_file(path, io::ImageLimits{}.max_file_bytes, flag);
  const std::string origin = fmt::format("{} {}", flag, path);
  const auto format = io::sniff_image_format(bytes);
  if (format == io::ImageFormat::jpeg) throw Error(origin + io::kJpegDepthRefusal);
  if (a.depth_scale_given && (format == io::ImageFormat::exr || format == io::ImageFormat::hdr))
    throw Error(fmt::format("--depth-scale-m: scales the codes of a PNG depth map; {} holds metres already", origin));
  const double scale_m = a.depth_scale_m;
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
          {"unresolved_transmittance_mean", s.unresolved_transmittance_mean},
          {"negative_values_clamped", s.negative_values_clamped}};
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
  return c;
}

// Refuses a frame size whose rendering would not fit in the memory available now, before any work.
void check_memory(const rain::RainCamera& c, int input_channels, bool with_layer, const std::string& what) {
  const double need = double(rain::estimated_render_bytes(c, input_channels, with_layer));
  const double avail = double(available_memory_bytes());
  if (need <= avail) return;
  // What grows with the pixels scales; the program and the drops do not.
  rain::RainCamera none = c;
  none.width = none.height = 0;
  const double fixed = double(rain::estimated_render_bytes(none, input_channels, with_layer));
  const double scale = std::sqrt(std::max(0.0, avail - fixed) / (need - fixed));
  throw Error(fmt::format("{}: rain over {}x{} needs about {} of memory and {} is available; about {}x{} would fit",
                          what, c.width, c.height, format_bytes(need), format_bytes(avail),
                          int(std::floor(c.width * scale)), int(std::floor(c.height * scale))));
}

// One frame rendered: a non-finite input value is bad input naming the frame.
void render_frame(rain::RainRenderer& renderer, const Image& frame, const Image* depth, std::int64_t index,
                  bool with_layer, rain::RainFrame& out, const std::string& origin) {
  try {
    renderer.render_into(frame, depth, index, with_layer, out);
  } catch (const rain::NonFinitePixel& e) {
    throw Error(fmt::format("{}: {}", origin, e.what()));
  }
}

// The negative input values read as 0 over a run, said once at its end (not a line a frame).
struct NegativeValues {
  std::uint64_t values = 0, frames = 0;
  void add(const rain::RainStats& st) {
    values += st.negative_values_clamped;
    frames += st.negative_values_clamped > 0 ? 1 : 0;
  }
  void report(const std::string& origin, std::size_t frame_count) const {
    if (values == 0) return;
    warn(frame_count > 1 ? fmt::format("{}: {} negative value{} in {} of {} frames read as 0 (light cannot be negative)",
                                       origin, values, values == 1 ? "" : "s", frames, frame_count)
                         : fmt::format("{}: {} negative value{} read as 0 (light cannot be negative)", origin,
                                       values, values == 1 ? "" : "s"));
  }
};

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
  if (a.crf_given) throw Error("--crf: sets the H.264 quality of --video's output; --image writes one picture");
  if (a.depth_scale_given && !a.depth) throw Error("--depth-scale-m: scales a PNG --depth map; none is given");
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
    const std::string size = a.size.value_or("1280x720");
    const auto wh = parse_size(size);  // checked by the option's validator
    const rain::RainCamera c = camera_for(a, (*wh)[0], (*wh)[1], a.fps);
    check_memory(c, 3, layer.has_value(), "--size " + size);
    frame = rain::builtin_scene(c);
  } else {
    frame = read_input_image("--image", *a.image);
  }
  const rain::RainCamera cam = camera_for(a, frame.width, frame.height, a.fps);
  if (!builtin) check_memory(cam, frame.channels, layer.has_value(), "--image " + *a.image);
  std::optional<Image> depth;
  if (a.depth) depth = read_depth(a, "--depth", *a.depth, frame.width, frame.height);
  rain::RainSettings s = a.s;
  s.unresolved = !a.no_unresolved;
  rain::RainRenderer renderer(make_field(s, cam, !depth));
  rain::RainFrame result;
  const std::string origin = builtin ? std::string("--image builtin") : "--image " + *a.image;
  render_frame(renderer, frame, depth ? &*depth : nullptr, a.frame_index, layer.has_value(), result, origin);
  NegativeValues negatives;
  negatives.add(result.stats);
  negatives.report(origin, 1);
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

// The frames of --input-dir in name order: regular files (through links) with an image extension.
// Entries with such a name that cannot be read as a file (a FIFO, a device, a folder, a dangling link)
// are left out and listed in one warning line, never skipped without a word.
std::vector<fs::path> list_frames(const std::string& input_dir) {
  const fs::path in_dir(input_dir);
  std::error_code ec;
  if (!fs::is_directory(in_dir, ec)) throw Error(fmt::format("--input-dir {}: not a folder", input_dir));
  std::vector<fs::path> frames;
  std::vector<std::string> skipped;
  for (const auto& e : fs::directory_iterator(in_dir, ec)) {
    const std::string name = e.path().filename().string();
    if (!is_frame_file(e.path()) || name.front() == '.') continue;
    std::error_code kind_ec;
    const fs::file_status st = fs::status(e.path(), kind_ec);
    if (fs::is_regular_file(st)) {
      frames.push_back(e.path());
      continue;
    }
    const char* kind = !fs::exists(st)           ? "dangling link"
                       : fs::is_directory(st)    ? "folder"
                       : fs::is_fifo(st)         ? "FIFO"
                       : fs::is_socket(st)       ? "socket"
                       : fs::is_block_file(st) || fs::is_character_file(st) ? "device"
                                                                              : "not a regular file";
    skipped.push_back(fmt::format("{} ({})", name, kind));
  }
  if (ec) throw Error(fmt::format("--input-dir {}: cannot list: {}", input_dir, ec.message()));
  std::sort(frames.begin(), frames.end());
  std::sort(skipped.begin(), skipped.end());
  if (!skipped.empty()) {
    std::string list;
    for (const auto& k : skipped) list += (list.empty() ? "" : ", ") + k;
    warn(fmt::format("--input-dir {}: skipped {} entr{} that {} not regular files: {}", input_dir, skipped.size(),
                     skipped.size() == 1 ? "y" : "ies", skipped.size() == 1 ? "is" : "are", list));
  }
  if (frames.empty())
    throw Error(fmt::format("--input-dir {}: no image files (png, jpg, exr, tif, hdr, ppm, pfm)", input_dir));
  return frames;
}

int run_folder(const RainArgs& a) {
  if (a.output) throw Error("-o: with --input-dir the frames go to --output-dir");
  if (!a.output_dir) throw Error("--output-dir: give the folder for the rainy frames (with --input-dir)");
  if (a.depth) throw Error("--depth: one depth map serves one --image; give a folder's maps with --depth-dir");
  if (a.mask_out) throw Error("--mask-out: with --input-dir give --mask-dir for the masks");
  if (a.layer_out) throw Error("--layer-out: available with --image");
  if (a.crf_given) throw Error("--crf: sets the H.264 quality of --video's output; --input-dir writes pictures");
  if (a.depth_scale_given && !a.depth_dir) throw Error("--depth-scale-m: scales PNG maps of --depth-dir; none is given");
  const fs::path in_dir(*a.input_dir), out_dir(*a.output_dir);
  std::error_code ec;
  const std::vector<fs::path> frames = list_frames(*a.input_dir);
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
        if (fs::exists(fs::symlink_status(candidate, ec))) {
          found = candidate;
          break;
        }
      }
      if (found.empty())
        throw Error(fmt::format("--depth-dir {}: no depth map for {} ({}.exr or {}.png)", *a.depth_dir,
                                f.filename().string(), f.stem().string(), f.stem().string()));
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
  // Every file the run reads or writes, declared before any work: the frames and depth maps as inputs,
  // each frame's output and mask as planned outputs, the statistics as an output. An output on an
  // input (a --stats-json naming a frame, a link in --output-dir to a frame) or two outputs on one
  // path are refused here, whichever folders they are in.
  io::FileSet files;
  for (const auto& f : frames) files.input("--input-dir", f);
  for (const auto& d : depth_files) files.input("--depth-dir", d);
  for (const auto& n : out_names) files.planned_output("--output-dir", out_dir / n);
  if (a.mask_dir)
    for (const auto& n : out_names) files.planned_output("--mask-dir", fs::path(*a.mask_dir) / n);
  io::OutputFile* stats = a.stats_json ? &files.output("--stats-json", *a.stats_json) : nullptr;
  fs::create_directories(out_dir, ec);
  if (ec) throw IoError(fmt::format("--output-dir {}: cannot create: {}", *a.output_dir, ec.message()));
  if (a.mask_dir) {
    fs::create_directories(*a.mask_dir, ec);
    if (ec) throw IoError(fmt::format("--mask-dir {}: cannot create: {}", *a.mask_dir, ec.message()));
  }

  // A frame that cannot be used (unreadable, truncated, of another size, a non-finite value) is named
  // and left out, the others written, and the run ends with exit 1, as the batch job does: found only
  // by decoding, it would otherwise cost a second pass over every frame before the work.
  const auto start = std::chrono::steady_clock::now();
  ProgressBar bar("rain", a.quiet);
  std::optional<rain::RainRenderer> renderer;
  rain::RainFrame result;
  nlohmann::json per_frame = nlohmann::json::array();
  std::vector<std::string> failed;
  std::size_t written = 0;
  NegativeValues negatives;
  const ImageApi& images = image_api();
  for (std::size_t k = 0; k < frames.size(); ++k) {
    const std::string name = frames[k].string();
    try {
      const Image frame = read_input_image("--input-dir", name);
      if (!renderer) {
        rain::RainSettings s = a.s;
        s.unresolved = !a.no_unresolved;
        const rain::RainCamera cam = camera_for(a, frame.width, frame.height, a.fps);
        check_memory(cam, frame.channels, false, "--input-dir " + name);
        renderer.emplace(make_field(s, cam, !a.depth_dir));
      } else if (frame.width != renderer->field().camera().width ||
                 frame.height != renderer->field().camera().height) {
        throw IoError(fmt::format("--input-dir {}: is {}x{}, unlike the first frame ({}x{}); one sequence has one size",
                                  name, frame.width, frame.height, renderer->field().camera().width,
                                  renderer->field().camera().height));
      }
      std::optional<Image> depth;
      if (a.depth_dir) depth = read_depth(a, "--depth-dir", depth_files[k].string(), frame.width, frame.height);
      render_frame(*renderer, frame, depth ? &*depth : nullptr, a.frame_index + std::int64_t(k), false, result,
                   "--input-dir " + name);
    } catch (const IoFailure&) {
      throw;
    } catch (const Error& e) {
      // Before any frame is written nothing is lost by stopping: bad input, exit 2, nothing written.
      if (written == 0) throw;
      bar.clear();
      warn(fmt::format("{} (left out)", e.what()));
      failed.push_back(frames[k].filename().string());
      continue;
    }
    const fs::path& out_name = out_names[k];
    const auto format = out_name.extension() == ".exr" ? io::ImageFormat::exr : io::ImageFormat::png;
    io::write_file(out_dir / out_name, images.encode_image(result.image, format, io::PngOptions{}), "--output-dir");
    if (a.mask_dir) {
      io::write_file(fs::path(*a.mask_dir) / out_name, images.encode_image(io::coverage_for_encoding(result.alpha, format), format,
                                                                    io::PngOptions{16}),
                     "--mask-dir");
    }
    ++written;
    negatives.add(result.stats);
    if (stats) {
      auto j = stats_json(result.stats);
      j["frame_index"] = a.frame_index + std::int64_t(k);
      j["input"] = frames[k].filename().string();
      per_frame.push_back(std::move(j));
    }
    bar.update(double(k + 1) / double(frames.size()), fmt::format("frame {}/{}", k + 1, frames.size()));
  }
  bar.finish();
  negatives.report("--input-dir " + *a.input_dir, frames.size());
  if (stats) {
    auto j = run_json(a, renderer->field());
    j["input"] = *a.input_dir;
    j["frames"] = std::move(per_frame);
    if (!failed.empty()) j["left_out"] = failed;
    stats->write(j.dump(2) + "\n");
  }
  files.commit();
  print_summary(a, renderer->field(), result.stats, frames.size() - failed.size(),
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  if (!failed.empty()) {
    std::string list;
    for (const auto& f : failed) list += (list.empty() ? "" : ", ") + f;
    fmt::print(stderr, "{}: {} of {} frames left out ({}); the others are written\n", program_name(), failed.size(),
               frames.size(), printable(list));
    return kExitFailure;
  }
  return 0;
}

int run_video(const RainArgs& a) {
  if (!a.output) throw Error("-o: give the output video (.mp4, .mov or .mkv)");
  if (a.depth || a.depth_dir) throw Error("--depth: depth maps are for --image and --input-dir; video frames use the ground plane");
  if (a.mask_out || a.mask_dir || a.layer_out || a.output_dir)
    throw Error("--video writes one video (-o) and optionally --stats-json; masks are for --image and --input-dir");
  if (a.fps) throw Error("--fps: a video's frame rate is its own");
  if (a.depth_scale_given) throw Error("--depth-scale-m: scales PNG depth maps, which are for --image and --input-dir");
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
  rain::RainCamera cam = camera_for(a, info.width, info.height, std::nullopt);
  cam.fps = info.fps();
  // The video's own frame rate, size and the exposure it allows, said in the video's terms.
  try {
    rain::validate(cam);
  } catch (const DomainError& e) {
    if (e.quantity() == "fps" || e.quantity() == "width" || e.quantity() == "height")
      throw Error(fmt::format("--video {}: its {} {:g} is {}", *a.video,
                              e.quantity() == "fps" ? "frame rate (1/s)" : e.quantity().c_str(), e.value(),
                              e.range_text()));
    if (e.quantity() == "exposure_s")
      throw Error(fmt::format("--exposure-s {:g}: is longer than one frame of --video {} ({:g} frames/s); at most {:g} s",
                              e.value(), *a.video, cam.fps, 1.0 / cam.fps));
    throw;
  }
  check_memory(cam, 3, false, "--video " + *a.video);
  rain::RainRenderer renderer(make_field(s, cam, true));
  auto writer = api.open_writer([&out](std::uint64_t off, std::string_view bytes) { out.write_at(off, bytes); }, ext,
                                info, a.crf, fmt::format("-o {}", *a.output));
  const SrgbTables tables;
  ProgressBar bar("rain", a.quiet);
  VideoFrame in_frame, out_frame;
  Image linear;
  rain::RainFrame result;
  nlohmann::json per_frame = nlohmann::json::array();
  NegativeValues negatives;
  std::int64_t k = 0;
  // The frame count for the progress: the container's, else the duration times the rate (Matroska).
  const std::int64_t expected = info.frame_count > 0 ? info.frame_count
                                : info.duration_s > 0 ? std::llround(info.duration_s * info.fps())
                                                      : -1;
  while (reader->read(in_frame)) {
    tables.to_linear(in_frame, linear);
    render_frame(renderer, linear, nullptr, a.frame_index + k, false, result, "--video " + *a.video);
    negatives.add(result.stats);
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
  negatives.report("--video " + *a.video, std::size_t(k));
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
  auto* depth_scale = sub->add_option("--depth-scale-m", a->depth_scale_m, "Metres per code of a PNG depth map (--depth, --depth-dir)")
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
      ->check(number_in(0.01, 1000, "1/s"));
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
      ->transform(integer_in(0, (long long)rain::kMaxSeed))->capture_default_str();
  auto* crf = sub->add_option("--crf", a->crf, "H.264 quality of --video's output (0 lossless .. 51; 18 visually lossless)")
      ->transform(integer_in(0, 51))->capture_default_str();
  sub->add_flag("-q,--quiet", a->quiet, "No progress or summary on stderr");
  return {sub,
          [a, crf, depth_scale] {
            a->crf_given = crf->count() > 0;
            a->depth_scale_given = depth_scale->count() > 0;
            return run_rain(*a);
          },
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
