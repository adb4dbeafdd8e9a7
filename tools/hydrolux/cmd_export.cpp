// hydrolux export: what an engine needs to draw the bow: the Lee tables (EXR, PNG, raw float32 and
// the JSON axes), the sun and sky parameters over the sun's elevation, and GLSL / HLSL that
// evaluate the sky, the bow, the secondary, the corona and the blend from them (docs/sky.md).
#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>

#include "common.hpp"
#include "hydrolux/atmos/lee.hpp"
#include "hydrolux/core/error.hpp"
#include "hydrolux/io/sky_report.hpp"
#include "hydrolux/scene/bow_tables.hpp"
#include "hydrolux/scene/compositor.hpp"
#include "hydrolux/scene/sky_params.hpp"
#include "hydrolux/version.hpp"
#include "image_plugin.hpp"
#include "lee_files.hpp"
#include "params.hpp"
#include "progress.hpp"

namespace hydrolux::cli {

namespace {

struct ExportArgs {
  CLI::App* sub = nullptr;
  std::string dir;
  std::optional<std::string> size;
  std::string theory = "mie";
  std::shared_ptr<scene::ExportOptions> o = std::make_shared<scene::ExportOptions>();  // the declared values
  bool quiet = false;
};

constexpr int kMaxCoronaRows = 16384;  // atmos::validate's largest side

int run_export(const ExportArgs& a) {
  const scene::ExportOptions& o = *a.o;
  // The scene's tables (scene/bow_tables.hpp): --radius-um makes them one column, --size W columns
  // and H rows (the corona 2H).
  int columns = 0, rows = scene::kBowTableRows;
  if (a.size) {
    const auto wh = parse_size(*a.size);  // checked by the option's validator
    columns = (*wh)[0];
    rows = (*wh)[1];
  }
  atmos::LeeSpec rainbow = scene::bow_table_spec(atmos::LeeTableKind::rainbow, o.radius_um, rows);
  atmos::LeeSpec corona = scene::bow_table_spec(atmos::LeeTableKind::corona, o.radius_um, rows);
  if (a.size) rainbow.columns = corona.columns = columns;
  try {
    rainbow.theory = corona.theory = scatter::parse_theory(a.theory);
  } catch (const Error& e) {
    throw Error(fmt::format("--theory {}: {}", a.theory, e.what()));
  }
  const bool with_corona = !o.radius_um || *o.radius_um <= scene::kCoronaMaxRadiusUm;
  if (o.radius_um) {
    // The largest radius depends on the theory (the size parameter's limit): checked here, where it is known.
    const double rmax = atmos::max_radius_um(rainbow);
    if (*o.radius_um > rmax)
      throw Error(fmt::format("--radius-um {:g} is outside the valid range [{:g}, {:g}] um for --theory {} (the "
                              "largest drops of the 10% spread at 380 nm reach the theory's size parameter limit)",
                              *o.radius_um, atmos::kMinRadiusUm, rmax, scatter::theory_name(rainbow.theory)));
    if (a.size && columns != 1)
      throw Error(fmt::format("--size {}: one --radius-um makes one column; give --size 1x{}", *a.size, rows));
  }
  if (a.size && with_corona && corona.rows > kMaxCoronaRows)
    throw Error(fmt::format("--size {}: the corona table has twice H's rows ({}); H is at most {} (valid range "
                            "[1, {}] with the corona, which --radius-um above {:g} um leaves out)",
                            *a.size, corona.rows, kMaxCoronaRows / 2, kMaxCoronaRows / 2, scene::kCoronaMaxRadiusUm));
  rainbow.sampling = corona.sampling = o.sampling;
  // The Stokes Q too (1.04x the time of I alone, BENCHMARKS.md): the tables' EXR gains Q.X, Q.Y, Q.Z
  // and the shaders a polariser (<name>_q.f32; the 3-D table's Q comes along, its spec derived from
  // this one).
  rainbow.stokes = corona.stokes = true;
  atmos::validate(rainbow);
  if (with_corona) atmos::validate(corona);

  // Non-spherical drops: the position-dependent rainbow table besides the spheres' (scene/bow_tables.hpp).
  atmos::DropShapeSpec shape;
  try {
    shape = atmos::parse_drop_shape(o.shape);
  } catch (const Error& e) {
    throw Error(fmt::format("--{}", e.what()));  // the library's message starts "shape '<value>': "
  }
  const bool shaped = !shape.spherical();
  const auto* sun_flag = a.sub->get_option_no_throw("--sun-elevation-deg");
  if (!shaped && sun_flag && sun_flag->count() > 0)
    throw Error(fmt::format("--sun-elevation-deg {:g}: sets the sun of the non-spherical drops' table (--shape); the "
                            "spheres' tables do not depend on it (omit it or give --shape)",
                            o.sun_elevation_deg));
  std::optional<atmos::LeeSpec> shaped_spec;
  if (shaped) {
    // The table's own radii (5-800 um) are within every shape's range; one --radius-um may not be.
    scene::check_shape_radius(shape, rainbow.radius_max_um);
    if (rainbow.rows > scene::kShapedTableMaxRows)
      throw Error(fmt::format("--size {}: with --shape the rainbow's rows are also the 3-D table's, whose side is at "
                              "most {} (a 3-D texture's); H is at most {} with --shape",
                              a.size.value_or(""), scene::kShapedTableMaxRows, scene::kShapedTableMaxRows));
    shaped_spec = scene::shaped_table_spec(rainbow, shape, o.sun_elevation_deg);
    atmos::validate(*shaped_spec);
  }
  std::vector<const atmos::LeeSpec*> specs = {&rainbow};
  if (with_corona) specs.push_back(&corona);
  if (shaped_spec) specs.push_back(&*shaped_spec);
  check_table_memory(specs, a.size ? *a.size : fmt::format("{}x{} (the default)", rainbow.columns, rainbow.rows));
  (void)scene::make_sun_sky(0, o.turbidity);  // checks the turbidity

  // The folders are staged beside their destinations and moved into place at the end.
  io::FileSet files;
  auto& top = files.output_directory("--dir", a.dir);
  (void)image_api();

  ProgressBar bar("export", a.quiet);
  const auto start = std::chrono::steady_clock::now();
  // The rainbow table is most of the work (larger drops, more partial waves); the 3-D table's 38
  // Airy tables of at most 128 columns about 30% of the whole (82 s against 57 s by default).
  const double shaped_share = shaped ? 0.3 : 0.0;
  const double share = (with_corona ? 0.85 : 1.0) * (1 - shaped_share);
  nlohmann::json manifest;
  manifest["format"] = "hydrolux-rainbow-assets";
  manifest["format_version"] = 1;
  manifest["hydrolux_version"] = kVersion;
  manifest["docs"] = "README.md here; docs/sky.md and docs/lee.md in the hydrolux sources";
  nlohmann::json tables = nlohmann::json::object();
  const auto write_table = [&](const atmos::LeeSpec& spec, const std::string& name, double from, double to) {
    tables[name] = write_engine_table(top, name, atmos::compute_lee_table(spec, [&](double f, std::string_view label) {
                                        bar.update(from + f * (to - from), label);
                                      }));
  };
  write_table(rainbow, "rainbow", 0, share);
  if (with_corona) write_table(corona, "corona", share, 1 - shaped_share);
  if (shaped)
    tables["rainbow_shaped"] = io::write_shaped_rainbow_table(
        top, "rainbow_shaped",
        scene::compute_shaped_rainbow_table(rainbow, shape, o.sun_elevation_deg, [&](double f, std::string_view label) {
          bar.update(1 - shaped_share + f * shaped_share, label);
        }));
  bar.finish();

  top.write("sky.json", io::sky_parameters_json(o.turbidity).dump(1) + "\n");
  manifest["tables"] = tables;
  manifest["sky"] = "sky.json";
  manifest["shaders"] = io::write_engine_shaders(top);
  if (!with_corona)
    manifest["corona"] = fmt::format("not exported: drops of {:g} um put their corona within 0.2 degrees of the sun",
                                     *o.radius_um);
  top.write("manifest.json", manifest.dump(1) + "\n");
  files.commit();
  if (!a.quiet)
    fmt::print(stderr, "export: wrote {} ({} files, tables {}{}) in {:.1f} s\n", printable(a.dir),
               top.files().size(), with_corona ? "rainbow, corona" : "rainbow",
               shaped ? fmt::format(", rainbow_shaped ({} drops, sun {:g} deg, {} positions)", o.shape,
                                    o.sun_elevation_deg, scene::kShapePositions)
                      : "",
               std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  return 0;
}

}  // namespace

Command add_export(CLI::App& app) {
  auto a = std::make_shared<ExportArgs>();
  auto* sub = a->sub = app.add_subcommand(
      "export",
      "Engine assets for rainbows in a scene: the rainbow (5-800 um, 90-180 deg) and corona (1-50 um, 0-90 deg) Lee "
      "tables as EXR, PNG, raw float32 and JSON axes; the sun and sky parameters for every sun elevation (sky.json); "
      "GLSL and HLSL that evaluate the sky, the bow, the secondary, the corona and the blend, and a linear polariser "
      "in front of the camera (the tables carry the Stokes Q: EXR channels Q.X, Q.Y, Q.Z and <name>_q.f32); a "
      "README for integrators. With --shape, also the bow of non-spherical drops as a 3-D table (radius x angle x 19 position "
      "angles, for one sun elevation) that the shaders read instead. The folder appears complete or not at all.");
  sub->add_option("--dir", a->dir, "Output folder (created; files of the same names in it are replaced)")->required();
  Command cmd{sub, [a] { return run_export(*a); }, {}};
  const auto params = scene::export_params();  // --radius-um; then --sampling, --turbidity, --sun-elevation-deg
  add_params(*sub, a->o, params.first(1), cmd.flags_for_quantity);
  sub->add_option("--size", a->size, "Table size WxH: W radii, H angles of the rainbow table (the corona table has 2H) [512x1024]")->check(size_validator());
  sub->add_option("--theory", a->theory, "mie, debye:P, airy or geometric[:P] (hydrolux lee --help) of the spheres' tables")->capture_default_str();
  sub->add_option("--shape", a->o->shape,
                  fmt::format("Drop shape: sphere (the spheres' tables only), spheroid:Q (axis ratio Q = polar / "
                              "equatorial in [{:g}, 1], axis vertical) or beard-chuang (falling drops, Q from the "
                              "radius; radii up to {:g} um): also rainbow_shaped.f32/.json, the bow of such drops by "
                              "Airy theory of their plane section (primary and secondary added) over the rainbow "
                              "table's radii (at most {} columns) and rows and position angles 0, 10, ..., 180 "
                              "degrees, for --sun-elevation-deg (docs/sky.md)",
                              atmos::kMinBowAxisRatio, scene::max_sky_radius_um(atmos::parse_drop_shape("beard-chuang")),
                              scene::kShapedTableMaxColumns))
      ->capture_default_str();
  add_params(*sub, a->o, params.subspan(1), cmd.flags_for_quantity);
  sub->add_flag("-q,--quiet", a->quiet, "No progress or summary on stderr");
  cmd.flags_for_quantity.insert({{"columns", "--size"},
                                 {"shape", "--shape"},
                                 {"rows", "--size"},
                                 {"size_parameter", "--radius-um (the size parameter 2 pi r / lambda)"},
                                 {"p", "--theory"}});
  return cmd;
}

}  // namespace hydrolux::cli
