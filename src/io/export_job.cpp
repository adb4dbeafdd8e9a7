// hydrolux export's run: see hydrolux/io/export_job.hpp.
#include "hydrolux/io/export_job.hpp"

#include <fmt/format.h>

#include <chrono>
#include <cstring>

#include "hydrolux/core/error.hpp"
#include "hydrolux/io/sky_report.hpp"
#include "hydrolux/scene/bow_tables.hpp"
#include "hydrolux/scene/compositor.hpp"
#include "hydrolux/version.hpp"

namespace hydrolux::io {

namespace {

// --size as the user wrote it ("512x1024"); empty where it was not given.
std::string size_text(const std::optional<std::array<int, 2>>& size) {
  return size ? fmt::format("{}x{}", (*size)[0], (*size)[1]) : std::string();
}

constexpr int kMaxCoronaRows = 16384;  // atmos::validate's largest side

// Non-spherical drops: the position-dependent rainbow table besides the spheres' (scene/bow_tables.hpp).
void shaped_table(const ExportJob& job, ExportTables& t) {
  const scene::ExportOptions& o = job.options;
  try {
    t.shape = atmos::parse_drop_shape(o.shape);
  } catch (const Error& e) {
    throw Error(fmt::format("--{}", e.what()));  // the library's message starts "shape '<value>': "
  }
  const bool shaped = !t.shape.spherical();
  if (!shaped && job.given.count("sun_elevation_deg"))
    throw Error(fmt::format("--sun-elevation-deg {:g}: sets the sun of the non-spherical drops' table (--shape); the "
                            "spheres' tables do not depend on it (omit it or give --shape)",
                            o.sun_elevation_deg));
  if (!shaped) return;
  // The table's own radii (5-800 um) are within every shape's range; one --radius-um may not be.
  scene::check_shape_radius(t.shape, t.rainbow.radius_max_um);
  if (t.rainbow.rows > scene::kShapedTableMaxRows)
    throw Error(fmt::format("--size {}: with --shape the rainbow's rows are also the 3-D table's, whose side is at "
                            "most {} (a 3-D texture's); H is at most {} with --shape",
                            size_text(job.options.size), scene::kShapedTableMaxRows, scene::kShapedTableMaxRows));
  t.shaped = scene::shaped_table_spec(t.rainbow, t.shape, o.sun_elevation_deg);
  atmos::validate(*t.shaped);
}

}  // namespace

ExportTables export_tables(const ExportJob& job) {
  const scene::ExportOptions& o = job.options;
  // The scene's tables (scene/bow_tables.hpp): --radius-um makes them one column, --size W columns
  // and H rows (the corona 2H).
  int columns = 0, rows = scene::kBowTableRows;
  if (o.size) {
    columns = (*o.size)[0];
    rows = (*o.size)[1];
  }
  ExportTables t;
  atmos::LeeSpec& rainbow = t.rainbow;
  atmos::LeeSpec& corona = t.corona;
  rainbow = scene::bow_table_spec(atmos::LeeTableKind::rainbow, o.radius_um, rows);
  corona = scene::bow_table_spec(atmos::LeeTableKind::corona, o.radius_um, rows);
  if (o.size) rainbow.columns = corona.columns = columns;
  try {
    rainbow.theory = corona.theory = scatter::parse_theory(job.theory);
  } catch (const Error& e) {
    throw Error(fmt::format("--theory {}: {}", job.theory, e.what()));
  }
  t.with_corona = !o.radius_um || *o.radius_um <= scene::kCoronaMaxRadiusUm;
  if (o.radius_um) {
    // The largest radius depends on the theory (the size parameter's limit): checked here, where it is known.
    const double rmax = atmos::max_radius_um(rainbow);
    if (*o.radius_um > rmax)
      throw Error(fmt::format("--radius-um {:g} is outside the valid range [{:g}, {:g}] um for --theory {} (the "
                              "largest drops of the 10% spread at 380 nm reach the theory's size parameter limit)",
                              *o.radius_um, atmos::kMinRadiusUm, rmax, scatter::theory_name(rainbow.theory)));
    if (o.size && columns != 1)
      throw Error(fmt::format("--size {}: one --radius-um makes one column; give --size 1x{}", size_text(job.options.size),
                              rows));
  }
  if (o.size && t.with_corona && corona.rows > kMaxCoronaRows)
    throw Error(fmt::format("--size {}: the corona table has twice H's rows ({}); H is at most {} (valid range "
                            "[1, {}] with the corona, which --radius-um above {:g} um leaves out)",
                            size_text(job.options.size), corona.rows, kMaxCoronaRows / 2, kMaxCoronaRows / 2,
                            scene::kCoronaMaxRadiusUm));
  // Unset: automatic, as hydrolux lee's (each table once more at up to atmos::kAutoSamplingMost where its
  // estimated error is above 1%).
  rainbow.sampling = corona.sampling = o.sampling.value_or(1);
  rainbow.sampling_most = corona.sampling_most = o.sampling ? 0.0 : atmos::kAutoSamplingMost;
  // The Stokes Q too (1.04x the time of I alone, BENCHMARKS.md): the tables' EXR gains Q.X, Q.Y, Q.Z
  // and the shaders a polariser (<name>_q.f32; the 3-D table's Q comes along, its spec derived from
  // this one).
  rainbow.stokes = corona.stokes = true;
  atmos::validate(rainbow);
  if (t.with_corona) atmos::validate(corona);
  shaped_table(job, t);
  return t;
}

ExportJobResult run_export_job(const ExportJob& job, const ExportJobHooks& h) {
  const scene::ExportOptions& o = job.options;
  const ExportTables t = export_tables(job);
  std::vector<const atmos::LeeSpec*> specs = {&t.rainbow};
  if (t.with_corona) specs.push_back(&t.corona);
  if (t.shaped) specs.push_back(&*t.shaped);
  atmos::check_table_memory(
      specs, job.options.size ? size_text(job.options.size) : fmt::format("{}x{} (the default)", t.rainbow.columns, t.rainbow.rows),
      atmos::SizeSyntax::cli);
  (void)scene::make_sun_sky(0, o.turbidity);  // checks the turbidity

  // The folders are staged beside their destinations and moved into place at the end.
  FileSet files;
  auto& top = files.output_directory("--dir", job.dir);
  if (h.codec_ready) h.codec_ready();

  const auto start = std::chrono::steady_clock::now();
  const auto progress = [&h](double from, double to) {
    return [&h, from, to](double f, std::string_view label) {
      if (h.progress) h.progress(from + f * (to - from), label);
    };
  };
  // The rainbow table is most of the work (larger drops, more partial waves); the 3-D table's 38
  // Airy tables of at most 128 columns about 30% of the whole (82 s against 57 s by default).
  const double shaped_share = t.shaped ? 0.3 : 0.0;
  const double share = (t.with_corona ? 0.85 : 1.0) * (1 - shaped_share);
  nlohmann::json manifest;
  manifest["format"] = "hydrolux-rainbow-assets";
  manifest["format_version"] = 1;
  manifest["hydrolux_version"] = kVersion;
  manifest["docs"] = "README.md here; docs/sky.md and docs/lee.md in the hydrolux sources";
  nlohmann::json tables = nlohmann::json::object();
  tables["rainbow"] = write_engine_table(top, "rainbow", atmos::compute_lee_table(t.rainbow, progress(0, share)),
                                         h.codec.encode);
  if (t.with_corona)
    tables["corona"] = write_engine_table(
        top, "corona", atmos::compute_lee_table(t.corona, progress(share, 1 - shaped_share)), h.codec.encode);
  if (t.shaped)
    tables["rainbow_shaped"] = write_shaped_rainbow_table(
        top, "rainbow_shaped",
        scene::compute_shaped_rainbow_table(t.rainbow, t.shape, o.sun_elevation_deg, progress(1 - shaped_share, 1)));
  if (h.finish_progress) h.finish_progress();

  top.write("sky.json", sky_parameters_json(o.turbidity).dump(1) + "\n");
  manifest["tables"] = tables;
  manifest["sky"] = "sky.json";
  manifest["shaders"] = write_engine_shaders(top);
  if (!t.with_corona)
    manifest["corona"] = fmt::format("not exported: drops of {:g} um put their corona within 0.2 degrees of the sun",
                                     *o.radius_um);
  top.write("manifest.json", manifest.dump(1) + "\n");
  files.commit();
  ExportJobResult r;
  r.files = top.files().size();
  r.with_corona = t.with_corona;
  r.shaped = t.shaped.has_value();
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return r;
}

std::string export_summary(const ExportJob& job, const ExportJobResult& r) {
  const scene::ExportOptions& o = job.options;
  return fmt::format("export: wrote {} ({} files, tables {}{}) in {:.1f} s", printable(job.dir), r.files,
                     r.with_corona ? "rainbow, corona" : "rainbow",
                     r.shaped ? fmt::format(", rainbow_shaped ({} drops, sun {:g} deg, {} positions)", o.shape,
                                            o.sun_elevation_deg, scene::kShapePositions)
                              : "",
                     r.seconds);
}

nlohmann::json write_engine_table(OutputDirectory& dir, const std::string& name, const atmos::LeeTable& t,
                                  const LeeImageEncoder& encode) {
  const atmos::LeeImages im = atmos::lee_images(t);
  const LeeFileBytes bytes = encode_lee_files(t, im, encode);
  nlohmann::json side = lee_sidecar(t, im, name + ".exr", name + ".png");
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

}  // namespace hydrolux::io
