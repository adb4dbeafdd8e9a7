// The CLI's side of a Lee table's files: see lee_files.hpp.
#include "lee_files.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <optional>

#include "common.hpp"
#include "hydrolux/core/error.hpp"
#include "hydrolux/core/memory.hpp"
#include "hydrolux/core/parse.hpp"
#include "hydrolux/io/netcdf.hpp"
#include "image_plugin.hpp"

namespace hydrolux::cli {

io::LeeFileBytes encode_lee_files(const atmos::LeeTable& t, const atmos::LeeImages& im) {
  return io::encode_lee_files(t, im, image_api().encode_image);
}

void set_wavelengths_flag(atmos::LeeSpec& s, const std::string& w) {
  const auto colons = std::count(w.begin(), w.end(), ':');
  const auto bad = [&] {
    return Error(fmt::format("--wavelengths-nm '{}': expected A:B or A:B:N (nanometres in [360, 830], A <= B; N "
                             "samples in [1, 2000])",
                             w));
  };
  std::optional<std::array<double, 2>> p;
  if (colons == 2) {
    const auto last = w.rfind(':');
    p = parse::pair(w.substr(0, last), ':');
    const auto n = parse::integer(w.substr(last + 1));
    if (!n || *n < 1 || *n > 2000) throw bad();
    s.wavelengths = int(*n);
  } else if (colons == 1) {
    p = parse::pair(w, ':');
  }
  if (!p || (*p)[1] < (*p)[0]) throw bad();
  s.wavelength_min_nm = (*p)[0];
  s.wavelength_max_nm = (*p)[1];
}

LeeOutputs declare_lee_outputs(io::FileSet& files, const std::string& exr_path) {
  const std::filesystem::path p(exr_path);
  LeeOutputs o;
  const std::string ext = io::lower_extension(p);  // as every output's format: whatever the case
  if (ext == ".nc") {
    o.netcdf = &files.output("-o", exr_path);
    (void)io::netcdf_api();  // NetCDF support loads now, not after the work
    return o;
  }
  if (ext != ".exr")
    throw Error(fmt::format("-o {}: give a .exr path (the table as OpenEXR, with a .png and a .json beside it) or a "
                            ".nc path (one NetCDF-4 file with CF attributes)",
                            printable(exr_path)));
  o.exr_path = exr_path;
  o.png_path = std::filesystem::path(p).replace_extension(".png").string();
  o.json_path = std::filesystem::path(p).replace_extension(".json").string();
  o.exr = declare_output_image(files, "-o", o.exr_path);
  o.png = declare_output_image(files, "-o (its .png)", o.png_path);
  o.sidecar = &files.output("-o (its .json)", o.json_path);
  (void)image_api();  // image support loads now, not after the work
  return o;
}

void LeeOutputs::write(const atmos::LeeTable& t, const atmos::LeeImages& im) const {
  if (netcdf) {
    netcdf->write(io::netcdf_api().encode(io::lee_dataset(t, im, history_line(command_line()))));
    return;
  }
  const io::LeeFileBytes bytes = encode_lee_files(t, im);
  exr.file->write(bytes.exr);
  png.file->write(bytes.png);
  sidecar->write(io::lee_sidecar(t, im, std::filesystem::path(exr_path).filename().string(),
                                    std::filesystem::path(png_path).filename().string())
                     .dump(1) +
                 "\n");
}

std::string LeeOutputs::describe() const {
  if (netcdf) return printable(netcdf->target().string());
  return fmt::format("{}, {} and {}", printable(exr_path), printable(png_path), printable(json_path));
}

nlohmann::json write_engine_table(io::OutputDirectory& dir, const std::string& name, const atmos::LeeTable& t) {
  const atmos::LeeImages im = atmos::lee_images(t);
  const io::LeeFileBytes bytes = encode_lee_files(t, im);
  nlohmann::json side = io::lee_sidecar(t, im, name + ".exr", name + ".png");
  side["files"]["f32"] = name + ".f32";
  side["f32_layout"] =
      "little-endian float32, rows x columns x 3 (R, G, B as in the EXR), row-major: value (row j, column i, "
      "channel c) at index (j * width + i) * 3 + c";
  // A Stokes table's Q for shaders: <name>_q.f32 in the .f32's layout, the compositor's RGB Q
  // (scene::bow_table: Q's XYZ through xyz_to_rgb, not gamut-mapped, signed).
  std::string q_bytes;
  if (t.spec.stokes) {
    const std::vector<float> q = scene::bow_table(t).q;
    q_bytes.resize(q.size() * sizeof(float));
    std::memcpy(q_bytes.data(), q.data(), q_bytes.size());
    side["files"]["f32_q"] = name + "_q.f32";
    side["f32_q_layout"] =
        "the Stokes Q (see stokes) as linear RGB in f32's layout: the EXR's Q.X, Q.Y, Q.Z through "
        "color_space.xyz_to_rgb, not gamut-mapped (signed: > 0 polarised normal to the scattering plane, tangential "
        "to the bow); a linear polariser passes max((R,G,B + Q cos 2(chi - A)) / 2, 0), chi the angle of the "
        "scattering plane's normal in the image, A the polariser's axis";
  }
  dir.write(name + ".exr", bytes.exr);
  dir.write(name + ".png", bytes.png);
  dir.write(name + ".f32", bytes.f32);
  if (!q_bytes.empty()) dir.write(name + "_q.f32", q_bytes);
  dir.write(name + ".json", side.dump(1) + "\n");
  nlohmann::json files = {name + ".exr", name + ".png", name + ".f32", name + ".json"};
  if (!q_bytes.empty()) files.push_back(name + "_q.f32");
  nlohmann::json entry = {{"kind", atmos::table_kind_name(t.spec.table)},
                          {"columns", t.columns()},
                          {"rows", t.rows()},
                          {"radius_um", {t.radius_um.front(), t.radius_um.back()}},
                          {"angle_deg", {t.angle_deg.front(), t.angle_deg.back()}},
                          {"files", files}};
  if (!q_bytes.empty()) entry["stokes_q"] = name + "_q.f32";
  return entry;
}

void check_table_memory(const std::vector<const atmos::LeeSpec*>& specs, const std::string& size_text) {
  atmos::check_table_memory(specs, size_text, atmos::SizeSyntax::cli);  // the library's one check
}

// A frame too large for the memory left is refused before the work, naming what would fit.
void check_sky_memory(const scene::SkySettings& s, const std::string& size_text) {
  const double need = scene::estimated_bytes(s), avail = double(available_memory_bytes());
  if (need <= avail) return;
  const double cube = s.mode == scene::BowMode::cube_map
                          ? scene::kSkyBytesPerCubeTexel * double(s.cube_face_size) * s.cube_face_size
                          : 0;
  const double frame = need - cube - scene::kSkyFixedBytes;
  const double room = avail - scene::kSkyFixedBytes;
  if (cube > frame) {
    const double fits = std::floor(std::sqrt(std::max(0.0, room - frame) / scene::kSkyBytesPerCubeTexel));
    throw Error(fmt::format("--cube-face-size {}: the frame and its cube map need about {} of memory and {} is "
                            "available; faces of at most {:g} texels fit",
                            s.cube_face_size, format_bytes(need), format_bytes(avail), std::max(0.0, fits)));
  }
  const double pixels = double(s.camera.width) * s.camera.height;
  const double fit_pixels = std::max(0.0, room - cube) / scene::kSkyBytesPerPixel;
  const double k = std::sqrt(fit_pixels / pixels);
  throw Error(fmt::format("--size {}: the frame needs about {} of memory and {} is available; at most about {:.0f} "
                          "megapixels fit (--size {:.0f}x{:.0f} at this aspect)",
                          size_text, format_bytes(need), format_bytes(avail), fit_pixels / 1e6,
                          std::floor(s.camera.width * k), std::floor(s.camera.height * k)));
}

scene::BowTable read_lee_lut(const std::string& flag, const std::string& exr_path) {
  const std::filesystem::path p(exr_path);
  const std::string json_path = std::filesystem::path(p).replace_extension(".json").string();
  const auto bad = [&](const std::string& what) {
    return Error(fmt::format("{} {}: {} (a table written by hydrolux lee or hydrolux export, with its .json sidecar "
                             "beside it)",
                             flag, printable(exr_path), what));
  };
  if (io::lower_extension(p) != ".exr") throw bad("expected a .exr file");
  const std::string text = io::read_file(json_path, std::uint64_t(64) << 20, flag + " (its .json sidecar)");
  io::LeeSidecarAxes axes;
  try {
    axes = io::parse_lee_sidecar(text);
  } catch (const Error& e) {
    throw bad(fmt::format("its sidecar {}: {}", printable(json_path), e.what()));
  }
  // The content decides, not the name: a PNG renamed .exr decodes to display values in [0, 1].
  const io::DecodedImage decoded = read_input_decoded(flag, exr_path);
  try {
    return io::lee_bow_table(std::move(axes), decoded);
  } catch (const Error& e) {
    throw bad(e.what());
  }
}

SkySlices read_sky_luts(const std::vector<std::string>& luts, double radius_um, bool corona) {
  SkySlices out;
  bool have_rainbow = false;
  for (const auto& l : luts) {
    const scene::BowTable t = read_lee_lut("--lut", l);
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

}  // namespace hydrolux::cli
