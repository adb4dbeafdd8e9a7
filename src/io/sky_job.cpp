// hydrolux sky's run over files: see hydrolux/io/sky_job.hpp.
#include "hydrolux/io/sky_job.hpp"

#include <fmt/format.h>

#include <chrono>
#include <filesystem>
#include <memory>
#include <optional>
#include <utility>
#include <vector>

#include "hydrolux/core/error.hpp"
#include "hydrolux/io/files.hpp"
#include "hydrolux/io/lee_files.hpp"
#include "hydrolux/scene/bow_tables.hpp"
#include "hydrolux/scene/environment.hpp"
#include "hydrolux/scene/sky_scene.hpp"

namespace hydrolux::io {

namespace {

using Warn = std::function<void(const std::string&)>;

Warn warner(const SkyJobHooks& h) {
  return [&h](const std::string& text) {
    if (h.warn) h.warn(text);
  };
}

SkySlices given_tables(const SkyJob& a, const scene::SkySettings& s, const SkyJobHooks& h) {
  SkySlices t = read_sky_luts(h.codec, a.luts, s.radius_um, s.corona, warner(h));
  // A polariser or the Stokes images need the tables' Stokes Q: the compositor's one check.
  scene::check_polarization(s, t.rainbow.has_q(), t.corona.empty() || t.corona.has_q(), Door::cli);
  return t;
}

std::shared_ptr<const scene::Environment> read_environment(const SkyJob& a, const SkyJobHooks& h) {
  if (!a.environment) return nullptr;
  Image image = read_decoded(h.codec, "--environment", *a.environment, warner(h)).image;
  try {
    return std::make_shared<scene::EquirectEnvironment>(std::move(image));
  } catch (const Error& e) {
    throw Error(fmt::format("--environment {}: {}", *a.environment, e.what()));  // printed through printable()
  }
}

}  // namespace

SkyJobResult run_sky_job(const SkyJob& a, const SkyJobHooks& h) {
  const auto start = std::chrono::steady_clock::now();
  const scene::SkyOptions& o = a.options;
  const scene::SkySettings& s = o.settings;
  scene::validate(s);
  atmos::DropShapeSpec shape;
  try {
    shape = atmos::parse_drop_shape(o.shape);
  } catch (const Error& e) {
    throw Error(fmt::format("--{}", e.what()));  // the library's message starts "shape '<value>': "
  }
  const bool tables_given = !a.luts.empty();
  scene::check_sky_request(o, shape, tables_given, Door::cli);
  scene::refuse_unused_sky_params(
      o, [&](std::string_view name) { return a.given.count(name) > 0; }, tables_given, a.environment.has_value(),
      Door::cli);
  if (a.output.empty()) throw Error("-o is required (a .png or .exr path)");
  scene::check_sky_memory(s, Door::cli);

  // Every file is checked before the work.
  FileSet files;
  for (const auto& l : a.luts) {
    files.input("--lut", l);
    files.input("--lut (its .json sidecar)", std::filesystem::path(l).replace_extension(".json"));
  }
  if (a.moisture) files.input("--moisture", *a.moisture);
  if (a.environment) files.input("--environment", *a.environment);
  const ImageFormat format = output_image_format(a.output, "-o");
  OutputFile& out = files.output("-o", a.output);
  if (s.stokes && format != ImageFormat::exr)
    throw Error(fmt::format("--stokes: the Stokes images are linear and signed: -o must be a .exr (got {})",
                            printable(a.output)));
  if (h.codec_ready) h.codec_ready();

  // The tables given are read (and checked) first, then the images, before any work.
  SkySlices tables;
  if (tables_given) tables = given_tables(a, s, h);
  const std::shared_ptr<const scene::Environment> env = read_environment(a, h);
  std::optional<Image> moisture;
  if (a.moisture) moisture = read_decoded(h.codec, "--moisture", *a.moisture, warner(h)).image;

  scene::RainbowSlices rainbow(std::move(tables.rainbow));
  scene::ProfileAccuracy accuracy;
  if (!tables_given) {  // this radius's tables, computed now
    scene::SkyTables computed = scene::compute_sky_tables(o, shape, h.progress);
    rainbow = std::move(computed.rainbow);
    tables.corona = std::move(computed.corona);
    accuracy = scene::profile_accuracy(rainbow, tables.corona);
  }
  const scene::SkyCompositor comp(s, std::move(rainbow), std::move(tables.corona), env, o.environment_scale);
  const auto t0 = std::chrono::steady_clock::now();
  const Image radiance = comp.render(moisture ? &*moisture : nullptr);
  SkyJobResult r;
  r.render_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  if (h.finish_progress) h.finish_progress();
  // The PNG's exposure: a polariser passes half of unpolarised light, for which a camera opens up one
  // stop; the EXR stays absolute.
  out.write(h.codec.encode(format == ImageFormat::exr
                               ? radiance
                               : scene::tone_map(radiance, comp.sun_sky().l_ref * (s.polarizer_deg ? 0.5 : 1.0)),
                           format, PngOptions{}));
  files.commit();
  // The profiles' accuracy once the frame is written (a failure before it is the one line said).
  if (auto note = scene::sky_profile_note(accuracy.error, accuracy.sampling, Door::cli)) warner(h)(*note);
  r.settings = s;
  r.output = a.output;
  r.shape = atmos::drop_shape_name(shape);
  r.shaped = !shape.spherical();
  r.positions = comp.rainbow_positions();
  r.optical_depth = comp.beta_geo_per_m() * (s.curtain_far_m - s.curtain_near_m);
  r.sun_illuminance_lux = comp.sun_sky().sun_illuminance_lux;
  r.bake_ms = comp.bake_seconds() * 1e3;
  r.profile_error = accuracy.error;
  r.profile_sampling = accuracy.sampling;
  r.sampling_automatic = !tables_given && !o.sampling;
  r.profile_first_error = accuracy.first_error;
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return r;
}

namespace {

// "sampling up to 2, chosen because 1 gave up to 1.9%", "sampling 1, chosen", "sampling 0.5": how the profiles'
// sampling came about.
std::string profile_sampling_text(const SkyJobResult& r) {
  if (!r.sampling_automatic) return fmt::format("sampling {:g}", r.profile_sampling);
  if (!r.profile_first_error) return fmt::format("sampling {:g}, chosen", r.profile_sampling);
  return fmt::format("sampling up to {:g}, chosen because 1 gave up to {:.2g}%", r.profile_sampling,
                     100 * *r.profile_first_error);
}

}  // namespace

std::string sky_summary(const SkyJobResult& r) {
  const scene::SkySettings& s = r.settings;
  return fmt::format(
      "sky: wrote {} ({}x{}, {}, {} blend{}); rain {:g} mm/h: optical depth {:.3g} (projected area) over the curtain; "
      "sun {:.0f} klux;{}{} frame {:.1f} ms{}; {:.1f} s in all",
      printable(r.output), s.camera.width, s.camera.height, scene::bow_mode_name(s.mode), scene::blend_name(s.blend),
      s.polarizer_deg ? fmt::format(", polariser at {:g} deg", *s.polarizer_deg)
      : s.stokes      ? std::string(", Stokes I, Q, U")
                      : std::string(),
      s.rain_rate_mmh, r.optical_depth, r.sun_illuminance_lux / 1000,
      r.shaped ? fmt::format(" {} drops: the bow at {} position angles (Airy theory);", r.shape, r.positions)
               : std::string(),
      r.profile_error ? fmt::format(" the bow profiles' estimated error {:.2g}% RMS in luminance ({});",
                                    100 * *r.profile_error, profile_sampling_text(r))
                      : std::string(),
      r.render_ms, s.mode == scene::BowMode::per_pixel ? "" : fmt::format(" (bake {:.1f} ms)", r.bake_ms), r.seconds);
}

scene::BowTable read_lee_lut(const ImageCodec& codec, const std::string& flag, const std::string& exr_path,
                             const std::function<void(const std::string&)>& warn) {
  const std::filesystem::path p(exr_path);
  const std::string json_path = std::filesystem::path(p).replace_extension(".json").string();
  const auto bad = [&](const std::string& what) {
    return Error(fmt::format("{} {}: {} (a table written by hydrolux lee or hydrolux export, with its .json sidecar "
                             "beside it)",
                             flag, printable(exr_path), what));
  };
  if (lower_extension(p) != ".exr") throw bad("expected a .exr file");
  const std::string text = read_file(json_path, std::uint64_t(64) << 20, flag + " (its .json sidecar)");
  LeeSidecarAxes axes;
  try {
    axes = parse_lee_sidecar(text);
  } catch (const Error& e) {
    throw bad(fmt::format("its sidecar {}: {}", printable(json_path), e.what()));
  }
  // The content decides, not the name: a PNG renamed .exr decodes to display values in [0, 1].
  const DecodedImage decoded = read_decoded(codec, flag, exr_path, warn ? warn : [](const std::string&) {});
  try {
    return lee_bow_table(std::move(axes), decoded);
  } catch (const Error& e) {
    throw bad(e.what());
  }
}

SkySlices read_sky_luts(const ImageCodec& codec, const std::vector<std::string>& luts, double radius_um, bool corona,
                        const std::function<void(const std::string&)>& warn) {
  SkySlices out;
  bool have_rainbow = false;
  for (const auto& l : luts) {
    const scene::BowTable t = read_lee_lut(codec, "--lut", l, warn);
    const double lo = t.radius_um.front(), hi = t.radius_um.back();
    if (t.kind == atmos::LeeTableKind::rainbow) {
      if (have_rainbow) throw Error(fmt::format("--lut {}: a second rainbow table (give one per kind)", printable(l)));
      if (radius_um < lo * 0.999 || radius_um > hi * 1.001)
        throw Error(fmt::format("--radius-um {:g}: outside the radii of --lut {} [{:g}, {:g}] um", radius_um,
                                printable(l), lo, hi));
      out.rainbow = scene::slice_at_radius(t, radius_um);
      have_rainbow = true;
    } else if (t.kind == atmos::LeeTableKind::corona) {
      if (!out.corona.empty())
        throw Error(fmt::format("--lut {}: a second corona table (give one per kind)", printable(l)));
      out.corona = scene::slice_at_radius(t, radius_um, /*outside_is_empty=*/true);
    } else {
      throw Error(fmt::format("--lut {}: a {} table; the scene takes a rainbow table and optionally a corona table",
                              printable(l), atmos::table_kind_name(t.kind)));
    }
  }
  if (!have_rainbow)
    throw Error("--lut: no rainbow table among the tables given (hydrolux lee --table rainbow, or hydrolux export)");
  if (corona && out.corona.empty())
    throw Error(fmt::format("--corona: no corona table among --lut covers --radius-um {:g}, so nothing would be drawn "
                            "(give one: hydrolux lee --table corona, or hydrolux export; or omit --corona)",
                            radius_um));
  return out;
}

}  // namespace hydrolux::io
