// A rain run over files (rain_job.hpp): the photograph, folder and video modes of `hydrolux rain`.
#include "hydrolux/io/rain_job.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <deque>
#include <exception>
#include <filesystem>
#include <functional>
#include <memory>
#include <mutex>
#include <thread>

#include "hydrolux/color/srgb.hpp"
#include "hydrolux/core/error.hpp"
#include "hydrolux/core/parse.hpp"
#include "hydrolux/io/files.hpp"
#include "hydrolux/io/frames.hpp"
#include "hydrolux/io/rain_report.hpp"
#include "hydrolux/io/video.hpp"

namespace hydrolux::io {

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

using Warn = std::function<void(const std::string&)>;

struct Run {
  const RainJob& a;
  const RainJobHooks& h;
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

  // read_decoded's read: each warning of the codec to `sink` as "<flag> <path>: <warning>". A frame too
  // large for the memory left is refused from its header, before its pixels are decoded: rendering it
  // with `with_layer` and `extra_bytes_per_pixel` (check_render_memory) must fit.
  Image read_image(const std::string& flag, const std::string& path, const Warn& sink, bool with_layer = false,
                   double extra_bytes_per_pixel = 0) const {
    const std::string bytes = read_file(path, ImageLimits{}.max_file_bytes, flag);
    const std::string origin = fmt::format("{} {}", flag, path);
    ImageLimits limits;
    limits.before_pixels = [&](std::int64_t width, std::int64_t height, std::int64_t channels) {
      rain::check_render_memory(rain::camera_for(a.options, int(width), int(height)), int(channels), with_layer, origin,
                                extra_bytes_per_pixel);
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
    if (a.depth_scale_given && (format == ImageFormat::exr || format == ImageFormat::hdr))
      throw Error(fmt::format("--depth-scale-m: scales the codes of a PNG depth map; {} holds metres already", origin));
    auto decoded = decode(bytes, origin);
    for (const auto& w : decoded.warnings) sink(fmt::format("{}: {}", origin, w));
    return depth_from_decoded(decoded, a.files.depth_scale_m, width, height, origin);
  }
  Image read_depth(const std::string& flag, const std::string& path, int width, int height) const {
    return read_depth(flag, path, width, height, warner());
  }

  nlohmann::json run_json(const rain::RainField& field) const {
    return rain_run_json(field, a.depth ? *a.depth : a.depth_dir ? *a.depth_dir : std::string("ground plane"));
  }

  // The renderer for one camera, with the library's "too many drops" said in the flags.
  rain::RainRenderer make_renderer(const rain::RainCamera& cam, bool ground_plane) const {
    try {
      rain::RainRenderer r(rain::RainField(a.options.settings, cam, ground_plane));
      if (a.options.has_fog()) r.set_fog(a.options.fog);
      return r;
    } catch (const rain::TooManyDrops& e) {
      throw Error(fmt::format(
          "--min-alpha {:g}: the rain field would hold {:.3g} drops, more than the limit of {:.3g}; "
          "raise --min-alpha, --near-m or --min-radius-mm, or lower --far-m or --rate-mmh",
          a.options.settings.min_alpha, e.drops(), double(rain::RainField::kMaxDrops)));
    }
  }

  RainJobResult result(const rain::RainRenderer& r, const rain::RainStats& last, std::size_t frames,
                       std::size_t total) const {
    RainJobResult out;
    out.frames = frames;
    out.frames_total = total;
    out.rate_mmh = r.field().settings().rate_mmh;
    out.drops = r.field().drop_count();
    out.last = last;
    out.seconds = std::chrono::duration<double>(Clock::now() - start).count();
    return out;
  }
};

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
  void report(const Run& run, const std::string& origin, std::size_t frame_count) const {
    if (values == 0) return;
    const std::string n = fmt::format("{} negative value{}", values, values == 1 ? "" : "s");
    run.warn(frame_count > 1 ? fmt::format("{}: {} in {} of {} frames read as 0 (light cannot be negative)", origin, n,
                                           frames, frame_count)
                             : fmt::format("{}: {} read as 0 (light cannot be negative)", origin, n));
  }
};

static_assert(rain::RainFileOptions{}.png_compression == kDefaultPngCompression, "one default for PNG files");

PngOptions png_options(const RainJob& a, int bits) { return PngOptions{bits, a.files.png_compression}; }

struct ImageOut {
  OutputFile* file;
  ImageFormat format;
};
ImageOut declare_image(FileSet& files, const std::string& flag, const std::string& path) {
  const ImageFormat format = output_image_format(path, flag);
  return {&files.output(flag, path), format};
}

RainJobResult run_image(const Run& run) {
  const RainJob& a = run.a;
  if (a.crf_given) throw Error("--crf: sets the H.264 quality of --video's output; --image writes one picture");
  if (a.depth_scale_given && !a.depth) throw Error("--depth-scale-m: scales a PNG --depth map; none is given");
  FileSet files;
  const bool builtin = *a.image == "builtin";
  if (!builtin) files.input("--image", *a.image);
  if (a.size && !builtin) throw Error("--size: goes with --image builtin (a photograph has its own size)");
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

  const std::string origin = builtin ? std::string("--image builtin") : "--image " + *a.image;
  Image frame;
  if (builtin) {
    const std::string size = a.size.value_or("1280x720");
    const auto wh = parse::pair(size, 'x');
    if (!wh) throw Error(fmt::format("--size {}: not WxH", size));
    const rain::RainCamera c = rain::camera_for(a.options, int((*wh)[0]), int((*wh)[1]));
    rain::check_render_memory(c, 3, layer.has_value(), "--size " + size);
    frame = rain::builtin_scene(c);
  } else {
    frame = run.read_image("--image", *a.image, run.warner(), layer.has_value());
  }
  const rain::RainCamera cam = rain::camera_for(a.options, frame.width, frame.height);
  if (!builtin) rain::check_render_memory(cam, frame.channels, layer.has_value(), origin);
  std::optional<Image> depth;
  if (a.depth) depth = run.read_depth("--depth", *a.depth, frame.width, frame.height);
  rain::RainRenderer renderer = run.make_renderer(cam, !depth);
  rain::RainFrame result;
  render_frame(renderer, frame, depth ? &*depth : nullptr, a.files.frame_index, layer.has_value(), result, origin);
  NegativeValues negatives;
  negatives.add(result.stats);
  negatives.report(run, origin, 1);
  // The optional outputs first: a failure (a full disk) is then reported under their own flag.
  if (layer) layer->file->write(run.h.codec.encode(result.layer, layer->format, png_options(a, 8)));
  if (mask)
    mask->file->write(
        run.h.codec.encode(coverage_for_encoding(result.alpha, mask->format), mask->format, png_options(a, 16)));
  out.file->write(run.h.codec.encode(result.image, out.format, png_options(a, 8)));
  if (stats) {
    auto j = run.run_json(renderer.field());
    j["input"] = *a.image;
    j["frames"] = nlohmann::json::array({rain_stats_json(result.stats)});
    j["frames"][0]["frame_index"] = a.files.frame_index;
    stats->write(j.dump(2) + "\n");
  }
  files.commit();
  return run.result(renderer, result.stats, 1, 1);
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
  std::unique_ptr<rain::RainFrame> result;
  std::vector<std::string> warnings;
  std::exception_ptr error;
};

// The frames in flight of a folder or video run, bounded: one being decoded, kDecodedFrames decoded and
// waiting, one being rendered, and kRenderedFrames rendered frames (each rendered into one of as many
// reused RainFrames) waiting for or being encoded. At 1920 x 1080 RGB: three frames of 24 MB in and
// three of 32 MB out (frame and alpha), measured 115 MB above one frame at a time at the peak.
class FramePipeline {
 public:
  static constexpr std::size_t kDecodedFrames = 1, kRenderedFrames = 3;
  // What that adds to one frame at a time, per pixel, for the memory check: the measured 115 MB
  // over 1920 x 1080 pixels.
  static constexpr double kExtraBytesPerPixel = 115e6 / (1920.0 * 1080.0);
  BoundedQueue<DecodedFrame> decoded{kDecodedFrames};
  BoundedQueue<RenderedFrame> rendered{kRenderedFrames};

  // A RainFrame to render into: a new one until kRenderedFrames exist, then one the writer has
  // released; nothing once stopped.
  std::unique_ptr<rain::RainFrame> acquire() {
    if (made_ < kRenderedFrames) {
      ++made_;
      return std::make_unique<rain::RainFrame>();
    }
    auto f = free_.pop();
    return f ? std::move(*f) : nullptr;
  }
  void release(std::unique_ptr<rain::RainFrame> f) { (void)free_.push(std::move(f)); }

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
  BoundedQueue<std::unique_ptr<rain::RainFrame>> free_{kRenderedFrames};
  BoundedQueue<Image> spare_inputs_{kDecodedFrames + 2};
};

RainJobResult run_folder(const Run& run) {
  const RainJob& a = run.a;
  if (a.output) throw Error("-o: with --input-dir the frames go to --output-dir");
  if (!a.output_dir) throw Error("--output-dir: give the folder for the rainy frames (with --input-dir)");
  if (a.depth) throw Error("--depth: one depth map serves one --image; give a folder's maps with --depth-dir");
  if (a.mask_out) throw Error("--mask-out: with --input-dir give --mask-dir for the masks");
  if (a.layer_out) throw Error("--layer-out: available with --image");
  if (a.crf_given) throw Error("--crf: sets the H.264 quality of --video's output; --input-dir writes pictures");
  if (a.depth_scale_given && !a.depth_dir) throw Error("--depth-scale-m: scales PNG maps of --depth-dir; none is given");
  const FrameFolderRequest request{*a.input_dir, *a.output_dir, a.mask_dir, a.depth_dir};
  const FrameFolder plan = plan_frame_folder(request);
  if (!plan.skipped.empty()) run.warn(plan.skipped_warning(*a.input_dir));
  const fs::path out_dir(*a.output_dir);
  const auto& frames = plan.frames;
  // Every file the run reads or writes, declared before any work: an output on an input (a
  // --stats-json naming a frame, a link in --output-dir to a frame) or two outputs on one path are
  // refused here, whichever folders they are in.
  FileSet files;
  declare_frame_folder(files, plan, request);
  OutputFile* stats = a.stats_json ? &files.output("--stats-json", *a.stats_json) : nullptr;
  create_output_folders(request);

  // A frame that cannot be used (unreadable, truncated, of another size, a non-finite value) is named
  // and left out, the others written, and the run ends with the list, as the batch job does: found
  // only by decoding, it would otherwise cost a second pass over every frame before the work.
  //
  // Three stages overlap over neighbouring frames (FramePipeline): one thread reads and decodes
  // frames in order, this one renders them in order (the rain field is one sequence; the renderer's
  // own loops use every core), and a third encodes and writes them in order, and does all the
  // bookkeeping a frame's end needs (its warnings, left out or written, statistics, progress), so
  // that everything is said and written in the order of the frames, as one frame at a time would.
  // Each stage is deterministic and sees the frames in order: the same bytes whatever the threads.
  std::optional<rain::RainRenderer> renderer;
  nlohmann::json per_frame = nlohmann::json::array();
  std::vector<std::string> failed;
  std::size_t written = 0;
  NegativeValues negatives;
  rain::RainStats last_stats;

  FramePipeline pipe;
  // Stage 1: read and decode; the codec's warnings travel with the frame, said when it is written.
  const auto read_stage = [&] {
    for (std::size_t k = 0; k < frames.size(); ++k) {
      DecodedFrame f;
      f.k = k;
      const Warn sink = [&f](const std::string& text) { f.warnings.push_back(text); };
      try {
        f.frame = run.read_image("--input-dir", frames[k].string(), sink, false, FramePipeline::kExtraBytesPerPixel);
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
  };
  // Stage 3: encode and write, in order.
  const auto write_stage = [&] {
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
          failed.push_back(frames[k].filename().string());
          continue;
        }
      }
      const rain::RainFrame& result = *item->result;
      const fs::path& out_name = plan.outputs[k];
      const auto format = out_name.extension() == ".exr" ? ImageFormat::exr : ImageFormat::png;
      write_file(out_dir / out_name, run.h.codec.encode(result.image, format, png_options(a, 8)), "--output-dir");
      if (a.mask_dir)
        write_file(fs::path(*a.mask_dir) / out_name,
                   run.h.codec.encode(coverage_for_encoding(result.alpha, format), format, png_options(a, 16)),
                   "--mask-dir");
      ++written;
      negatives.add(result.stats);
      last_stats = result.stats;
      if (stats) {
        auto j = rain_stats_json(result.stats);
        j["frame_index"] = a.files.frame_index + std::int64_t(k);
        j["input"] = frames[k].filename().string();
        per_frame.push_back(std::move(j));
      }
      pipe.release(std::move(item->result));
      run.progress(double(k + 1) / double(frames.size()), fmt::format("frame {}/{}", k + 1, frames.size()));
    }
  };
  // Stage 2, on this thread: render in order.
  const auto render_stage = [&] {
    while (auto f = pipe.decoded.pop()) {
      RenderedFrame out;
      out.k = f->k;
      out.warnings = std::move(f->warnings);
      out.error = f->error;
      const std::string name = frames[f->k].string();
      if (!out.error) {
        try {
          const Image& frame = f->frame;
          if (!renderer) {
            const rain::RainCamera cam = rain::camera_for(a.options, frame.width, frame.height);
            rain::check_render_memory(cam, frame.channels, false, "--input-dir " + name,
                                      FramePipeline::kExtraBytesPerPixel);
            renderer.emplace(run.make_renderer(cam, !a.depth_dir));
          } else if (const auto& c = renderer->field().camera(); frame.width != c.width || frame.height != c.height) {
            throw IoError(fmt::format("--input-dir {}: is {}x{}, unlike the first frame ({}x{}); one sequence has one size",
                                      name, frame.width, frame.height, c.width, c.height));
          }
          if (f->depth_error) std::rethrow_exception(f->depth_error);
          auto result = pipe.acquire();
          if (!result) return;  // stopped
          render_frame(*renderer, frame, a.depth_dir ? &f->depth : nullptr, a.files.frame_index + std::int64_t(f->k),
                       false, *result, "--input-dir " + name);
          out.result = std::move(result);
        } catch (...) {
          out.error = std::current_exception();
        }
      }
      if (!pipe.rendered.push(std::move(out))) return;
    }
    pipe.rendered.close();
  };
  pipe.run(read_stage, render_stage, write_stage);
  run.finish_progress();
  negatives.report(run, "--input-dir " + *a.input_dir, frames.size());
  if (stats) {
    auto j = run.run_json(renderer->field());
    j["input"] = *a.input_dir;
    j["frames"] = std::move(per_frame);
    if (!failed.empty()) j["left_out"] = failed;
    stats->write(j.dump(2) + "\n");
  }
  files.commit();
  auto out = run.result(*renderer, last_stats, frames.size() - failed.size(), frames.size());
  out.left_out = std::move(failed);
  return out;
}

// The video's own frame rate, size and the exposure it allows, said in the video's terms.
void check_video_camera(const rain::RainCamera& cam, const std::string& video) {
  try {
    rain::validate(cam);
  } catch (const DomainError& e) {
    if (e.quantity() == "fps" || e.quantity() == "width" || e.quantity() == "height")
      throw Error(fmt::format("--video {}: its {} {:g} is {}", video,
                              e.quantity() == "fps" ? "frame rate (1/s)" : e.quantity().c_str(), e.value(),
                              e.range_text()));
    if (e.quantity() == "exposure_s")
      throw Error(fmt::format("--exposure-s {:g}: is longer than one frame of --video {} ({:g} frames/s); at most {:g} s",
                              e.value(), video, cam.fps, 1.0 / cam.fps));
    throw;
  }
}

RainJobResult run_video(const Run& run) {
  const RainJob& a = run.a;
  if (!a.output) throw Error("-o: give the output video (.mp4, .mov or .mkv)");
  if (a.depth || a.depth_dir) throw Error("--depth: depth maps are for --image and --input-dir; video frames use the ground plane");
  if (a.mask_out || a.mask_dir || a.layer_out || a.output_dir)
    throw Error("--video writes one video (-o) and optionally --stats-json; masks are for --image and --input-dir");
  if (a.options.fps) throw Error("--fps: a video's frame rate is its own");
  if (a.depth_scale_given) throw Error("--depth-scale-m: scales PNG depth maps, which are for --image and --input-dir");
  const std::string ext = lower_extension(*a.output);
  if (std::find(std::begin(kVideoExtensions), std::end(kVideoExtensions), ext) == std::end(kVideoExtensions))
    throw Error(fmt::format("-o {}: expected a .mp4, .mov or .mkv file", *a.output));
  FileSet files;
  files.input("--video", *a.video);
  OutputFile& out = files.output("-o", *a.output);
  OutputFile* stats = a.stats_json ? &files.output("--stats-json", *a.stats_json) : nullptr;
  const VideoApi& api = video_api();
  const InputFile input(*a.video, "--video");

  auto reader = api.open_reader([&input](std::uint64_t off, char* buf, std::size_t n) { return input.read_at(off, buf, n); },
                                input.size(), fmt::format("--video {}", *a.video), VideoLimits{});
  const VideoInfo info = reader->info();
  rain::RainCamera cam = rain::camera_for(a.options, info.width, info.height);
  cam.fps = info.fps();
  check_video_camera(cam, *a.video);
  rain::check_render_memory(cam, 3, false, "--video " + *a.video, FramePipeline::kExtraBytesPerPixel);
  rain::RainRenderer renderer = run.make_renderer(cam, true);
  auto writer = api.open_writer([&out](std::uint64_t off, std::string_view bytes) { out.write_at(off, bytes); }, ext,
                                info, a.files.crf, fmt::format("-o {}", *a.output));
  const color::Srgb8Tables tables;
  nlohmann::json per_frame = nlohmann::json::array();
  NegativeValues negatives;
  rain::RainStats last_stats;
  std::int64_t k = 0;  // frames written
  // The frame count for the progress: the container's, else the duration times the rate (Matroska).
  const std::int64_t expected = info.frame_count > 0 ? info.frame_count
                                : info.duration_s > 0 ? std::llround(info.duration_s * info.fps())
                                                      : -1;
  // Three overlapping stages, as for a folder (FramePipeline): this thread renders in order while one
  // decodes the next frames and another encodes the last ones, in order, so the encoder's time is
  // not added to the renderer's; the same bytes as one frame at a time. A decoding, rendering or
  // encoding failure ends the run (a video has no frame to leave out).
  FramePipeline pipe;
  const auto read_stage = [&] {
    VideoFrame in_frame;
    for (std::size_t n = 0; reader->read(in_frame); ++n) {
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
  };
  const auto render_stage = [&] {
    while (auto f = pipe.decoded.pop()) {
      auto result = pipe.acquire();
      if (!result) return;  // stopped
      render_frame(renderer, f->frame, nullptr, a.files.frame_index + std::int64_t(f->k), false, *result,
                   "--video " + *a.video);
      pipe.recycle_input(std::move(f->frame));
      RenderedFrame rendered;
      rendered.k = f->k;
      rendered.result = std::move(result);
      if (!pipe.rendered.push(std::move(rendered))) return;
    }
    pipe.rendered.close();
  };
  const auto write_stage = [&] {
    VideoFrame out_frame;
    while (auto item = pipe.rendered.pop()) {
      const rain::RainFrame& result = *item->result;
      const Image& img = result.image;
      out_frame.width = img.width;
      out_frame.height = img.height;
      out_frame.rgb.resize(std::size_t(img.width) * img.height * 3);
      tables.to_srgb8(img.pixels.data(), std::size_t(img.width) * img.height, img.channels, out_frame.rgb.data());
      writer->write(out_frame);
      negatives.add(result.stats);
      last_stats = result.stats;
      if (stats) {
        auto j = rain_stats_json(result.stats);
        j["frame_index"] = a.files.frame_index + k;
        per_frame.push_back(std::move(j));
      }
      pipe.release(std::move(item->result));
      ++k;
      if (expected > 0) run.progress(std::min(1.0, double(k) / double(expected)), fmt::format("frame {}/{}", k, expected));
    }
  };
  pipe.run(read_stage, render_stage, write_stage);
  writer->finish();
  run.finish_progress();
  negatives.report(run, "--video " + *a.video, std::size_t(k));
  if (stats) {
    auto j = run.run_json(renderer.field());
    j["input"] = *a.video;
    j["video"] = {{"codec", info.codec}, {"fps_num", info.fps_num}, {"fps_den", info.fps_den}, {"frames", k},
                  {"crf", a.files.crf}};
    j["frames"] = std::move(per_frame);
    stats->write(j.dump(2) + "\n");
  }
  files.commit();
  return run.result(renderer, last_stats, std::size_t(k), std::size_t(k));
}

}  // namespace

RainJobResult run_rain_job(const RainJob& a, const RainJobHooks& hooks) {
  const int modes = int(a.image.has_value()) + int(a.input_dir.has_value()) + int(a.video.has_value());
  if (modes != 1) throw Error("give exactly one of --image, --input-dir and --video");
  if (a.output_dir && !a.input_dir) throw Error("--output-dir: goes with --input-dir");
  if (a.mask_dir && !a.input_dir) throw Error("--mask-dir: goes with --input-dir (use --mask-out with --image)");
  if (a.depth_dir && !a.input_dir) throw Error("--depth-dir: goes with --input-dir (use --depth with --image)");
  rain::rain_param("png_compression").check(double(a.files.png_compression));  // the declared range (params.cpp)
  if (const auto name = rain::fog_setting_without_fog(a.options); !name.empty())
    throw Error(fmt::format("{}: sets the fog; give --visibility-m or --lwc-g-m3 with it", rain::rain_param(name).flag));
  const Run run{a, hooks, Clock::now(), {}};
  if (a.image) return run_image(run);
  if (a.input_dir) return run_folder(run);
  return run_video(run);
}

std::string rain_summary(const RainJobResult& r) {
  const auto& st = r.last;
  return fmt::format(
      "rain: {} frame{} at {:g} mm/h; {} drops in the field, {} streaks in view (length p50 {:.1f} px, p95 "
      "{:.1f} px); drops {:.2f}x the luminance under them; {:.2f} s ({:.1f} frames/s)",
      r.frames, r.frames == 1 ? "" : "s", r.rate_mmh, r.drops, st.drops_in_view, st.streak_length_px_p50,
      st.streak_length_px_p95,
      st.background_luminance_mean > 0 ? st.drop_luminance_mean / st.background_luminance_mean : 0.0, r.seconds,
      r.seconds > 0 ? double(r.frames) / r.seconds : 0.0);
}

}  // namespace hydrolux::io
