// hydrolux sky: a rainbow (secondary, fogbow, corona) in a daylight scene, rendered per pixel from
// the Lee tables on the CPU: the reference the shaders and the web demo are checked against.
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <memory>
#include <optional>

#include "common.hpp"
#include "hydrolux/atmos/lee.hpp"
#include "hydrolux/core/error.hpp"
#include "hydrolux/core/memory.hpp"
#include "hydrolux/core/parse.hpp"
#include "hydrolux/scene/compositor.hpp"
#include "image_plugin.hpp"
#include "lee_files.hpp"
#include "progress.hpp"

namespace hydrolux::cli {

namespace {

struct SkyArgs {
  scene::SkySettings s;
  std::string size = "1280x720";
  std::string curtain = "1000:3000";
  std::vector<std::string> luts;
  std::optional<std::string> moisture, environment, light_color;
  double environment_scale = 1;
  bool no_secondary = false;
  std::string blend = "physical", mode = "per-pixel";
  double sampling = 1;
  std::string output;
  bool quiet = false;
  // The options whose use depends on others: refused when given (count(), never their defaults)
  // where they would be ignored.
  const CLI::Option *sampling_opt = nullptr, *environment_scale_opt = nullptr, *cube_face_size_opt = nullptr,
                    *dome_rings_opt = nullptr, *dome_segments_opt = nullptr;
};

constexpr double kCoronaTableMaxRadiusUm = 50;
constexpr double kTableSizeSpread = 0.1;

// The tables computed without --lut: one radius's profile, a 10% gamma spread. The same spec gives
// --radius-um's range (atmos::max_radius_um), so the help, the check and the work agree.
atmos::LeeSpec table_spec(atmos::LeeTableKind kind, double radius_um, double sampling) {
  atmos::LeeSpec spec = kind == atmos::LeeTableKind::corona
                            ? atmos::profile_spec(kind, radius_um, 0, 90, 2048)
                            : atmos::profile_spec(kind, radius_um, 90, 180, 1024);
  spec.size_spread = kTableSizeSpread;
  spec.sampling = sampling;
  return spec;
}
double max_radius_um() { return atmos::max_radius_um(table_spec(atmos::LeeTableKind::rainbow, 500, 1)); }

// A flag given where it has no effect is refused: it says why, and what would use it.
void refuse_unused(const CLI::Option* opt, bool used_here, const std::string& why) {
  if (opt && opt->count() > 0 && !used_here)
    throw Error(fmt::format("{} {}: {}", opt->get_name(), opt->as<std::string>(), why));
}

// A frame too large for the memory left is refused before the work, naming what would fit.
void check_memory(const scene::SkySettings& s, const std::string& size_text) {
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

int run_sky(SkyArgs a) {
  scene::SkySettings s = a.s;
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
  s.secondary = !a.no_secondary;
  s.blend = a.blend == "whitepaper" ? scene::Blend::whitepaper : scene::Blend::physical;
  s.mode = a.mode == "cube-map" ? scene::BowMode::cube_map
                                : a.mode == "half-dome" ? scene::BowMode::half_dome : scene::BowMode::per_pixel;
  scene::validate(s);
  // The tables computed here are Mie's, whose size parameter limit caps the radius; given tables
  // (--lut, e.g. geometric optics up to 5000 um) cover what they cover.
  if (a.luts.empty() && s.radius_um > max_radius_um())
    throw Error(fmt::format("--radius-um {:g} is outside the valid range [{:g}, {:g}] um of the tables computed "
                            "without --lut (Mie's size parameter limit at 380 nm); give tables that cover it with --lut",
                            s.radius_um, atmos::kMinRadiusUm, max_radius_um()));
  refuse_unused(a.sampling_opt, a.luts.empty(),
                "sets the sampling of the tables computed without --lut; --lut gives the tables (omit --sampling)");
  refuse_unused(a.environment_scale_opt, a.environment.has_value(),
                "scales --environment's values; without --environment there is nothing to scale");
  refuse_unused(a.cube_face_size_opt, s.mode == scene::BowMode::cube_map,
                fmt::format("used by --mode cube-map only (this run is --mode {})", a.mode));
  refuse_unused(a.dome_rings_opt, s.mode == scene::BowMode::half_dome,
                fmt::format("used by --mode half-dome only (this run is --mode {})", a.mode));
  refuse_unused(a.dome_segments_opt, s.mode == scene::BowMode::half_dome,
                fmt::format("used by --mode half-dome only (this run is --mode {})", a.mode));
  if (s.corona && a.luts.empty() && s.radius_um > kCoronaTableMaxRadiusUm)
    throw Error(fmt::format("--corona: drops of {:g} um (--radius-um) put their corona within 0.2 degrees of the sun, "
                            "where nothing is drawn; coronas come from cloud droplets of 1-{:g} um (try --radius-um "
                            "10) or omit --corona",
                            s.radius_um, kCoronaTableMaxRadiusUm));
  if (a.output.empty()) throw Error("-o is required (a .png or .exr path)");
  check_memory(s, a.size);

  // Every file is checked before the work.
  io::FileSet files;
  for (const auto& l : a.luts) {
    files.input("--lut", l);
    files.input("--lut (its .json sidecar)", std::filesystem::path(l).replace_extension(".json"));
  }
  if (a.moisture) files.input("--moisture", *a.moisture);
  if (a.environment) files.input("--environment", *a.environment);
  const ImageOutput out = declare_output_image(files, "-o", a.output);
  // The image plugin, loaded now: a missing or broken plugin is reported before the tables are computed.
  (void)image_api();

  // The tables: given (--lut), or one radius's profiles computed now.
  scene::BowSlice rainbow, corona;
  bool have_rainbow = false;
  for (const auto& l : a.luts) {
    const scene::BowTable t = read_lee_lut("--lut", l);
    const double lo = t.radius_um.front(), hi = t.radius_um.back();
    if (t.kind == atmos::LeeTableKind::rainbow) {
      if (have_rainbow) throw Error(fmt::format("--lut {}: a second rainbow table (give one per kind)", printable(l)));
      if (s.radius_um < lo * 0.999 || s.radius_um > hi * 1.001)
        throw Error(fmt::format("--radius-um {:g}: outside the radii of --lut {} [{:g}, {:g}] um", s.radius_um,
                                printable(l), lo, hi));
      rainbow = scene::slice_at_radius(t, s.radius_um);
      have_rainbow = true;
    } else if (t.kind == atmos::LeeTableKind::corona) {
      if (!corona.empty()) throw Error(fmt::format("--lut {}: a second corona table (give one per kind)", printable(l)));
      corona = scene::slice_at_radius(t, s.radius_um, /*outside_is_empty=*/true);
    } else {
      throw Error(fmt::format("--lut {}: a {} table; the scene takes a rainbow table and optionally a corona table",
                              printable(l), atmos::table_kind_name(t.kind)));
    }
  }
  if (!a.luts.empty() && !have_rainbow)
    throw Error("--lut: no rainbow table among the tables given (hydrolux lee --table rainbow, or hydrolux export)");
  if (s.corona && !a.luts.empty() && corona.empty())
    throw Error(fmt::format("--corona: no corona table among --lut covers --radius-um {:g}, so nothing would be drawn "
                            "(give one: hydrolux lee --table corona, or hydrolux export; or omit --corona)",
                            s.radius_um));

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
  if (!have_rainbow) {  // no --lut: this radius's tables, computed now
    const bool need_corona = s.corona && s.radius_um <= kCoronaTableMaxRadiusUm;
    const int jobs = need_corona ? 2 : 1;
    int done = 0;
    const auto sub = [&](double f, std::string_view label) {
      bar.update((done + f) / jobs, label);
    };
    {
      const atmos::LeeSpec spec = table_spec(atmos::LeeTableKind::rainbow, s.radius_um, a.sampling);
      rainbow = scene::slice_at_radius(scene::bow_table(atmos::compute_lee_table(spec, sub)), s.radius_um);
      ++done;
    }
    if (need_corona) {
      const atmos::LeeSpec spec = table_spec(atmos::LeeTableKind::corona, s.radius_um, a.sampling);
      corona = scene::slice_at_radius(scene::bow_table(atmos::compute_lee_table(spec, sub)), s.radius_um);
    }
  }

  const scene::SkyCompositor comp(s, std::move(rainbow), std::move(corona), env, a.environment_scale);
  const auto t0 = std::chrono::steady_clock::now();
  const Image radiance = comp.render(moisture ? &*moisture : nullptr);
  const double render_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  bar.finish();
  write_output_image(out, out.format == io::ImageFormat::exr ? radiance : scene::tone_map(radiance, comp.sun_sky().l_ref));
  files.commit();
  if (!a.quiet) {
    const double tau = comp.beta_geo_per_m() * (s.curtain_far_m - s.curtain_near_m);
    fmt::print(stderr,
               "sky: wrote {} ({}x{}, {}, {} blend); rain {:g} mm/h: optical depth {:.3g} (projected area) over the "
               "curtain; sun {:.0f} klux; frame {:.1f} ms{}; {:.1f} s in all\n",
               printable(a.output), s.camera.width, s.camera.height, scene::bow_mode_name(s.mode),
               scene::blend_name(s.blend), s.rain_rate_mmh, tau, comp.sun_sky().sun_illuminance_lux / 1000, render_ms,
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
  auto& s = a->s;
  sub->add_option("--sun-elevation-deg", s.sun_elevation_deg, "The sun's elevation above the horizon, degrees")
      ->check(number_in(0, 90, "deg"))->capture_default_str();
  sub->add_option("--sun-azimuth-deg", s.sun_azimuth_deg, "The sun's azimuth, degrees from north towards east")
      ->check(number_in(-360, 360, "deg"))->capture_default_str();
  sub->add_option("--radius-um", s.radius_um,
                  fmt::format("Drop radius in micrometres (the table column; 10% gamma spread): 500 rain, 10-50 fogbow "
                              "or corona; without --lut at most {:g}, where the largest drops of the spread reach Mie "
                              "theory's size parameter limit (1e5) at 380 nm; with --lut up to {:g}, as its tables cover",
                              max_radius_um(), atmos::kMaxRadiusUm))
      ->check(number_in(atmos::kMinRadiusUm, atmos::kMaxRadiusUm, "um"))->capture_default_str();
  sub->add_option("--fov-deg", s.camera.fov_deg, "Horizontal field of view, degrees")
      ->check(number_in(1, 170, "deg"))->capture_default_str();
  sub->add_option("--view-azimuth-deg", s.camera.azimuth_deg, "Where the camera looks: azimuth, degrees from north towards east")
      ->check(number_in(-360, 360, "deg"))->capture_default_str();
  sub->add_option("--view-elevation-deg", s.camera.elevation_deg, "Where the camera looks: elevation, degrees")
      ->check(number_in(-89, 89, "deg"))->capture_default_str();
  sub->add_option("--size", a->size, "Image size WxH in pixels")->check(size_validator())->capture_default_str();
  sub->add_option("--rain-rate-mmh", s.rain_rate_mmh, "Rain rate in mm/h (Marshall-Palmer drops): sets the curtain's optical depth")
      ->check(number_in(0, 500, "mm/h"))->capture_default_str();
  sub->add_option("--curtain-distance-m", a->curtain, "The rain fills NEAR:FAR metres from the camera")->capture_default_str();
  sub->add_option("--turbidity", s.turbidity, "Atmospheric turbidity of the sky and the sun's path (Preetham: 2 clear, 10 hazy)")
      ->check(number_in(scene::kMinTurbidity, scene::kMaxTurbidity))->capture_default_str();
  sub->add_option("--lut", a->luts, "A Lee table .exr (with its .json beside it): a rainbow table, and optionally a corona table; repeat the flag");
  sub->add_option("--moisture", a->moisture, "Moisture mask image (red channel, 0-1, stretched over the frame): scales the rain per pixel");
  sub->add_option("--environment", a->environment, "Equirectangular HDR background (.exr/.hdr) in cd/m^2 instead of the analytic sky and ground");
  a->environment_scale_opt =
      sub->add_option("--environment-scale", a->environment_scale, "Multiplier on --environment's values (needs --environment)")
          ->check(number_in(0, 1e12))->capture_default_str();
  sub->add_option("--light-color", a->light_color, "R,G,B multiplier on the sun's light in the bow [1,1,1]");
  sub->add_flag("--corona", s.corona, "Draw the corona and the forward light around the sun (0-90 degrees; drops of 1-50 um)");
  sub->add_flag("--no-secondary", a->no_secondary, "Leave out the secondary bow (fades out below 134 degrees)");
  sub->add_option("--blend", a->blend, "physical (attenuation + in-scattering) or whitepaper (scene + bow (1 - scene))")
      ->check(CLI::IsMember({"physical", "whitepaper"}))->capture_default_str();
  sub->add_option("--mode", a->mode, "per-pixel (reference), cube-map (baked bow) or half-dome (tessellated, 1D lookup)")
      ->check(CLI::IsMember({"per-pixel", "cube-map", "half-dome"}))->capture_default_str();
  a->cube_face_size_opt =
      sub->add_option("--cube-face-size", s.cube_face_size, "Cube map face size in texels (--mode cube-map only)")
          ->transform(integer_in(4, 4096))->capture_default_str();
  a->dome_rings_opt =
      sub->add_option("--dome-rings", s.dome_rings, "Half dome rings from the antisolar point to 90 degrees (--mode half-dome only)")
          ->transform(integer_in(2, 4096))->capture_default_str();
  a->dome_segments_opt = sub->add_option("--dome-segments", s.dome_segments, "Half dome segments around (--mode half-dome only)")
                             ->transform(integer_in(3, 8192))->capture_default_str();
  a->sampling_opt =
      sub->add_option("--sampling", a->sampling,
                      "Sampling multiplier of the tables computed without --lut (not with --lut); the time grows as "
                      "its square: about 12 s at 1 for 500 um drops on two cores, an hour at 16")
          ->check(number_in(0.25, 16))->capture_default_str();
  sub->add_option("-o,--output", a->output, "Output .png (tone-mapped) or .exr (cd/m^2)");
  sub->add_flag("-q,--quiet", a->quiet, "No progress or summary on stderr");
  return {sub,
          [a] { return run_sky(*a); },
          {{"fov_deg", "--fov-deg"},
           {"view_azimuth_deg", "--view-azimuth-deg"},
           {"view_elevation_deg", "--view-elevation-deg"},
           {"width", "--size"},
           {"height", "--size"},
           {"sun_azimuth_deg", "--sun-azimuth-deg"},
           {"sun_elevation_deg", "--sun-elevation-deg"},
           {"turbidity", "--turbidity"},
           {"radius_um", "--radius-um"},
           {"rain_rate_mmh", "--rain-rate-mmh"},
           {"curtain_near_m", "--curtain-distance-m"},
           {"curtain_far_m", "--curtain-distance-m"},
           {"light_color", "--light-color"},
           {"environment_scale", "--environment-scale"},
           {"size_parameter", "--radius-um (the size parameter 2 pi r / lambda)"},
           {"sampling", "--sampling"}}};
}

}  // namespace hydrolux::cli
