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
#include "hydrolux/core/embedded_data.hpp"
#include "hydrolux/core/error.hpp"
#include "hydrolux/core/parse.hpp"
#include "hydrolux/scene/compositor.hpp"
#include "hydrolux/version.hpp"
#include "image_plugin.hpp"
#include "lee_files.hpp"
#include "progress.hpp"

namespace hydrolux::cli {

namespace {

struct ExportArgs {
  std::string dir;
  std::optional<double> radius_um;
  std::optional<std::string> size;
  std::string theory = "mie";
  double sampling = 1;
  double turbidity = 2.5;
  bool quiet = false;
};

constexpr double kCoronaMaxRadiusUm = 50;
constexpr double kForwardMaxDeg = 90;
constexpr int kMaxCoronaRows = 16384;  // atmos::validate's largest side

nlohmann::json sky_parameters(double turbidity) {
  nlohmann::json j;
  j["format"] = "hydrolux-sky-parameters";
  j["format_version"] = 1;
  j["hydrolux_version"] = kVersion;
  j["model"] =
      "Preetham, Shirley and Smits 1999 sky; the sun is ASTM G173 direct (air mass 1.5) carried to the air mass "
      "of Kasten and Young 1989 with Preetham's Rayleigh and aerosol optical depths; docs/sky.md";
  j["units"] = {{"radiance", "cd/m^2 per channel, linear Rec.709 (luminance 0.2126 R + 0.7152 G + 0.0722 B)"},
                {"irradiance", "lux per channel"},
                {"zenith_Y_kcd", "kcd/m^2"}};
  j["turbidity"] = turbidity;
  j["camera_height_m"] = scene::kCameraHeightM;
  j["sun_angular_radius_deg"] = scene::kSunAngularRadiusDeg;
  j["ground_albedo"] = {scene::kGroundAlbedo[0], scene::kGroundAlbedo[1], scene::kGroundAlbedo[2]};
  j["extinction_efficiency"] = 2.0;
  // beta_geo = pi M2 of Marshall-Palmer rain is a power law in the rain rate: c R^0.63.
  const double b1 = scene::rain_beta_geo_per_m(1.0), b10 = scene::rain_beta_geo_per_m(10.0);
  j["rain"] = {{"beta_geo_per_m", "coefficient * rain_rate_mmh ^ exponent (Marshall and Palmer 1948, n0 = 1.6e7 m^-4 "
                                  "per metre of radius, Lambda = 8200 R^-0.21 m^-1)"},
               {"coefficient", b1},
               {"exponent", std::log10(b10 / b1)}};
  j["tone_map"] = {{"exposure", 0.6}, {"white", 6.0},
                   {"formula", "x = exposure L / l_ref; x (1 + x / white^2) / (1 + x), clamped to [0,1]; sRGB"}};
  nlohmann::json e = nlohmann::json::array(), lux = nlohmann::json::array(), sun = nlohmann::json::array(),
                 sky = nlohmann::json::array(), ground = nlohmann::json::array(), lref = nlohmann::json::array(),
                 zy = nlohmann::json::array(), zx = nlohmann::json::array(), zyc = nlohmann::json::array(),
                 py = nlohmann::json::array(), px = nlohmann::json::array(), pyc = nlohmann::json::array(),
                 pat = nlohmann::json::array();
  scene::SunSky first;
  for (int deg = 0; deg <= 90; ++deg) {
    const scene::SunSky s = scene::make_sun_sky(deg, turbidity);
    if (deg == 0) first = s;
    e.push_back(deg);
    lux.push_back(s.sun_illuminance_lux);
    sun.push_back({s.sun_rgb.x, s.sun_rgb.y, s.sun_rgb.z});
    sky.push_back({s.sky_illuminance_rgb.x, s.sky_illuminance_rgb.y, s.sky_illuminance_rgb.z});
    ground.push_back({s.ground_rgb.x, s.ground_rgb.y, s.ground_rgb.z});
    lref.push_back(s.l_ref);
    zy.push_back(s.zenith_Y_kcd);
    zx.push_back(s.zenith_x);
    zyc.push_back(s.zenith_y);
    const auto coef = [](const scene::Perez& p) { return nlohmann::json{p.A, p.B, p.C, p.D, p.E}; };
    py.push_back(coef(s.perez[0]));
    px.push_back(coef(s.perez[1]));
    pyc.push_back(coef(s.perez[2]));
    pat.push_back({s.perez_at_sun[0], s.perez_at_sun[1], s.perez_at_sun[2]});
  }
  j["xyz_to_rgb"] = {{first.xyz_to_rgb[0][0], first.xyz_to_rgb[0][1], first.xyz_to_rgb[0][2]},
                     {first.xyz_to_rgb[1][0], first.xyz_to_rgb[1][1], first.xyz_to_rgb[1][2]},
                     {first.xyz_to_rgb[2][0], first.xyz_to_rgb[2][1], first.xyz_to_rgb[2][2]}};
  j["elevations_deg"] = e;
  j["sun_illuminance_lux"] = lux;
  j["sun_rgb"] = sun;
  j["sky_illuminance_rgb"] = sky;
  j["ground_rgb"] = ground;
  j["l_ref"] = lref;
  j["zenith_Y_kcd"] = zy;
  j["zenith_x"] = zx;
  j["zenith_y"] = zyc;
  j["perez_Y"] = py;
  j["perez_x"] = px;
  j["perez_y"] = pyc;
  j["perez_at_sun"] = pat;
  return j;
}

int run_export(const ExportArgs& a) {
  atmos::LeeSpec rainbow = atmos::default_lee_spec(atmos::LeeTableKind::rainbow);
  // The corona table spans the whole forward hemisphere (0-90 degrees, 2048 rows: 0.044 degree,
  // four rows to the closest rings of 50 um droplets), so that with the corona on, the light small
  // drops scatter forward has no edge at the corona's usual 20 degrees.
  atmos::LeeSpec corona = atmos::default_lee_spec(atmos::LeeTableKind::corona);
  corona.angle_max_deg = kForwardMaxDeg;
  corona.rows = 2048;
  try {
    rainbow.theory = corona.theory = scatter::parse_theory(a.theory);
  } catch (const Error& e) {
    throw Error(fmt::format("--theory {}: {}", a.theory, e.what()));
  }
  bool with_corona = true;
  if (a.radius_um) {
    // The largest radius depends on the theory (the size parameter's limit): checked here, where it is known.
    const double rmax = atmos::max_radius_um(rainbow);
    if (*a.radius_um > rmax)
      throw Error(fmt::format("--radius-um {:g} is outside the valid range [{:g}, {:g}] um for --theory {} (the "
                              "largest drops of the 10% spread at 380 nm reach the theory's size parameter limit)",
                              *a.radius_um, atmos::kMinRadiusUm, rmax, scatter::theory_name(rainbow.theory)));
    rainbow.radius_min_um = rainbow.radius_max_um = *a.radius_um;
    rainbow.columns = 1;
    corona.radius_min_um = corona.radius_max_um = *a.radius_um;
    corona.columns = 1;
    with_corona = *a.radius_um <= kCoronaMaxRadiusUm;
  }
  if (a.size) {
    const auto wh = parse_size(*a.size);  // checked by the option's validator
    if (a.radius_um && (*wh)[0] != 1)
      throw Error(fmt::format("--size {}: one --radius-um makes one column; give --size 1x{}", *a.size, (*wh)[1]));
    rainbow.columns = corona.columns = (*wh)[0];
    rainbow.rows = (*wh)[1];
    corona.rows = 2 * (*wh)[1];
    if (with_corona && corona.rows > kMaxCoronaRows)
      throw Error(fmt::format("--size {}: the corona table has twice H's rows ({}); H is at most {} (valid range "
                              "[1, {}] with the corona, which --radius-um above {:g} um leaves out)",
                              *a.size, corona.rows, kMaxCoronaRows / 2, kMaxCoronaRows / 2, kCoronaMaxRadiusUm));
  }
  rainbow.sampling = corona.sampling = a.sampling;
  atmos::validate(rainbow);
  if (with_corona) atmos::validate(corona);
  std::vector<const atmos::LeeSpec*> specs = {&rainbow};
  if (with_corona) specs.push_back(&corona);
  check_table_memory(specs, a.size ? *a.size : fmt::format("{}x{} (the default)", rainbow.columns, rainbow.rows));
  (void)scene::make_sun_sky(0, a.turbidity);  // checks the turbidity

  // The folders are staged beside their destinations and moved into place at the end.
  io::FileSet files;
  auto& top = files.output_directory("--dir", a.dir);
  (void)image_api();

  ProgressBar bar("export", a.quiet);
  const auto start = std::chrono::steady_clock::now();
  // The rainbow table is most of the work (larger drops, more partial waves).
  const double share = with_corona ? 0.85 : 1.0;
  nlohmann::json manifest;
  manifest["format"] = "hydrolux-rainbow-assets";
  manifest["format_version"] = 1;
  manifest["hydrolux_version"] = kVersion;
  manifest["docs"] = "README.md here; docs/sky.md and docs/lee.md in the hydrolux sources";
  nlohmann::json tables = nlohmann::json::object();
  const auto write_table = [&](const atmos::LeeSpec& spec, const std::string& name, double from, double to) {
    const atmos::LeeTable t = atmos::compute_lee_table(
        spec, [&](double f, std::string_view label) { bar.update(from + f * (to - from), label); });
    const atmos::LeeImages im = atmos::lee_images(t);
    const LeeFileBytes bytes = encode_lee_files(t, im);
    nlohmann::json side = lee_sidecar(t, im, name + ".exr", name + ".png");
    side["files"]["f32"] = name + ".f32";
    side["f32_layout"] =
        "little-endian float32, rows x columns x 3 (R, G, B as in the EXR), row-major: value (row j, column i, "
        "channel c) at index (j * width + i) * 3 + c";
    top.write(name + ".exr", bytes.exr);
    top.write(name + ".png", bytes.png);
    top.write(name + ".f32", bytes.f32);
    top.write(name + ".json", side.dump(1) + "\n");
    tables[name] = {{"kind", atmos::table_kind_name(spec.table)},
                    {"columns", t.columns()},
                    {"rows", t.rows()},
                    {"radius_um", {t.radius_um.front(), t.radius_um.back()}},
                    {"angle_deg", {t.angle_deg.front(), t.angle_deg.back()}},
                    {"files", {name + ".exr", name + ".png", name + ".f32", name + ".json"}}};
  };
  write_table(rainbow, "rainbow", 0, share);
  if (with_corona) write_table(corona, "corona", share, 1);
  bar.finish();

  top.write("sky.json", sky_parameters(a.turbidity).dump(1) + "\n");
  nlohmann::json shaders = nlohmann::json::array();
  for (const auto& f : detail::embedded_files()) {
    const std::string_view p = f.path;
    if (p.rfind("shaders/", 0) != 0) continue;
    const std::string rest(p.substr(8));
    if (rest.rfind("glsl/", 0) == 0 || rest.rfind("hlsl/", 0) == 0 || rest.find('/') == std::string::npos)
      top.write(rest, f.text);
    else
      continue;
    shaders.push_back(rest);
  }
  manifest["tables"] = tables;
  manifest["sky"] = "sky.json";
  manifest["shaders"] = shaders;
  if (!with_corona)
    manifest["corona"] = fmt::format("not exported: drops of {:g} um put their corona within 0.2 degrees of the sun",
                                     *a.radius_um);
  top.write("manifest.json", manifest.dump(1) + "\n");
  files.commit();
  if (!a.quiet)
    fmt::print(stderr, "export: wrote {} ({} files, tables {}) in {:.1f} s\n", printable(a.dir),
               top.files().size(), with_corona ? "rainbow, corona" : "rainbow",
               std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  return 0;
}

}  // namespace

Command add_export(CLI::App& app) {
  auto a = std::make_shared<ExportArgs>();
  auto* sub = app.add_subcommand(
      "export",
      "Engine assets for rainbows in a scene: the rainbow (5-800 um, 90-180 deg) and corona (1-50 um, 0-90 deg) Lee "
      "tables as EXR, PNG, raw float32 and JSON axes; the sun and sky parameters for every sun elevation (sky.json); "
      "GLSL and HLSL that evaluate the sky, the bow, the secondary, the corona and the blend; a README for "
      "integrators. The folder appears complete or not at all.");
  sub->add_option("--dir", a->dir, "Output folder (created; files of the same names in it are replaced)")->required();
  atmos::LeeSpec geometric = atmos::default_lee_spec(atmos::LeeTableKind::rainbow);
  geometric.theory = scatter::parse_theory("geometric");
  sub->add_option("--radius-um", a->radius_um,
                  fmt::format("One drop radius in micrometres: one-column tables (a 1D slice); at most {:g} with Mie "
                              "or Debye theory, {:g} with geometric (the size parameter's limit at 380 nm)",
                              atmos::max_radius_um(atmos::default_lee_spec(atmos::LeeTableKind::rainbow)),
                              atmos::max_radius_um(geometric)))
      ->check(number_in(atmos::kMinRadiusUm, atmos::kMaxRadiusUm, "um"));
  sub->add_option("--size", a->size, "Table size WxH: W radii, H angles of the rainbow table (the corona table has 2H) [512x1024]")->check(size_validator());
  sub->add_option("--theory", a->theory, "mie, debye:P, airy or geometric[:P] (hydrolux lee --help)")->capture_default_str();
  sub->add_option("--sampling", a->sampling, "Multiplier on the tables' sampling rates")
      ->check(number_in(0.25, 16))->capture_default_str();
  sub->add_option("--turbidity", a->turbidity, "Turbidity of sky.json's sky and sun (Preetham)")
      ->check(number_in(scene::kMinTurbidity, scene::kMaxTurbidity))->capture_default_str();
  sub->add_flag("-q,--quiet", a->quiet, "No progress or summary on stderr");
  return {sub,
          [a] { return run_export(*a); },
          {{"radius_um", "--radius-um"},
           {"columns", "--size"},
           {"rows", "--size"},
           {"sampling", "--sampling"},
           {"turbidity", "--turbidity"},
           {"size_parameter", "--radius-um (the size parameter 2 pi r / lambda)"},
           {"p", "--theory"}}};
}

}  // namespace hydrolux::cli
