// hydrolux lee: Lee diagrams (colour over scattering angle and drop radius), corona and glory
// tables, as a linear EXR, a display PNG and a JSON sidecar; or one radius's profile as JSON.
#include <fmt/format.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <iostream>
#include <memory>
#include <optional>

#include "common.hpp"
#include "hydrolux/atmos/lee.hpp"
#include "hydrolux/atmos/lee_params.hpp"
#include "hydrolux/core/error.hpp"
#include "hydrolux/core/parse.hpp"
#include "hydrolux/io/lee_files.hpp"
#include "hydrolux/optics/media.hpp"
#include "image_plugin.hpp"
#include "lee_files.hpp"
#include "params.hpp"
#include "progress.hpp"

namespace hydrolux::cli {

namespace {

struct LeeArgs {
  // The declared values (atmos/lee_params.hpp) and the names the flags set as they are (--radius-scale, --axis).
  std::shared_ptr<atmos::LeeRequest> req = std::make_shared<atmos::LeeRequest>();
  std::string table = "rainbow";
  std::string theory = "mie";
  std::optional<std::string> radius_um, angle_deg, size;
  std::string wavelengths = "380:780";
  std::string medium = "water";
  std::string sun = "astm-g173-direct";
  std::string color_space = "rec709";
  bool json = false;
  std::string output;
  bool quiet = false;
  const CLI::App* sub = nullptr;  // which flags were given: refused where they have no effect
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
  atmos::LeeRequest req = *a.req;
  req.table = atmos::parse_table_kind(a.table);  // checked by the option's validator
  try {
    req.theory = scatter::parse_theory(a.theory);
  } catch (const Error& e) {
    throw Error(fmt::format("--theory {}: {}", a.theory, e.what()));
  }
  bool spheres = true;
  try {
    spheres = atmos::parse_drop_shape(req.shape).spherical();
  } catch (const Error& e) {
    throw Error(fmt::format("--{}", e.what()));  // the library's message starts "shape '<value>': "
  }
  // The non-spherical drops' flags given for spheres would be ignored (as export refuses them).
  for (const std::string_view name : atmos::kShapeOnlyParams)
    if (const Param& p = atmos::lee_param(name); spheres && given(*a.sub, p))
      throw Error(atmos::shape_only_message(name, find_field(atmos::lee_params(), name)->get(req), p.flag, "--shape"));
  if (a.radius_um)
    req.radius_um = parse_span(*a.radius_um, "--radius-um",
                               fmt::format("micrometres in [{:g}, {:g}]", atmos::kMinRadiusUm, atmos::kMaxRadiusUm), true);
  if (a.angle_deg) req.angle_deg = parse_span(*a.angle_deg, "--angle-deg", "degrees", false);
  if (a.size) req.size = *parse_size(*a.size);  // checked by the option's validator
  const bool single = req.one_radius();
  atmos::LeeSpec s;
  try {
    s = atmos::make_lee_spec(req);
  } catch (const atmos::LeeShapeError& e) {  // said in the flags' words
    if (e.rule() == atmos::LeeShapeError::Rule::one_radius_columns)
      throw Error(fmt::format("--size {}: a single --radius-um {} makes one column; give --size 1x{}", *a.size,
                              *a.radius_um, e.rows()));
    throw Error(fmt::format("--angle-deg {}: a table of {} rows needs A < B (or --size Wx1 for one angle)",
                            a.angle_deg ? *a.angle_deg : "", e.rows()));
  }
  if (!s.shape.spherical() &&
      (s.table != atmos::LeeTableKind::rainbow || s.theory.kind != scatter::TheoryKind::Airy || s.theory.p > 3))
    throw Error(fmt::format("--shape {}: non-spherical drops are computed by Airy theory of their plane section "
                            "(docs/non-spherical.md): give --theory airy (primary) or airy:3 (secondary) with "
                            "--table rainbow, not --table {} --theory {}",
                            req.shape, a.table, a.theory));
  set_wavelengths_flag(s, a.wavelengths);
  s.drop_medium = a.medium;
  const auto drop = medium_flag("--medium", a.medium);
  check_temperature_flag(req.temperature_c, {drop.get()});
  try {
    s.sun = color::Illuminant::parse(a.sun);
  } catch (const DomainError& e) {
    throw Error(fmt::format("--sun {}: {:g} K is {}", a.sun, e.value(), e.range_text()));
  } catch (const Error& e) {
    throw Error(fmt::format("--sun: {}", e.what()));
  }
  s.rgb_space = color::parse_rgb_space(a.color_space);
  if (given(*a.sub, atmos::lee_param("limb_darkening")) && s.sun_disk_deg == 0)
    throw Error("--limb-darkening: --sun-disk-deg 0 makes the sun a point, which has no limb to darken");
  if (a.sub->get_option("--radius-scale")->count() > 0 && s.columns == 1)
    throw Error(fmt::format("--radius-scale {}: a table of one column has no column spacing", req.radius_scale));
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
  atmos::check_table_memory({&s}, a.size ? *a.size : fmt::format("{}x{} (the default)", s.columns, s.rows),
                            atmos::SizeSyntax::cli);
  if (!a.json && a.output.empty())
    throw Error("-o is required (a .exr path, or .nc for NetCDF), unless --json prints a profile");
  if (a.json && !single) throw Error("--json prints one radius's profile: give a single --radius-um R");

  // Every output is reserved before the work: the EXR, and the PNG and JSON beside it.
  io::FileSet files;
  std::optional<LeeOutputs> out;
  if (!a.output.empty()) out = declare_lee_outputs(files, a.output);

  ProgressBar bar("lee", a.quiet || a.json);
  const auto start = std::chrono::steady_clock::now();
  const atmos::LeeTable t = atmos::compute_lee_table(s, bar.callback());
  bar.finish();
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const atmos::LeeImages im = atmos::lee_images(t);

  if (a.json) {
    std::cout << io::lee_profile_json(t).dump() << '\n';
    std::cout.flush();
    if (!std::cout) throw IoFailure(fmt::format("cannot write to standard output: {}", std::strerror(errno)));
  }
  if (out) {
    out->write(t, im);
    files.commit();
    if (!a.quiet)
      fmt::print(stderr, "lee: wrote {} ({}x{}, {}) in {:.1f} s ({} evaluations, {:.3g} terms x angles)\n",
                 out->describe(), t.columns(), t.rows(), scatter::theory_name(s.theory), seconds,
                 t.work.evaluations, double(t.work.term_angles));
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
  args->sub = sub;
  Command cmd{sub, [args] { return run_lee(*args); }, {}};
  const auto declared = [&](std::string_view first, std::string_view last) {
    add_params(*sub, args->req, fields_from(atmos::lee_params(), first, last), cmd.flags_for_quantity);
  };
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
  sub->add_option("--radius-scale", args->req->radius_scale, "Column spacing: log or linear")
      ->check(CLI::IsMember({"log", "linear"}))
      ->capture_default_str();
  sub->add_option("--angle-deg", args->angle_deg, "Scattering angles A:B in degrees [0, 180] (0 forward, 180 antisolar) [table's default]");
  sub->add_option("--axis", args->req->axis, "Rows in scattering angle (angle) or in its cosine (cos)")
      ->check(CLI::IsMember({"angle", "cos"}))
      ->capture_default_str();
  sub->add_option("--size", args->size, "Table size WxH in pixels: W radii, H angles [512x1024; 1xH for one radius]")
      ->check(size_validator());
  declared("sun_disk_deg", "size_spread");
  sub->add_option("--wavelengths-nm", args->wavelengths,
                  "Wavelengths A:B[:N] in nanometres [360, 830]; N samples (default one per 10 nm)")
      ->capture_default_str();
  declared("temperature_c", "temperature_c");
  sub->add_option("--shape", args->req->shape,
                  fmt::format("Drop shape: sphere, spheroid:Q (axis ratio Q = polar / equatorial in [{:g}, 1], axis "
                              "vertical) or beard-chuang (falling drops, Q from the radius); non-spherical drops need "
                              "--theory airy or airy:3 (docs/non-spherical.md)",
                              atmos::kMinBowAxisRatio))
      ->capture_default_str();
  declared("sun_elevation_deg", "canting_deg");
  sub->add_option("--medium", args->medium, "Drop medium (hydrolux ior --list)")->capture_default_str();
  sub->add_option("--sun", args->sun, "Light source: astm-g173-direct, blackbody:T (kelvin) or equal-energy")
      ->capture_default_str();
  sub->add_option("--color-space", args->color_space, "Linear RGB primaries: rec709 (sRGB) or rec2020")
      ->check(CLI::IsMember({"rec709", "srgb", "rec2020"}))
      ->capture_default_str();
  declared("sampling", "threads");
  sub->add_flag("--json", args->json,
                "Print one radius's profile (angle, RGB, luminance, XYZ; with --stokes Q's XYZ and dolp) as JSON on "
                "stdout");
  declared("stokes", "stokes");
  sub->add_option("-o,--output", args->output,
                  "Output .exr (the .png and .json are written beside it), or .nc: one NetCDF-4 file with CF "
                  "attributes (xarray.open_dataset, ncdump)");
  sub->add_flag("-q,--quiet", args->quiet, "No progress or summary on stderr");
  cmd.flags_for_quantity.insert({{"radius_um", "--radius-um"},
                                 {"angle_deg", "--angle-deg"},
                                 {"columns", "--size"},
                                 {"rows", "--size"},
                                 {"wavelength_nm", "--wavelengths-nm"},
                                 {"wavelengths", "--wavelengths-nm"},
                                 {"size_parameter", "--radius-um (the size parameter 2 pi r / lambda)"},
                                 {"temperature_k", "--sun"},
                                 {"m_imag", "--medium (its index relative to air)"},
                                 {"m_real", "--medium (its index relative to air)"},
                                 {"p", "--theory"},
                                 {"axis_ratio", "--shape"}});
  return cmd;
}

}  // namespace hydrolux::cli
