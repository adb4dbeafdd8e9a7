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

}  // namespace hydrolux::cli
