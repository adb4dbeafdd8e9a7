// The frame jobs' one driver (frame_driver.hpp): the photograph, folder and video modes, the
// pipeline, the files, the left-out policy and the statistics; the effects supply the frames.
#include "hydrolux/io/frame_driver.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <deque>
#include <exception>
#include <filesystem>
#include <memory>
#include <mutex>
#include <thread>

#include "hydrolux/color/srgb.hpp"
#include "hydrolux/core/error.hpp"
#include "hydrolux/io/files.hpp"
#include "hydrolux/io/frames.hpp"
#include "hydrolux/io/video.hpp"
#include "hydrolux/rain/params.hpp"

namespace hydrolux::io {

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
using Warn = std::function<void(const std::string&)>;

struct Driver {
  const FrameRequest& a;
  FrameEffect& effect;
  const FrameHooks& h;
  Clock::time_point start = Clock::now();
  // The decoder captures the process's stderr while it runs (image_io.cpp), so nothing may print
  // meanwhile: a folder's frames are decoded on one thread while another reports progress, and every
  // decode and every hook call takes this lock.
  mutable std::mutex console;

  void warn(const std::string& text) const {
    std::lock_guard lock(console);
    if (h.warn) h.warn(text);
  }
  void progress(double f, std::string_view label) const {
    std::lock_guard lock(console);
    if (h.progress) h.progress(f, label);
  }
  void clear_progress() const {
    std::lock_guard lock(console);
    if (h.clear_progress) h.clear_progress();
  }
  void finish_progress() const {
    std::lock_guard lock(console);
    if (h.finish_progress) h.finish_progress();
  }
  Warn warner() const {
    return [this](const std::string& text) { warn(text); };
  }
  DecodedImage decode(const std::string& bytes, const std::string& origin, const ImageLimits& limits = {}) const {
    std::lock_guard lock(console);
    return h.codec.decode(bytes, origin, limits);
  }
  PngOptions png(int bits) const { return PngOptions{bits, a.png_compression}; }

  // A frame, each warning of the codec to `sink` as "<flag> <path>: <warning>". A frame too large
  // for the memory left is refused from its header, before its pixels are decoded (the effect's
  // estimate with `with_layer` and the pipeline's `extra_bytes_per_pixel`).
  Image read_image(const std::string& flag, const std::string& path, const Warn& sink, bool with_layer,
                   double extra_bytes_per_pixel) const {
    const std::string bytes = read_file(path, ImageLimits{}.max_file_bytes, flag);
    const std::string origin = fmt::format("{} {}", flag, path);
    ImageLimits limits;
    limits.before_pixels = [&](std::int64_t width, std::int64_t height, std::int64_t channels) {
      effect.check_memory(origin, int(width), int(height), int(channels), with_layer, extra_bytes_per_pixel);
    };
    auto decoded = decode(bytes, origin, limits);
    for (const auto& w : decoded.warnings) sink(fmt::format("{}: {}", origin, w));
    return std::move(decoded.image);
  }

  // A depth map (depth_from_decoded), the JPEG refused before it is decoded. --depth-scale-m, if
  // given, must have a coded map (PNG, TIFF, PNM) to scale: an EXR holds metres.
  Image read_depth(const std::string& flag, const std::string& path, int width, int height, const Warn& sink) const {
    const std::string bytes = read_file(path, ImageLimits{}.max_file_bytes, flag);
    const std::string origin = fmt::format("{} {}", flag, path);
    const auto format = sniff_image_format(bytes);
    if (format == ImageFormat::jpeg) throw Error(origin + kJpegDepthRefusal);
    if (a.given.given("depth_scale_m") && (format == ImageFormat::exr || format == ImageFormat::hdr))
      throw Error(fmt::format("--depth-scale-m: scales the codes of a PNG depth map; {} holds metres already", origin));
    auto decoded = decode(bytes, origin);
    for (const auto& w : decoded.warnings) sink(fmt::format("{}: {}", origin, w));
    return depth_from_decoded(decoded, a.depth_scale_m, width, height, origin);
  }

  FrameRunResult result(std::size_t frames, std::size_t total) const {
    FrameRunResult out;
    out.frames = frames;
    out.frames_total = total;
    out.seconds = std::chrono::duration<double>(Clock::now() - start).count();
    return out;
  }
};

// The parameters given that the run leaves unused, by the table's conditions (crf only with a video,
// depth_scale_m only with depth maps, rain's fps not with a video): refused in ParamUse's one format.
void check_unused_flags(const FrameRequest& a, FrameMode mode) {
  ParamUse use = a.given;
  if (mode == FrameMode::video) use.hold("video");
  if (a.depth) use.hold("depth");
  if (a.depth_dir) use.hold("depth_dir");
  use.report_unused();
}

// The negative input values read as 0 over a run, said once at its end (not a line a frame).
struct NegativeValues {
  std::uint64_t values = 0, frames = 0;
  void add(std::uint64_t n) {
    values += n;
    frames += n > 0 ? 1 : 0;
  }
  void report(const Driver& run, const std::string& origin, std::size_t frame_count) const {
    if (values == 0) return;
    const std::string n = fmt::format("{} negative value{}", values, values == 1 ? "" : "s");
    run.warn(frame_count > 1 ? fmt::format("{}: {} in {} of {} frames read as 0 (light cannot be negative)", origin, n,
                                           frames, frame_count)
                             : fmt::format("{}: {} read as 0 (light cannot be negative)", origin, n));
  }
};

static_assert(rain::RainFileOptions{}.png_compression == kDefaultPngCompression, "one default for PNG files");

struct ImageOut {
  OutputFile* file;
  ImageFormat format;
};
ImageOut declare_image(FileSet& files, const std::string& flag, const std::string& path) {
  const ImageFormat format = output_image_format(path, flag);
  return {&files.output(flag, path), format};
}

// The run's statistics: the effect's, the input and the frames.
nlohmann::json run_stats(const FrameEffect& effect, const std::string& key, const std::string& input,
                         nlohmann::json frames) {
  auto j = effect.run_json();
  j[key] = input;
  j["frames"] = std::move(frames);
  return j;
}

FrameRunResult run_image(const Driver& run) {
  const FrameRequest& a = run.a;
  check_unused_flags(a, FrameMode::image);
  run.effect.check_mode(a, FrameMode::image);
  FileSet files;
  const bool synthetic = run.effect.synthetic(a);
  if (!synthetic) files.input("--image", *a.image);
  if (a.depth) files.input("--depth", *a.depth);
  if (!a.output) throw Error("-o: give the output image (.png or .exr)");
  const ImageOut out = declare_image(files, "-o", *a.output);
  std::optional<ImageOut> mask, layer;
  if (a.mask_out) mask = declare_image(files, "--mask-out", *a.mask_out);
  if (a.layer_out) {
    layer = declare_image(files, "--layer-out", *a.layer_out);
    if (layer->format != ImageFormat::exr)
      throw Error(fmt::format("--layer-out {}: the rain layer is linear light; give an .exr file", *a.layer_out));
  }
  OutputFile* stats = a.stats_json ? &files.output("--stats-json", *a.stats_json) : nullptr;
  run.effect.validate();

  const std::string origin = "--image " + *a.image;
  const Image frame = synthetic ? run.effect.make_synthetic(a, layer.has_value())
                                : run.read_image("--image", *a.image, run.warner(), layer.has_value(), 0);
  std::optional<Image> depth;
  if (a.depth) depth = run.read_depth("--depth", *a.depth, frame.width, frame.height, run.warner());
  run.effect.prepare({FrameMode::image, frame.width, frame.height, frame.channels, 0, *a.image, origin,
                      depth.has_value(), layer.has_value(), 0});
  FrameOutput result;
  run.effect.render(frame, depth ? &*depth : nullptr, 0, layer.has_value(), origin, result);
  NegativeValues negatives;
  negatives.add(result.negative_values);
  negatives.report(run, origin, 1);
  // The optional outputs first: a failure (a full disk) is then reported under their own flag.
  if (layer) layer->file->write(run.h.codec.encode(result.layer, layer->format, run.png(8)));
  if (mask)
    mask->file->write(run.h.codec.encode(coverage_for_encoding(result.mask, mask->format), mask->format, run.png(16)));
  out.file->write(run.h.codec.encode(result.image, out.format, run.png(8)));
  if (stats) stats->write(run_stats(run.effect, "input", *a.image, nlohmann::json::array({result.stats})).dump(2) + "\n");
  files.commit();
  return run.result(1, 1);
}

// A queue of at most `capacity` items between two threads. close(): no more items (pop drains the
// rest, then returns nothing); stop(): the run is abandoned (push and pop return at once).
template <typename T>
class BoundedQueue {
 public:
  explicit BoundedQueue(std::size_t capacity) : capacity_(capacity) {}
  bool push(T item) {
    std::unique_lock lock(m_);
    cv_.wait(lock, [&] { return stopped_ || q_.size() < capacity_; });
    if (stopped_) return false;
    q_.push_back(std::move(item));
    cv_.notify_all();
    return true;
  }
  // An item if one is waiting, else nothing, at once.
  std::optional<T> try_pop() {
    std::lock_guard lock(m_);
    if (stopped_ || q_.empty()) return std::nullopt;
    T item = std::move(q_.front());
    q_.pop_front();
    cv_.notify_all();
    return item;
  }
  std::optional<T> pop() {
    std::unique_lock lock(m_);
    cv_.wait(lock, [&] { return stopped_ || closed_ || !q_.empty(); });
    if (stopped_ || q_.empty()) return std::nullopt;
    T item = std::move(q_.front());
    q_.pop_front();
    cv_.notify_all();
    return item;
  }
  void close() {
    std::lock_guard lock(m_);
    closed_ = true;
    cv_.notify_all();
  }
  void stop() {
    std::lock_guard lock(m_);
    stopped_ = true;
    cv_.notify_all();
  }

 private:
  std::mutex m_;
  std::condition_variable cv_;
  std::deque<T> q_;
  std::size_t capacity_;
  bool closed_ = false, stopped_ = false;
};

// A frame of a folder or a video as read (or why not), and as rendered.
struct DecodedFrame {
  std::size_t k = 0;
  Image frame, depth;
  std::vector<std::string> warnings;
  std::exception_ptr error, depth_error;
};
struct RenderedFrame {
  std::size_t k = 0;
  std::unique_ptr<FrameOutput> result;
  std::vector<std::string> warnings;
  std::exception_ptr error;
};

// The frames in flight of a folder or video run, bounded: one being decoded, kDecodedFrames decoded and
// waiting, one being rendered, and kRenderedFrames rendered frames (each rendered into one of as many
// reused FrameOutputs) waiting for or being encoded. At 1920 x 1080 RGB: three frames of 24 MB in and
// three of 32 MB out (frame and alpha), measured 115 MB above one frame at a time at the peak (rain).
class FramePipeline {
 public:
  static constexpr std::size_t kDecodedFrames = 1, kRenderedFrames = 3;
  // What that adds to one frame at a time, per pixel, for the memory check: the measured 115 MB
  // over 1920 x 1080 pixels.
  static constexpr double kExtraBytesPerPixel = 115e6 / (1920.0 * 1080.0);
  BoundedQueue<DecodedFrame> decoded{kDecodedFrames};
  BoundedQueue<RenderedFrame> rendered{kRenderedFrames};

  // A FrameOutput to render into: a new one until kRenderedFrames exist, then one the writer has
  // released; nothing once stopped.
  std::unique_ptr<FrameOutput> acquire() {
    if (made_ < kRenderedFrames) {
      ++made_;
      return std::make_unique<FrameOutput>();
    }
    auto f = free_.pop();
    return f ? std::move(*f) : nullptr;
  }
  void release(std::unique_ptr<FrameOutput> f) { (void)free_.push(std::move(f)); }

  // An input frame's buffer to decode into: one the render stage has finished with, else a new one
  // (at most kDecodedFrames + 2 are ever in use: decoding, waiting, rendering).
  Image spare_input() {
    auto img = spare_inputs_.try_pop();
    return img ? std::move(*img) : Image();
  }
  void recycle_input(Image&& img) { (void)spare_inputs_.push(std::move(img)); }

  // Runs `read` and `write` on threads of their own and `render` on this one. The first exception
  // any stage lets out stops the others and is rethrown here once all three have ended.
  template <typename Read, typename Render, typename Write>
  void run(const Read& read, const Render& render, const Write& write) {
    std::exception_ptr first;
    std::mutex m;
    const auto guarded = [&](const auto& stage) {
      try {
        stage();
      } catch (...) {
        {
          std::lock_guard lock(m);
          if (!first) first = std::current_exception();
        }
        stop();
      }
    };
    {
      std::jthread reader([&] { guarded(read); });
      std::jthread writer([&] { guarded(write); });
      guarded(render);
    }
    if (first) std::rethrow_exception(first);
  }

 private:
  void stop() {
    decoded.stop();
    rendered.stop();
    free_.stop();
    spare_inputs_.stop();
  }
  std::size_t made_ = 0;  // the render stage's alone
  BoundedQueue<std::unique_ptr<FrameOutput>> free_{kRenderedFrames};
  BoundedQueue<Image> spare_inputs_{kDecodedFrames + 2};
};

// A frame's rain layer in --layer-dir: its output's stem as .exr (the layer is linear light).
fs::path layer_name(const fs::path& output_name) {
  fs::path n = output_name;
  n.replace_extension(".exr");
  return n;
}

// A folder's run: the plan, the files and what the three stages share.
struct FolderRun {
  FolderRun(const Driver& r, FrameFolder p) : run(r), plan(std::move(p)) {}
  const Driver& run;
  FrameFolder plan;
  FramePipeline pipe;
  nlohmann::json per_frame = nlohmann::json::array();
  std::vector<std::string> failed;
  std::size_t written = 0;
  NegativeValues negatives;
  std::optional<SequenceStart> first;  // the first frame's size, once rendered

  // Stage 1: read and decode; the codec's warnings travel with the frame, said when it is written.
  void read_stage() {
    const FrameRequest& a = run.a;
    for (std::size_t k = 0; k < plan.frames.size(); ++k) {
      DecodedFrame f;
      f.k = k;
      const Warn sink = [&f](const std::string& text) { f.warnings.push_back(text); };
      try {
        f.frame = run.read_image("--input-dir", plan.frames[k].string(), sink, a.layer_dir.has_value(),
                                 FramePipeline::kExtraBytesPerPixel);
        if (a.depth_dir) {
          try {
            f.depth = run.read_depth("--depth-dir", plan.depth_maps[k].string(), f.frame.width, f.frame.height, sink);
          } catch (...) {
            f.depth_error = std::current_exception();
          }
        }
      } catch (...) {
        f.error = std::current_exception();
      }
      if (!pipe.decoded.push(std::move(f))) return;
    }
    pipe.decoded.close();
  }

  // The first frame prepares the effect; the others must be its size where the effect says so.
  void start_or_check(const Image& frame, const std::string& name) {
    if (!first) {
      first = SequenceStart{FrameMode::folder, frame.width, frame.height, frame.channels, 0, run.a.input_dir.value(),
                            "--input-dir " + name, run.a.depth_dir.has_value(), run.a.layer_dir.has_value(),
                            FramePipeline::kExtraBytesPerPixel};
      run.effect.prepare(*first);
    } else if (run.effect.traits().one_size && (frame.width != first->width || frame.height != first->height)) {
      throw IoError(fmt::format("--input-dir {}: is {}x{}, unlike the first frame ({}x{}); one sequence has one size",
                                name, frame.width, frame.height, first->width, first->height));
    }
  }

  // Stage 2, on the caller's thread: render in order.
  void render_stage() {
    while (auto f = pipe.decoded.pop()) {
      RenderedFrame out;
      out.k = f->k;
      out.warnings = std::move(f->warnings);
      out.error = f->error;
      if (!out.error) {
        try {
          const std::string name = plan.frames[f->k].string();
          start_or_check(f->frame, name);
          if (f->depth_error) std::rethrow_exception(f->depth_error);
          auto result = pipe.acquire();
          if (!result) return;  // stopped
          run.effect.render(f->frame, run.a.depth_dir ? &f->depth : nullptr, f->k, run.a.layer_dir.has_value(),
                            "--input-dir " + name,
                            *result);
          out.result = std::move(result);
        } catch (...) {
          out.error = std::current_exception();
        }
      }
      if (!pipe.rendered.push(std::move(out))) return;
    }
    pipe.rendered.close();
  }

  // Stage 3: encode and write in order, and all the bookkeeping of a frame's end (its warnings, left
  // out or written, statistics, progress), so that everything is said in the order of the frames.
  void write_stage() {
    const FrameRequest& a = run.a;
    const std::size_t n = plan.frames.size();
    while (auto item = pipe.rendered.pop()) {
      const std::size_t k = item->k;
      for (const auto& w : item->warnings) run.warn(w);
      if (item->error) {
        try {
          std::rethrow_exception(item->error);
        } catch (const IoFailure&) {
          throw;
        } catch (const Error& e) {
          // Before any frame is written nothing is lost by stopping: bad input, nothing written.
          if (written == 0) throw;
          run.clear_progress();
          run.warn(fmt::format("{} (left out)", e.what()));
          failed.push_back(plan.frames[k].filename().string());
          run.progress(double(k + 1) / double(n), fmt::format("frame {}/{}", k + 1, n));
          continue;
        }
      }
      FrameOutput& result = *item->result;
      const fs::path& out_name = plan.outputs[k];
      const auto format = out_name.extension() == ".exr" ? ImageFormat::exr : ImageFormat::png;
      write_file(fs::path(*a.output_dir) / out_name, run.h.codec.encode(result.image, format, run.png(8)),
                 "--output-dir");
      if (a.mask_dir)
        write_file(fs::path(*a.mask_dir) / out_name,
                   run.h.codec.encode(coverage_for_encoding(result.mask, format), format, run.png(16)), "--mask-dir");
      if (a.layer_dir)
        write_file(fs::path(*a.layer_dir) / layer_name(out_name),
                   run.h.codec.encode(result.layer, ImageFormat::exr, run.png(8)), "--layer-dir");
      ++written;
      negatives.add(result.negative_values);
      if (a.stats_json) {
        result.stats["input"] = plan.frames[k].filename().string();
        per_frame.push_back(std::move(result.stats));
      }
      pipe.release(std::move(item->result));
      run.progress(double(k + 1) / double(n), fmt::format("frame {}/{}", k + 1, n));
    }
  }
};

FrameRunResult run_folder(const Driver& run) {
  const FrameRequest& a = run.a;
  if (a.output) throw Error("-o: with --input-dir the frames go to --output-dir");
  if (!a.output_dir)
    throw Error(fmt::format("--output-dir: give the folder for the {} (with --input-dir)", run.effect.traits().noun));
  if (a.depth) throw Error("--depth: one depth map serves one --image; give a folder's maps with --depth-dir");
  if (a.mask_out) throw Error("--mask-out: with --input-dir give --mask-dir for the masks");
  if (a.layer_out) throw Error("--layer-out: available with --image");
  check_unused_flags(a, FrameMode::folder);
  run.effect.check_mode(a, FrameMode::folder);
  const FrameFolderRequest request{*a.input_dir, *a.output_dir, a.mask_dir, a.depth_dir};
  FolderRun f(run, plan_frame_folder(request));
  if (!f.plan.skipped.empty()) run.warn(f.plan.skipped_warning(*a.input_dir));
  // Every file the run reads or writes, declared before any work: an output on an input (a
  // --stats-json naming a frame, a link in --output-dir to a frame) or two outputs on one path are
  // refused here, whichever folders they are in.
  FileSet files;
  declare_frame_folder(files, f.plan, request);
  if (a.layer_dir) {
    std::error_code ec;
    for (const auto& [flag, dir] : {std::pair{"--input-dir", *a.input_dir}, {"--output-dir", *a.output_dir},
                                    {"--mask-dir", a.mask_dir.value_or("")}})
      if (!dir.empty() && fs::exists(*a.layer_dir, ec) && same_file(*a.layer_dir, dir))
        throw Error(fmt::format("--layer-dir {}: is {}; give the layers their own folder", *a.layer_dir, flag));
    if (fs::exists(*a.layer_dir, ec) && !fs::is_directory(*a.layer_dir, ec))
      throw Error(fmt::format("--layer-dir {}: exists and is not a folder", *a.layer_dir));
    for (const auto& n : f.plan.outputs) files.planned_output("--layer-dir", fs::path(*a.layer_dir) / layer_name(n));
  }
  OutputFile* stats = a.stats_json ? &files.output("--stats-json", *a.stats_json) : nullptr;
  run.effect.validate();
  create_output_folders(request);
  if (a.layer_dir) {
    std::error_code ec;
    fs::create_directories(*a.layer_dir, ec);
    if (ec) throw IoError(fmt::format("--layer-dir {}: cannot create: {}", *a.layer_dir, ec.message()));
  }
  // A frame that cannot be used (unreadable, truncated, of another size, a non-finite value) is named
  // and left out, the others written, and the run ends with the list, as the batch job does: found
  // only by decoding, it would otherwise cost a second pass over every frame before the work.
  //
  // Three stages overlap over neighbouring frames (FramePipeline): one thread reads and decodes
  // frames in order, this one renders them in order (an effect may carry state from frame to frame:
  // rain's field, fog's sky; its own loops use every core), and a third encodes and writes them in
  // order. Each stage is deterministic and sees the frames in order: the same bytes whatever the
  // threads.
  f.pipe.run([&] { f.read_stage(); }, [&] { f.render_stage(); }, [&] { f.write_stage(); });
  run.finish_progress();
  const std::size_t n = f.plan.frames.size();
  f.negatives.report(run, "--input-dir " + *a.input_dir, n);
  if (stats) {
    auto j = run_stats(run.effect, run.effect.traits().folder_input_key, *a.input_dir, std::move(f.per_frame));
    if (!f.failed.empty()) j["left_out"] = f.failed;
    stats->write(j.dump(2) + "\n");
  }
  files.commit();
  auto out = run.result(n - f.failed.size(), n);
  out.left_out = std::move(f.failed);
  return out;
}

// A video's run: its reader, writer and what the three stages share. A decoding, rendering or
// encoding failure ends the run (a video has no frame to leave out).
struct VideoRun {
  VideoRun(const Driver& r, VideoReader& in, VideoWriter& out, std::int64_t n)
      : run(r), reader(in), writer(out), expected(n) {}
  const Driver& run;
  VideoReader& reader;
  VideoWriter& writer;
  std::int64_t expected;  // the frame count for the progress, or -1
  FramePipeline pipe;
  const color::Srgb8Tables tables;
  nlohmann::json per_frame = nlohmann::json::array();
  NegativeValues negatives;
  std::int64_t written = 0;

  void read_stage() {
    VideoFrame in_frame;
    for (std::size_t n = 0; reader.read(in_frame); ++n) {
      DecodedFrame f;
      f.k = n;
      // 8-bit frames to linear float (and back below) through the library's tables, into a buffer
      // of an earlier frame (a fresh 1080p frame costs its 24 MB of page faults).
      f.frame = pipe.spare_input();
      if (f.frame.width != in_frame.width || f.frame.height != in_frame.height || f.frame.channels != 3)
        f.frame = Image(in_frame.width, in_frame.height, 3);
      tables.to_linear(in_frame.rgb.data(), std::size_t(in_frame.width) * in_frame.height, f.frame.pixels.data());
      if (!pipe.decoded.push(std::move(f))) return;
    }
    pipe.decoded.close();
  }
  void render_stage() {
    const std::string origin = "--video " + *run.a.video;
    while (auto f = pipe.decoded.pop()) {
      auto result = pipe.acquire();
      if (!result) return;  // stopped
      run.effect.render(f->frame, nullptr, f->k, false, origin, *result);
      pipe.recycle_input(std::move(f->frame));
      RenderedFrame rendered;
      rendered.k = f->k;
      rendered.result = std::move(result);
      if (!pipe.rendered.push(std::move(rendered))) return;
    }
    pipe.rendered.close();
  }
  void write_stage() {
    VideoFrame out_frame;
    while (auto item = pipe.rendered.pop()) {
      FrameOutput& result = *item->result;
      const Image& img = result.image;
      out_frame.width = img.width;
      out_frame.height = img.height;
      out_frame.rgb.resize(std::size_t(img.width) * img.height * 3);
      tables.to_srgb8(img.pixels.data(), std::size_t(img.width) * img.height, img.channels, out_frame.rgb.data());
      writer.write(out_frame);
      negatives.add(result.negative_values);
      if (run.a.stats_json) per_frame.push_back(std::move(result.stats));
      pipe.release(std::move(item->result));
      ++written;
      if (expected > 0)
        run.progress(std::min(1.0, double(written) / double(expected)), fmt::format("frame {}/{}", written, expected));
    }
  }
};

FrameRunResult run_video(const Driver& run) {
  const FrameRequest& a = run.a;
  if (!a.output) throw Error("-o: give the output video (.mp4, .mov or .mkv)");
  if (a.depth || a.depth_dir)
    throw Error("--depth: depth maps are for --image and --input-dir; video frames use the ground plane");
  if (a.mask_out || a.mask_dir || a.layer_out || a.layer_dir || a.output_dir)
    throw Error("--video writes one video (-o) and optionally --stats-json; masks are for --image and --input-dir");
  run.effect.check_mode(a, FrameMode::video);
  check_unused_flags(a, FrameMode::video);
  const std::string ext = lower_extension(*a.output);
  if (std::find(std::begin(kVideoExtensions), std::end(kVideoExtensions), ext) == std::end(kVideoExtensions))
    throw Error(fmt::format("-o {}: expected a .mp4, .mov or .mkv file", *a.output));
  FileSet files;
  files.input("--video", *a.video);
  OutputFile& out = files.output("-o", *a.output);
  OutputFile* stats = a.stats_json ? &files.output("--stats-json", *a.stats_json) : nullptr;
  run.effect.validate();
  const VideoApi& api = video_api();
  const InputFile input(*a.video, "--video");
  const std::string origin = "--video " + *a.video;
  auto reader = api.open_reader([&input](std::uint64_t off, char* buf, std::size_t n) { return input.read_at(off, buf, n); },
                                input.size(), origin, VideoLimits{});
  const VideoInfo info = reader->info();
  run.effect.check_memory(origin, info.width, info.height, 3, false, FramePipeline::kExtraBytesPerPixel);
  run.effect.prepare({FrameMode::video, info.width, info.height, 3, info.fps(), *a.video, origin, false, false,
                      FramePipeline::kExtraBytesPerPixel});
  auto writer = api.open_writer([&out](std::uint64_t off, std::string_view bytes) { out.write_at(off, bytes); }, ext,
                                info, a.crf, fmt::format("-o {}", *a.output));
  // The frame count for the progress: the container's, else the duration times the rate (Matroska).
  const std::int64_t expected = info.frame_count > 0 ? info.frame_count
                                : info.duration_s > 0 ? std::llround(info.duration_s * info.fps())
                                                      : -1;
  // Three overlapping stages, as for a folder (FramePipeline): this thread renders in order while one
  // decodes the next frames and another encodes the last ones, in order, so the encoder's time is
  // not added to the renderer's; the same bytes as one frame at a time.
  VideoRun v(run, *reader, *writer, expected);
  v.pipe.run([&] { v.read_stage(); }, [&] { v.render_stage(); }, [&] { v.write_stage(); });
  writer->finish();
  run.finish_progress();
  v.negatives.report(run, origin, std::size_t(v.written));
  if (stats) {
    auto j = run_stats(run.effect, "input", *a.video, std::move(v.per_frame));
    j["video"] = {{"codec", info.codec}, {"fps_num", info.fps_num}, {"fps_den", info.fps_den}, {"frames", v.written},
                  {"crf", a.crf}};
    stats->write(j.dump(2) + "\n");
  }
  files.commit();
  return run.result(std::size_t(v.written), std::size_t(v.written));
}

}  // namespace

FrameRunResult run_frames(const FrameRequest& a, FrameEffect& effect, const FrameHooks& hooks) {
  const int modes = int(a.image.has_value()) + int(a.input_dir.has_value()) + int(a.video.has_value());
  if (modes != 1) throw Error("give exactly one of --image, --input-dir and --video");
  if (a.output_dir && !a.input_dir) throw Error("--output-dir: goes with --input-dir");
  if (a.mask_dir && !a.input_dir) throw Error("--mask-dir: goes with --input-dir (use --mask-out with --image)");
  if (a.layer_dir && !a.input_dir) throw Error("--layer-dir: goes with --input-dir (use --layer-out with --image)");
  if (a.depth_dir && !a.input_dir) throw Error("--depth-dir: goes with --input-dir (use --depth with --image)");
  for (const auto& f : rain::rain_path_params())  // every path there is (the rain takes them all)
    if (!f.text(a).empty() && !find_field(effect.traits().paths, f.param.name))
      throw std::logic_error("run_frames: a path the effect does not take: " + std::string(f.param.flag));
  rain::rain_param("png_compression").check(double(a.png_compression));  // the declared range (params.cpp)
  effect.check_options(a);
  const Driver run{a, effect, hooks, Clock::now(), {}};
  if (a.image) return run_image(run);
  if (a.input_dir) return run_folder(run);
  return run_video(run);
}

FrameRequest frame_request(const FramePaths& paths, int png_compression, int crf, const ParamUse& given,
                           double depth_scale_m) {
  FrameRequest r;
  static_cast<FramePaths&>(r) = paths;
  r.png_compression = png_compression;
  r.crf = crf;
  r.given = given;
  r.depth_scale_m = depth_scale_m;
  return r;
}

std::span<const Field<VideoFileOptions>> video_file_params() {
  static const Field<VideoFileOptions> table[] = {
      {rain::rain_param("crf"), HYDROLUX_PARAM_MEMBER(crf)},
  };
  return table;
}

}  // namespace hydrolux::io
