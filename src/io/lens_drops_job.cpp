// A lens-drops run over files (lens_drops_job.hpp): the photograph and folder modes of
// `hydrolux lens-drops`, on the same checked file paths and folder planning as `hydrolux rain`.
#include "hydrolux/io/lens_drops_job.hpp"

#include <fmt/format.h>

#include <chrono>
#include <filesystem>

#include "hydrolux/core/error.hpp"
#include "hydrolux/io/files.hpp"
#include "hydrolux/io/frames.hpp"
#include "hydrolux/rain/rain.hpp"

namespace hydrolux::io {

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
using Warn = std::function<void(const std::string&)>;

static_assert(rain::LensDropsFileOptions{}.png_compression == kDefaultPngCompression, "one default for PNG files");

// A frame; one too large for the memory left is refused from its header, before its pixels are
// decoded, naming what would fit.
Image read_image(const ImageCodec& codec, const rain::LensDropSettings& s, const std::string& flag,
                 const std::string& path, const Warn& warn) {
  const std::string bytes = read_file(path, ImageLimits{}.max_file_bytes, flag);
  const std::string origin = fmt::format("{} {}", flag, path);
  ImageLimits limits;
  limits.before_pixels = [&](std::int64_t w, std::int64_t h, std::int64_t c) {
    rain::check_lens_drops_memory(s, origin, int(w), int(h), int(c));
  };
  auto decoded = codec.decode(bytes, origin, limits);
  for (const auto& w : decoded.warnings)
    if (warn) warn(fmt::format("{}: {}", origin, w));
  return std::move(decoded.image);
}

// The library's error on a frame, said with the frame's name.
rain::LensDropsResult render(const Image& frame, const rain::LensDropSettings& s, const std::string& origin) {
  try {
    return rain::render_lens_drops(frame, s);
  } catch (const DomainError&) {
    throw;  // a setting: the CLI names its flag
  } catch (const Error& e) {
    throw Error(fmt::format("{}: {}", origin, e.what()));
  }
}

void warn_negative(const rain::LensDropsResult& r, const std::string& origin, const Warn& warn) {
  if (r.negative_values_clamped > 0 && warn)
    warn(fmt::format("{}: {} negative values read as 0 (light cannot be negative)", origin, r.negative_values_clamped));
}

LensDropsJobResult summary(const rain::LensDropsResult& r, std::size_t frames, Clock::time_point start) {
  LensDropsJobResult out;
  out.frames = frames;
  out.drops = r.drops;
  out.coverage = r.coverage;
  out.blur_diameter_px = r.blur_diameter_px;
  out.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  return out;
}

LensDropsJobResult run_image(const LensDropsJob& a, const ImageCodec& codec, const Warn& warn) {
  const auto start = Clock::now();
  if (a.output_dir) throw Error("--output-dir: goes with --input-dir (use -o with --image)");
  if (a.mask_dir) throw Error("--mask-dir: goes with --input-dir (use --mask-out with --image)");
  if (!a.output) throw Error("-o: give the output image (.png or .exr)");
  FileSet files;
  files.input("--image", *a.image);
  const ImageFormat out_format = output_image_format(*a.output, "-o");
  OutputFile& out = files.output("-o", *a.output);
  OutputFile* mask = nullptr;
  ImageFormat mask_format = ImageFormat::png;
  if (a.mask_out) {
    mask_format = output_image_format(*a.mask_out, "--mask-out");
    mask = &files.output("--mask-out", *a.mask_out);
  }
  const Image frame = read_image(codec, a.settings, "--image", *a.image, warn);
  const auto r = render(frame, a.settings, "--image " + *a.image);
  warn_negative(r, "--image " + *a.image, warn);
  if (mask)
    mask->write(codec.encode(coverage_for_encoding(r.mask, mask_format), mask_format,
                             PngOptions{16, a.files.png_compression}));
  out.write(codec.encode(r.image, out_format, PngOptions{8, a.files.png_compression}));
  files.commit();
  auto result = summary(r, 1, start);
  result.frames_total = 1;
  return result;
}

LensDropsJobResult run_folder(const LensDropsJob& a, const ImageCodec& codec, const Warn& warn) {
  const auto start = Clock::now();
  if (a.output) throw Error("-o: with --input-dir the frames go to --output-dir");
  if (a.mask_out) throw Error("--mask-out: with --input-dir give --mask-dir for the masks");
  if (!a.output_dir) throw Error("--output-dir: give the folder for the frames with drops (with --input-dir)");
  const FrameFolderRequest request{*a.input_dir, *a.output_dir, a.mask_dir, std::nullopt};
  const FrameFolder plan = plan_frame_folder(request);
  if (!plan.skipped.empty() && warn) warn(plan.skipped_warning(*a.input_dir));
  const fs::path out_dir(*a.output_dir);
  FileSet files;
  declare_frame_folder(files, plan, request);
  // The settings are checked before any folder is made (a frame's size is not needed for that).
  (void)rain::place_lens_drops(a.settings, 1, 1);
  create_output_folders(request);
  // A frame that cannot be used is named and left out once one frame is written (as rain and fog
  // do); the first frame's failure is bad input, nothing written.
  rain::LensDropsResult last;
  std::size_t written = 0;
  std::vector<std::string> left_out;
  for (std::size_t k = 0; k < plan.frames.size(); ++k) {
    const std::string name = plan.frames[k].string();
    try {
      const Image frame = read_image(codec, a.settings, "--input-dir", name, warn);
      rain::LensDropSettings s = a.settings;
      s.seed = (a.settings.seed + k) % (rain::kMaxSeed + 1);
      last = render(frame, s, "--input-dir " + name);
      warn_negative(last, "--input-dir " + name, warn);
      const fs::path& out_name = plan.outputs[k];
      const auto format = out_name.extension() == ".exr" ? ImageFormat::exr : ImageFormat::png;
      write_file(out_dir / out_name, codec.encode(last.image, format, PngOptions{8, a.files.png_compression}),
                 "--output-dir");
      if (a.mask_dir)
        write_file(fs::path(*a.mask_dir) / out_name,
                   codec.encode(coverage_for_encoding(last.mask, format), format, PngOptions{16, a.files.png_compression}),
                   "--mask-dir");
      ++written;
    } catch (const IoFailure&) {
      throw;
    } catch (const Error& e) {
      if (written == 0) throw;
      if (warn) warn(fmt::format("{} (left out)", e.what()));
      left_out.push_back(plan.frames[k].filename().string());
    }
  }
  files.commit();
  auto r = summary(last, written, start);
  r.frames_total = plan.frames.size();
  r.left_out = std::move(left_out);
  return r;
}

}  // namespace

LensDropsJobResult run_lens_drops_job(const LensDropsJob& a, const ImageCodec& codec, const Warn& warn) {
  if (int(a.image.has_value()) + int(a.input_dir.has_value()) != 1)
    throw Error("give exactly one of --image and --input-dir");
  return a.image ? run_image(a, codec, warn) : run_folder(a, codec, warn);
}

std::string lens_drops_summary(const LensDropsJobResult& r) {
  return fmt::format("lens-drops: {} frame{}; {} drops covering {:.1f}% of the frame, blurred by a {:.1f} px circle of "
                     "confusion; {:.2f} s",
                     r.frames, r.frames == 1 ? "" : "s", r.drops, 100 * r.coverage, r.blur_diameter_px, r.seconds);
}

}  // namespace hydrolux::io
