// hydrolux sky: a rainbow (secondary, fogbow, corona) in a daylight scene, rendered per pixel from
// the Lee tables on the CPU: the reference the shaders and the web demo are checked against.
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <memory>
#include <optional>
#include <utility>

#include "common.hpp"
#include "hydrolux/atmos/lee.hpp"
#include "hydrolux/core/error.hpp"
#include "hydrolux/core/parse.hpp"
#include "hydrolux/scene/bow_tables.hpp"
#include "hydrolux/scene/compositor.hpp"
#include "hydrolux/scene/sky_params.hpp"
#include "image_plugin.hpp"
#include "lee_files.hpp"
#include "params.hpp"
#include "progress.hpp"

namespace hydrolux::cli {

namespace {

struct SkyArgs {
  std::shared_ptr<scene::SkyOptions> o = std::make_shared<scene::SkyOptions>();  // the declared values
  std::string size = "1280x720";
  std::string curtain = "1000:3000";
  std::vector<std::string> luts;
  std::optional<std::string> moisture, environment, light_color;
  std::string blend = "physical", mode = "per-pixel";
  std::string output;
  bool quiet = false;
  const CLI::App* sub = nullptr;  // which flags were given
};

// A flag given where it has no effect is refused (given, never its default): it says why, and what
// would use it.
void refuse_unused(const SkyArgs& a, std::string_view name, bool used_here, const std::string& why) {
  const auto* opt = a.sub->get_option_no_throw(std::string(scene::sky_param(name).flag));
  if (opt && opt->count() > 0 && !used_here)
    throw Error(fmt::format("{} {}: {}", opt->get_name(), opt->as<std::string>(), why));
}

int run_sky(const SkyArgs& a) {
  scene::SkySettings s = a.o->settings;
  {
    const auto wh = parse_size(a.size);  // checked by the option's validator
    s.camera.width = (*wh)[0];
    s.camera.height = (*wh)[1];
  }
  {
    const auto p = parse::pair(a.curtain, ':');
    if (!p || !((*p)[0] >= 0) || !((*p)[1] >= (*p)[0]) || (*p)[1] > 1e6)
      throw Error(fmt::format("--curtain-distance-m '{}': expected NEAR:FAR in metres, 0 <= NEAR <= FAR <= 1e6",
                              a.curtain));
    s.curtain_near_m = (*p)[0];
    s.curtain_far_m = (*p)[1];
  }
  if (a.light_color) {
    std::vector<double> v;
    std::string_view rest = *a.light_color;
    while (true) {
      const auto comma = rest.find(',');
      const auto x = parse::number(rest.substr(0, comma));
      v.push_back(x && *x >= 0 && *x <= 1000 ? *x : -1);
      if (comma == std::string_view::npos) break;
      rest.remove_prefix(comma + 1);
    }
    if (v.size() != 3 || std::any_of(v.begin(), v.end(), [](double x) { return x < 0; }))
      throw Error(fmt::format("--light-color '{}': expected R,G,B, three linear multipliers in [0, 1000]",
                              *a.light_color));
    s.light_color = {v[0], v[1], v[2]};
  }
  s.blend = a.blend == "whitepaper" ? scene::Blend::whitepaper : scene::Blend::physical;
  s.mode = a.mode == "cube-map" ? scene::BowMode::cube_map
                                : a.mode == "half-dome" ? scene::BowMode::half_dome : scene::BowMode::per_pixel;
  scene::validate(s);
  atmos::DropShapeSpec shape;
  try {
    shape = atmos::parse_drop_shape(a.o->shape);
  } catch (const Error& e) {
    throw Error(fmt::format("--{}", e.what()));  // the library's message starts "shape '<value>': "
  }
  const bool shaped = !shape.spherical();
  if (shaped) {
    // Non-spherical drops: their bow, which changes along its arc, is computed here for the scene's
    // sun at kShapePositions position angles (Airy theory of the plane section).
    if (!a.luts.empty())
      throw Error(fmt::format("--shape {}: non-spherical drops' bow changes along its arc and is computed here at {} "
                              "position angles, while --lut tables hold one bow for all of it (omit --lut or --shape)",
                              a.o->shape, scene::kShapePositions));
    if (s.sun_elevation_deg > scene::max_shape_sun_elevation_deg())
      throw Error(fmt::format("--shape {}: non-spherical drops' bow is computed for a sun at most {:g} degrees up "
                              "(--sun-elevation-deg {:g}; the bow is below the horizon anyway)",
                              a.o->shape, scene::max_shape_sun_elevation_deg(), s.sun_elevation_deg));
    scene::check_shape_radius(shape, s.radius_um);
  }
  // The tables computed here are Mie's, whose size parameter limit caps the radius; given tables
  // (--lut, e.g. geometric optics up to 5000 um) cover what they cover.
  if (!shaped && a.luts.empty() && s.radius_um > scene::max_sky_radius_um())
    throw Error(fmt::format("--radius-um {:g} is outside the valid range [{:g}, {:g}] um of the tables computed "
                            "without --lut (Mie's size parameter limit at 380 nm); give tables that cover it with --lut",
                            s.radius_um, atmos::kMinRadiusUm, scene::max_sky_radius_um()));
  refuse_unused(a, "sampling", a.luts.empty(),
                "sets the sampling of the tables computed without --lut; --lut gives the tables (omit --sampling)");
  refuse_unused(a, "sky_max_dolp", s.polarizer_deg.has_value() || s.stokes,
                "sets the sky's polarisation, which only a polariser or the Stokes images show (add --polarizer-deg or "
                "--stokes, or omit --sky-max-dolp)");
  if (s.stokes && s.polarizer_deg)
    throw Error(fmt::format("--stokes: the Stokes images are the light before any filter (a filter at A passes (I + Q "
                            "cos 2A + U sin 2A) / 2 of them); give --stokes or --polarizer-deg {:g}, not both",
                            *s.polarizer_deg));
  if (s.stokes && s.blend != scene::Blend::physical)
    throw Error("--stokes: the Stokes images need --blend physical (the whitepaper's blend is not linear in the light)");
  refuse_unused(a, "environment_scale", a.environment.has_value(),
                "scales --environment's values; without --environment there is nothing to scale");
  for (const auto& [name, mode] : {std::pair{"cube_face_size", scene::BowMode::cube_map},
                                   {"dome_rings", scene::BowMode::half_dome},
                                   {"dome_segments", scene::BowMode::half_dome}})
    refuse_unused(a, name, s.mode == mode,
                  fmt::format("used by --mode {} only (this run is --mode {})", scene::bow_mode_name(mode), a.mode));
  if (s.corona && a.luts.empty() && s.radius_um > scene::kCoronaMaxRadiusUm)
    throw Error(fmt::format("--corona: drops of {:g} um (--radius-um) put their corona within 0.2 degrees of the sun, "
                            "where nothing is drawn; coronas come from cloud droplets of 1-{:g} um (try --radius-um "
                            "10) or omit --corona",
                            s.radius_um, scene::kCoronaMaxRadiusUm));
  if (a.output.empty()) throw Error("-o is required (a .png or .exr path)");
  check_sky_memory(s, a.size);

  // Every file is checked before the work.
  io::FileSet files;
  for (const auto& l : a.luts) {
    files.input("--lut", l);
    files.input("--lut (its .json sidecar)", std::filesystem::path(l).replace_extension(".json"));
  }
  if (a.moisture) files.input("--moisture", *a.moisture);
  if (a.environment) files.input("--environment", *a.environment);
  const ImageOutput out = declare_output_image(files, "-o", a.output);
  if (s.stokes && out.format != io::ImageFormat::exr)
    throw Error(fmt::format("--stokes: the Stokes images are linear and signed: -o must be a .exr (got {})",
                            printable(a.output)));
  // The image plugin, loaded now: a missing or broken plugin is reported before the tables are computed.
  (void)image_api();

  // The tables: given (--lut), or one radius's profiles computed now.
  SkySlices tables;
  const bool polarized = s.polarizer_deg.has_value() || s.stokes;  // the tables' Q needed
  if (!a.luts.empty()) {
    tables = read_sky_luts(a.luts, s.radius_um, s.corona);
    // A polariser needs the tables' Stokes Q.
    for (const auto* slice : {&tables.rainbow, &tables.corona})
      if (polarized && !slice->empty() && !slice->has_q() && (slice == &tables.rainbow || s.corona))
        throw Error(fmt::format("{}: the {} table given with --lut has no Stokes Q (make it with hydrolux lee --stokes, "
                                "or hydrolux export)",
                                s.stokes ? std::string("--stokes") : fmt::format("--polarizer-deg {:g}", *s.polarizer_deg),
                                slice == &tables.rainbow ? "rainbow" : "corona"));
  }

  // The images are read (and checked) before any work.
  std::shared_ptr<const scene::Environment> env;
  if (a.environment) {
    Image image = read_input_image("--environment", *a.environment);
    try {
      env = std::make_shared<scene::EquirectEnvironment>(std::move(image));
    } catch (const Error& e) {
      throw Error(fmt::format("--environment {}: {}", *a.environment, e.what()));  // printed through printable()
    }
  }
  std::optional<Image> moisture;
  if (a.moisture) moisture = read_input_image("--moisture", *a.moisture);

  ProgressBar bar("sky", a.quiet);
  const auto start = std::chrono::steady_clock::now();
  scene::RainbowSlices shaped_rainbow;
  if (a.luts.empty()) {  // this radius's tables, computed now
    const bool need_corona = s.corona && s.radius_um <= scene::kCoronaMaxRadiusUm;
    const int jobs = need_corona ? 2 : 1;
    int done = 0;
    const auto sub = [&](double f, std::string_view label) { bar.update((done + f) / jobs, label); };
    // With a polariser the tables carry the Stokes Q (1.04x the time of I alone, BENCHMARKS.md).
    const auto spec = [&](atmos::LeeTableKind kind) {
      atmos::LeeSpec p = scene::sky_profile_spec(kind, s.radius_um, a.o->sampling);
      p.stokes = polarized;
      return p;
    };
    if (shaped)
      shaped_rainbow = scene::compute_shaped_rainbow(shape, s.radius_um, a.o->sampling, s.sun_elevation_deg,
                                                     s.secondary, sub, polarized);
    else
      tables.rainbow = scene::compute_bow_slice(spec(atmos::LeeTableKind::rainbow), sub);
    ++done;
    if (need_corona) tables.corona = scene::compute_bow_slice(spec(atmos::LeeTableKind::corona), sub);
  }

  const scene::SkyCompositor comp(s, shaped ? std::move(shaped_rainbow) : scene::RainbowSlices(std::move(tables.rainbow)),
                                  std::move(tables.corona), env, a.o->environment_scale);
  const auto t0 = std::chrono::steady_clock::now();
  const Image radiance = comp.render(moisture ? &*moisture : nullptr);
  const double render_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  bar.finish();
  // The PNG's exposure: a polariser passes half of unpolarised light, for which a camera opens up one
  // stop; the EXR stays absolute.
  write_output_image(out, out.format == io::ImageFormat::exr
                              ? radiance
                              : scene::tone_map(radiance, comp.sun_sky().l_ref * (s.polarizer_deg ? 0.5 : 1.0)));
  files.commit();
  if (!a.quiet) {
    const double tau = comp.beta_geo_per_m() * (s.curtain_far_m - s.curtain_near_m);
    fmt::print(stderr,
               "sky: wrote {} ({}x{}, {}, {} blend{}); rain {:g} mm/h: optical depth {:.3g} (projected area) over the "
               "curtain; sun {:.0f} klux;{} frame {:.1f} ms{}; {:.1f} s in all\n",
               printable(a.output), s.camera.width, s.camera.height, scene::bow_mode_name(s.mode),
               scene::blend_name(s.blend),
               s.polarizer_deg ? fmt::format(", polariser at {:g} deg", *s.polarizer_deg)
                               : s.stokes ? std::string(", Stokes I, Q, U") : std::string(),
               s.rain_rate_mmh,
               tau, comp.sun_sky().sun_illuminance_lux / 1000,
               shaped ? fmt::format(" {} drops: the bow at {} position angles (Airy theory);",
                                    atmos::drop_shape_name(shape), comp.rainbow_positions())
                      : std::string(),
               render_ms,
               s.mode == scene::BowMode::per_pixel ? "" : fmt::format(" (bake {:.1f} ms)", comp.bake_seconds() * 1e3),
               std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  return 0;
}

}  // namespace

Command add_sky(CLI::App& app) {
  auto a = std::make_shared<SkyArgs>();
  auto* sub = app.add_subcommand(
      "sky",
      "A rainbow in a daylight scene, per pixel on the CPU: the view ray's angle to the sun looked up in the Lee "
      "tables, times the sun's light and the rain curtain's scattering (Marshall-Palmer rain at --rain-rate-mmh), over "
      "Preetham's analytic sky and a ground plane. The EXR is linear Rec.709 in cd/m^2; the PNG is tone-mapped "
      "(docs/sky.md). Without --lut the tables for --radius-um are computed first (Mie, with progress and an ETA): "
      "about 12 s for 500 um drops on two cores at --sampling 1, growing as --sampling squared (50 s at 2, about an "
      "hour at 16) and with the radius; for repeated or finer renders compute a table once (hydrolux lee or export) "
      "and give it with --lut. Frames are refused up front when they would not fit in the memory available.");
  a->sub = sub;
  Command cmd{sub, [a] { return run_sky(*a); }, {}};
  const auto params = scene::sky_params();
  const auto declared = [&](std::string_view first, std::string_view last) {
    add_params(*sub, a->o, fields_from(params, first, last), cmd.flags_for_quantity);
  };
  declared("sun_elevation_deg", "view_elevation_deg");
  sub->add_option("--size", a->size, "Image size WxH in pixels")->check(size_validator())->capture_default_str();
  declared("rain_rate_mmh", "rain_rate_mmh");
  sub->add_option("--curtain-distance-m", a->curtain, "The rain fills NEAR:FAR metres from the camera")->capture_default_str();
  declared("turbidity", "turbidity");
  sub->add_option("--lut", a->luts, "A Lee table .exr (with its .json beside it): a rainbow table, and optionally a corona table; repeat the flag");
  sub->add_option("--moisture", a->moisture, "Moisture mask image (red channel, 0-1, stretched over the frame): scales the rain per pixel");
  sub->add_option("--environment", a->environment, "Equirectangular HDR background (.exr/.hdr) in cd/m^2 instead of the analytic sky and ground");
  declared("environment_scale", "environment_scale");
  sub->add_option("--light-color", a->light_color, "R,G,B multiplier on the sun's light in the bow [1,1,1]");
  declared("corona", "secondary");
  sub->add_option("--shape", a->o->shape,
                  fmt::format("Drop shape: sphere (the Mie tables), spheroid:Q (axis ratio Q = polar / equatorial in "
                              "[{:g}, 1], axis vertical) or beard-chuang (falling drops, Q from the radius; radii up to "
                              "{:g} um). Non-spherical drops' bow changes along its arc: computed by Airy theory of the "
                              "drops' plane section (primary, and the secondary unless --no-secondary) for the sun's "
                              "elevation at position angles 0, 10, ..., 180 degrees around the antisolar point and "
                              "interpolated between them; not with --lut (docs/sky.md)",
                              atmos::kMinBowAxisRatio,
                              scene::max_sky_radius_um(atmos::parse_drop_shape("beard-chuang"))))
      ->capture_default_str();
  sub->add_option("--blend", a->blend, "physical (attenuation + in-scattering) or whitepaper (scene + bow (1 - scene))")
      ->check(CLI::IsMember({"physical", "whitepaper"}))->capture_default_str();
  sub->add_option("--mode", a->mode, "per-pixel (reference), cube-map (baked bow) or half-dome (tessellated, 1D lookup)")
      ->check(CLI::IsMember({"per-pixel", "cube-map", "half-dome"}))->capture_default_str();
  declared("cube_face_size", "sampling");
  sub->add_option("-o,--output", a->output, "Output .png (tone-mapped) or .exr (cd/m^2)");
  sub->add_flag("-q,--quiet", a->quiet, "No progress or summary on stderr");
  cmd.flags_for_quantity.insert({{"width", "--size"},
                                 {"shape", "--shape"},
                                 {"height", "--size"},
                                 {"curtain_near_m", "--curtain-distance-m"},
                                 {"curtain_far_m", "--curtain-distance-m"},
                                 {"light_color", "--light-color"},
                                 {"size_parameter", "--radius-um (the size parameter 2 pi r / lambda)"}});
  return cmd;
}

}  // namespace hydrolux::cli
