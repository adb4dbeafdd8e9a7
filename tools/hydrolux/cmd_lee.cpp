// hydrolux lee: Lee diagrams (colour over scattering angle and drop radius), corona and glory
// tables, as a linear EXR, a display PNG and a JSON sidecar; or one radius's profile as JSON.
#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>

#include "common.hpp"
#include "hydrolux/atmos/lee.hpp"
#include "hydrolux/core/error.hpp"
#include "hydrolux/core/parse.hpp"
#include "hydrolux/optics/media.hpp"
#include "hydrolux/version.hpp"
#include "image_plugin.hpp"
#include "lee_files.hpp"
#include "progress.hpp"

namespace hydrolux::cli {

namespace {

struct LeeArgs {
  std::string table = "rainbow";
  std::string theory = "mie";
  std::optional<std::string> radius_um, angle_deg, size;
  std::string radius_scale = "log";
  std::string axis = "angle";
  double sun_disk_deg = atmos::kSunDiskDeg;
  bool limb_darkening = false;
  double size_spread = 0.1;
  std::string wavelengths = "380:780";
  std::optional<double> temperature_c;
  std::string medium = "water";
  std::string sun = "astm-g173-direct";
  std::string color_space = "rec709";
  double sampling = 1;
  long long seed = 1;
  int threads = 0;
  bool json = false;
  std::string output;
  bool quiet = false;
  // Refused when given where they have no effect (count(), never their defaults).
  const CLI::Option *limb_darkening_opt = nullptr, *radius_scale_opt = nullptr;
};

// "A:B" (or one value A, when `single` is allowed), A <= B.
std::array<double, 2> parse_span(const std::string& text, const std::string& flag, const std::string& unit,
                                 bool single_ok) {
  if (single_ok)
    if (const auto v = parse::number(text)) return {*v, *v};
  const auto p = parse::pair(text, ':');
  if (!p || (*p)[1] < (*p)[0])
    throw Error(fmt::format("{} '{}': expected A:B ({}, A <= B){}", flag, text, unit, single_ok ? " or one value" : ""));
  return *p;
}

int run_lee(const LeeArgs& a) {
  atmos::LeeTableKind kind = atmos::LeeTableKind::rainbow;
  if (a.table == "corona") kind = atmos::LeeTableKind::corona;
  if (a.table == "glory") kind = atmos::LeeTableKind::glory;
  atmos::LeeSpec s = atmos::default_lee_spec(kind);
  try {
    s.theory = scatter::parse_theory(a.theory);
  } catch (const Error& e) {
    throw Error(fmt::format("--theory {}: {}", a.theory, e.what()));
  }
  bool single = false;
  if (a.radius_um) {
    const auto r = parse_span(*a.radius_um, "--radius-um",
                              fmt::format("micrometres in [{:g}, {:g}]", atmos::kMinRadiusUm, atmos::kMaxRadiusUm), true);
    s.radius_min_um = r[0];
    s.radius_max_um = r[1];
    single = r[0] == r[1];
  }
  if (a.angle_deg) {
    const auto r = parse_span(*a.angle_deg, "--angle-deg", "degrees", false);
    s.angle_min_deg = r[0];
    s.angle_max_deg = r[1];
  }
  if (single) s.columns = 1;
  if (a.size) {
    const auto wh = parse_size(*a.size);  // checked by the option's validator
    s.columns = (*wh)[0];
    s.rows = (*wh)[1];
    if (single && s.columns != 1)
      throw Error(fmt::format("--size {}: a single --radius-um {} makes one column; give --size 1x{}", *a.size,
                              *a.radius_um, s.rows));
  }
  if (s.rows > 1 && s.angle_min_deg == s.angle_max_deg)
    throw Error(fmt::format("--angle-deg {}: a table of {} rows needs A < B (or --size Wx1 for one angle)",
                            a.angle_deg ? *a.angle_deg : "", s.rows));
  s.radius_scale = a.radius_scale == "log" ? atmos::RadiusScale::log : atmos::RadiusScale::linear;
  s.axis = a.axis == "angle" ? atmos::AngleAxis::angle : atmos::AngleAxis::cosine;
  s.sun_disk_deg = a.sun_disk_deg;
  s.limb_darkening = a.limb_darkening;
  s.size_spread = a.size_spread;
  {
    const std::string& w = a.wavelengths;
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
  s.drop_medium = a.medium;
  const auto drop = medium_flag("--medium", a.medium);
  const auto air = optics::find_medium("air");
  check_temperature_flag(a.temperature_c, {drop.get()});
  s.temperature_c = a.temperature_c;
  try {
    s.sun = color::Illuminant::parse(a.sun);
  } catch (const DomainError& e) {
    throw Error(fmt::format("--sun {}: {:g} K is {}", a.sun, e.value(), e.range_text()));
  } catch (const Error& e) {
    throw Error(fmt::format("--sun: {}", e.what()));
  }
  s.rgb_space = color::parse_rgb_space(a.color_space);
  s.sampling = a.sampling;
  s.seed = std::uint64_t(a.seed);
  s.threads = a.threads;
  if (a.limb_darkening_opt && a.limb_darkening_opt->count() > 0 && s.sun_disk_deg == 0)
    throw Error("--limb-darkening: --sun-disk-deg 0 makes the sun a point, which has no limb to darken");
  if (a.radius_scale_opt && a.radius_scale_opt->count() > 0 && s.columns == 1)
    throw Error(fmt::format("--radius-scale {}: a table of one column has no column spacing", a.radius_scale));
  if (a.radius_um) {
    // The largest radius depends on the theory, the spread and the shortest wavelength (the size
    // parameter's limit): stated with them, instead of as a size parameter out of range.
    const double rmax = atmos::max_radius_um(s);
    if (s.radius_max_um > rmax && s.radius_max_um <= atmos::kMaxRadiusUm)
      throw Error(fmt::format("--radius-um {}: {:g} um is outside the valid range [{:g}, {:g}] um for --theory {}, "
                              "--size-spread {:g} and {:g} nm (the largest drops' size parameter 2 pi r n / lambda "
                              "must stay within the theory's limit)",
                              *a.radius_um, s.radius_max_um, atmos::kMinRadiusUm, rmax,
                              scatter::theory_name(s.theory), s.size_spread, s.wavelength_min_nm));
  }
  atmos::validate(s);
  check_table_memory({&s}, a.size ? *a.size : fmt::format("{}x{} (the default)", s.columns, s.rows));
  if (!a.json && a.output.empty()) throw Error("-o is required (a .exr path), unless --json prints a profile");
  if (a.json && !single) throw Error("--json prints one radius's profile: give a single --radius-um R");

  // Every output is reserved before the work: the EXR, and the PNG and JSON beside it.
  io::FileSet files;
  std::optional<ImageOutput> exr, png;
  io::OutputFile* side = nullptr;
  std::string png_path, json_path;
  if (!a.output.empty()) {
    const std::filesystem::path p(a.output);
    if (p.extension() != ".exr")
      throw Error(fmt::format("-o {}: the table is written as OpenEXR; give a .exr path (the .png and .json go beside "
                              "it)",
                              a.output));
    png_path = std::filesystem::path(p).replace_extension(".png").string();
    json_path = std::filesystem::path(p).replace_extension(".json").string();
    exr = declare_output_image(files, "-o", a.output);
    png = declare_output_image(files, "-o (its .png)", png_path);
    side = &files.output("-o (its .json)", json_path);
    (void)image_api();  // image support loads now, not after the work
  }

  ProgressBar bar("lee", a.quiet || a.json);
  const auto start = std::chrono::steady_clock::now();
  const atmos::LeeTable t = atmos::compute_lee_table(s, bar.callback());
  bar.finish();
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const atmos::LeeImages im = atmos::lee_images(t);

  if (a.json) {
    nlohmann::json j;
    j["radius_um"] = t.radius_um.front();
    j["theory"] = scatter::theory_name(s.theory);
    j["units"] = "sr^-1";
    j["color_space"] = color::rgb_space_name(s.rgb_space);
    j["angle_deg"] = to_json(t.angle_deg);
    nlohmann::json rgb = nlohmann::json::array(), lum = nlohmann::json::array(), xyz = nlohmann::json::array();
    for (int r = 0; r < t.rows(); ++r) {
      const auto v = t.rgb(r, 0);
      rgb.push_back({v[0], v[1], v[2]});
      const auto c = t.at(r, 0);
      xyz.push_back({c.X, c.Y, c.Z});
      lum.push_back(c.Y);
    }
    j["rgb"] = rgb;
    j["luminance"] = lum;
    j["xyz"] = xyz;
    std::cout << j.dump() << '\n';
    std::cout.flush();
    if (!std::cout) throw IoFailure("writing the profile to standard output failed");
  }
  if (!a.output.empty()) {
    const LeeFileBytes bytes = encode_lee_files(t, im);
    exr->file->write(bytes.exr);
    png->file->write(bytes.png);
    side->write(lee_sidecar(t, im, std::filesystem::path(a.output).filename().string(),
                        std::filesystem::path(png_path).filename().string())
                    .dump(1) +
                "\n");
    files.commit();
    if (!a.quiet)
      fmt::print(stderr, "lee: wrote {} ({}x{}, {}), {} and {} in {:.1f} s ({} evaluations, {:.3g} terms x angles)\n",
                 printable(a.output), t.columns(), t.rows(), scatter::theory_name(s.theory), printable(png_path),
                 printable(json_path), seconds, t.work.evaluations, double(t.work.term_angles));
  }
  return 0;
}

}  // namespace

Command add_lee(CLI::App& app) {
  auto args = std::make_shared<LeeArgs>();
  auto* sub = app.add_subcommand(
      "lee",
      "Lee diagram: the colour of sunlight scattered by water drops over drop radius (columns) and scattering angle "
      "(rows), spectral and absolute (sr^-1: radiance per unit irradiance per unit projected-area optical depth), "
      "averaged over the sun's disk and a size spread. Writes a linear EXR (R,G,B gamut-mapped; XYZ unmapped), a "
      "display PNG and a JSON sidecar with the exact axes (docs/lee.md). --table corona/glory: forward and backward "
      "tables of cloud droplets. --json with one radius prints its profile.");
  sub->add_option("--table", args->table, "rainbow (90-180 deg, 5-800 um), corona (0-20 deg, 1-50 um) or glory (160-180 deg, 1-50 um)")
      ->check(CLI::IsMember({"rainbow", "corona", "glory"}))
      ->capture_default_str();
  sub->add_option("--theory", args->theory, "mie, debye:P (one Debye order), airy (primary; airy:3 secondary) or geometric[:P] (ray orders 0..P with diffraction)")
      ->capture_default_str();
  sub->add_option("--radius-um", args->radius_um,
                  fmt::format("Drop radii A:B in micrometres [{:g}, {:g}], or one radius R [table's default]; the "
                              "size parameter limits the largest: {:g} with Mie, --size-spread 0.1 and 380 nm",
                              atmos::kMinRadiusUm, atmos::kMaxRadiusUm,
                              atmos::max_radius_um(atmos::default_lee_spec(atmos::LeeTableKind::rainbow))));
  args->radius_scale_opt = sub->add_option("--radius-scale", args->radius_scale, "Column spacing: log or linear")
                               ->check(CLI::IsMember({"log", "linear"}))
                               ->capture_default_str();
  sub->add_option("--angle-deg", args->angle_deg, "Scattering angles A:B in degrees [0, 180] (0 forward, 180 antisolar) [table's default]");
  sub->add_option("--axis", args->axis, "Rows in scattering angle (angle) or in its cosine (cos)")
      ->check(CLI::IsMember({"angle", "cos"}))
      ->capture_default_str();
  sub->add_option("--size", args->size, "Table size WxH in pixels: W radii, H angles [512x1024; 1xH for one radius]")
      ->check(size_validator());
  sub->add_option("--sun-disk-deg", args->sun_disk_deg, "The sun's angular diameter in degrees (0: a point)")
      ->check(number_in(0, 5, "deg"))
      ->capture_default_str();
  args->limb_darkening_opt =
      sub->add_flag("--limb-darkening", args->limb_darkening, "Darken the sun's limb (linear law, u = 0.6; not with --sun-disk-deg 0)");
  sub->add_option("--size-spread", args->size_spread,
                  "Relative standard deviation of each column's gamma size distribution (0: one radius; else 0.01-0.5)")
      ->check(number_in(0, 0.5))
      ->capture_default_str();
  sub->add_option("--wavelengths-nm", args->wavelengths,
                  "Wavelengths A:B[:N] in nanometres [360, 830]; N samples (default one per 10 nm)")
      ->capture_default_str();
  sub->add_option("--temperature-c", args->temperature_c, "Water temperature in Celsius (0 to 100) [20]")
      ->check(number_in(-273.15, 1000, "C"));
  sub->add_option("--medium", args->medium, "Drop medium (hydrolux ior --list)")->capture_default_str();
  sub->add_option("--sun", args->sun, "Light source: astm-g173-direct, blackbody:T (kelvin) or equal-energy")
      ->capture_default_str();
  sub->add_option("--color-space", args->color_space, "Linear RGB primaries: rec709 (sRGB) or rec2020")
      ->check(CLI::IsMember({"rec709", "srgb", "rec2020"}))
      ->capture_default_str();
  sub->add_option("--sampling", args->sampling, "Multiplier on every sampling rate (wavelengths, radius grid)")
      ->check(number_in(0.25, 16))
      ->capture_default_str();
  sub->add_option("--seed", args->seed, "Seed of the sampling pattern")->transform(integer_in(0, 1LL << 53))->capture_default_str();
  sub->add_option("--threads", args->threads, "Threads (0: every core)")->transform(integer_in(0, 1024))->capture_default_str();
  sub->add_flag("--json", args->json, "Print one radius's profile (angle, RGB, luminance, XYZ) as JSON on stdout");
  sub->add_option("-o,--output", args->output, "Output .exr (the .png and .json are written beside it)");
  sub->add_flag("-q,--quiet", args->quiet, "No progress or summary on stderr");
  return {sub,
          [args] { return run_lee(*args); },
          {{"radius_um", "--radius-um"},
           {"angle_deg", "--angle-deg"},
           {"columns", "--size"},
           {"rows", "--size"},
           {"sun_disk_deg", "--sun-disk-deg"},
           {"size_spread", "--size-spread"},
           {"wavelength_nm", "--wavelengths-nm"},
           {"wavelengths", "--wavelengths-nm"},
           {"sampling", "--sampling"},
           {"size_parameter", "--radius-um (the size parameter 2 pi r / lambda)"},
           {"temperature_c", "--temperature-c"},
           {"temperature_k", "--sun"},
           {"m_imag", "--medium (its index relative to air)"},
           {"m_real", "--medium (its index relative to air)"},
           {"p", "--theory"}}};
}

}  // namespace hydrolux::cli
