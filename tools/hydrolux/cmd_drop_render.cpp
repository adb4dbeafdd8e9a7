// hydrolux drop render: a rain drop's picture from an environment (Garg & Nayar Figure 8).
#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <memory>
#include <optional>

#include "common.hpp"
#include "hydrolux/core/error.hpp"
#include "hydrolux/core/math.hpp"
#include "hydrolux/drop/render.hpp"
#include "hydrolux/drop/shape.hpp"
#include "hydrolux/drop/trace.hpp"
#include "image_plugin.hpp"
#include "hydrolux/optics/media.hpp"
#include "hydrolux/scene/environment.hpp"
#include "progress.hpp"

namespace hydrolux::cli {

namespace {

struct RenderArgs {
  std::string env = "builtin";
  double radius_mm = 1.0;
  double distance_m = 2.0;
  double focal_mm = 50.0;
  double f_number = 2.8;
  std::optional<double> frame_mm;
  int size = 512;
  int samples = 4;
  int internal = 2;
  std::string medium = "water";
  std::optional<double> temperature_c;
  double wavelength_nm = 589.3;
  bool dispersion = false;
  bool background_blur = false;
  bool no_background = false;
  double exposure_ev = 0;
  std::string method = "model";
  std::string shape = "sphere";
  int depth = 8;
  std::string output;
  bool quiet = false;
};

int run_render(const RenderArgs& a) {
  // Every file and flag is checked before the work starts: the environment is a regular file, the
  // output's folder takes a new file and the output is not the environment.
  io::FileSet files;
  if (a.env != "builtin") {
    const std::filesystem::path p(a.env);
    std::string e = p.extension().string();
    std::transform(e.begin(), e.end(), e.begin(), [](unsigned char ch) { return char(std::tolower(ch)); });
    if (e != ".exr" && e != ".hdr")
      throw Error(fmt::format("--env {}: expected an equirectangular .exr or .hdr file, or 'builtin'", a.env));
    files.input("--env", a.env);
  }
  const ImageOutput output = declare_output_image(files, "-o", a.output);
  const auto water = medium_flag("--medium", a.medium);
  const auto air = optics::find_medium("air");
  check_temperature_flag(a.temperature_c, {water.get()});
  if (a.distance_m <= 1.01 * a.radius_mm * 1e-3)
    throw Error(fmt::format("--distance-m {:g} must exceed the drop radius ({:g} m) by at least 1%", a.distance_m,
                            a.radius_mm * 1e-3));
  if (a.shape == "beard-chuang") {
    const auto range = drop::drop_shape_radius_range_m();
    if (a.radius_mm < range[0] * 1e3 || a.radius_mm > range[1] * 1e3)
      throw Error(fmt::format("--radius-mm {:g} is outside the valid range [{:g}, {:g}] mm of the Beard & Chuang shape",
                              a.radius_mm, range[0] * 1e3, range[1] * 1e3));
  }
  if (a.method == "model" && a.shape != "sphere")
    throw Error("--shape " + a.shape + ": the model is for a sphere; use --method exact for other shapes");
  double blur_rad = 0;
  if (a.background_blur) {
    if (a.distance_m <= 1.01 * a.focal_mm * 1e-3)
      throw Error(fmt::format("--distance-m {:g} must exceed the focal length (--focal-mm {:g}) to focus on the drop",
                              a.distance_m, a.focal_mm));
    blur_rad = drop::defocus_blur_radius_rad(a.focal_mm * 1e-3, a.f_number, a.distance_m);
    if (blur_rad > kPi<> / 6)
      throw Error(fmt::format("--background-blur: --focal-mm {:g} at --f-number {:g} focused at --distance-m {:g} "
                              "gives a defocus disk {:.1f} degrees wide; at most 60 degrees is supported",
                              a.focal_mm, a.f_number, a.distance_m, 2 * rad_to_deg(blur_rad)));
  }
  // The drop's index relative to the air around it, at one wavelength or per channel.
  const auto relative = [&](double nm) { return water->n(nm, a.temperature_c) / air->n(nm); };
  drop::ChannelIndex mu;
  if (a.dispersion) {
    for (std::size_t c = 0; c < 3; ++c) mu[c] = relative(drop::kChannelWavelengthsNm[c]);
  } else {
    mu.fill(relative(a.wavelength_nm));
  }
  (void)image_api();  // image support loads now, not after the render

  std::unique_ptr<scene::Environment> env;
  if (a.env == "builtin") {
    env = std::make_unique<scene::BuiltinSky>();
  } else {
    Image map = read_input_image("--env", a.env);
    try {
      env = std::make_unique<scene::EquirectEnvironment>(std::move(map));
    } catch (const IoError& err) {
      throw IoError(fmt::format("--env {}: {}", a.env, err.what()));
    }
  }

  drop::DropCamera cam;
  cam.radius_m = a.radius_mm * 1e-3;
  cam.distance_m = a.distance_m;
  cam.frame_m = (a.frame_mm ? *a.frame_mm : 5.0 * a.radius_mm) * 1e-3;
  cam.width = cam.height = a.size;
  drop::validate(cam);

  drop::RenderOptions opt;
  opt.samples_per_axis = a.samples;
  opt.n_internal = a.internal;
  opt.background = !a.no_background;
  opt.background_blur_rad = blur_rad;  // the lens is focused on the drop, the scene is at infinity
  ProgressBar bar("drop render", a.quiet);
  opt.progress = bar.callback();
  Image img;
  if (a.method == "model") {
    img = drop::render_model(cam, *env, mu, opt);
  } else {
    const auto surface = drop::make_drop_surface(
        cam, a.shape == "sphere" ? drop::DropShapeKind::sphere : drop::DropShapeKind::beard_chuang);
    drop::TraceOptions trace;
    trace.max_depth = a.depth;
    img = drop::render_exact(cam, *env, mu, *surface, opt, trace);
  }
  bar.finish();

  const float gain = float(std::exp2(a.exposure_ev));
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x)
      for (int c = 0; c < 3; ++c) img.at(x, y, c) *= gain;
  write_output_image(output, img);
  files.commit();
  if (!a.quiet)
    fmt::print(stderr, "drop render: wrote {} ({}x{}, drop radius {:.1f} px, mu {:.5f}{})\n", printable(a.output), img.width,
               img.height, cam.drop_radius_px(), mu[1], a.dispersion ? " (green channel)" : "");
  return 0;
}

}  // namespace

Command add_drop_render(CLI::App& drop) {
  auto args = std::make_shared<RenderArgs>();
  auto* sub = drop.add_subcommand(
      "render",
      "Render a rain drop from an environment with Garg & Nayar's model (their Figure 8): a pinhole camera "
      "looks along +z at a spherical drop on its axis; every pixel has its own viewing direction; the rim is "
      "anti-aliased by supersampling. Output: linear EXR, or sRGB PNG (RGBA: alpha is the drop's coverage "
      "when --no-background is given).");
  sub->add_option("--env", args->env,
                  "Environment: an equirectangular .exr/.hdr (longitude 0 at the centre column = straight ahead), "
                  "or 'builtin' (a procedural sky, sun, road and landmarks)")
      ->capture_default_str();
  sub->add_option("--radius-mm", args->radius_mm, "Drop radius in mm")->check(number_in(0.01, 100))->capture_default_str();
  sub->add_option("--distance-m", args->distance_m, "Distance from the camera to the drop's centre in metres")
      ->check(number_in(0.001, 1e4))
      ->capture_default_str();
  sub->add_option("--focal-mm", args->focal_mm, "Lens focal length in mm (sets the aperture for --background-blur)")
      ->check(number_in(1, 2000))
      ->capture_default_str();
  sub->add_option("--f-number", args->f_number, "Lens f-number (aperture = focal / f-number)")
      ->check(number_in(0.5, 128))
      ->capture_default_str();
  sub->add_option("--frame-mm", args->frame_mm,
                  "Width of the field at the drop's distance in mm [default: 5 x the drop radius]")
      ->check(number_in(1e-6, 1e6));
  sub->add_option("--size", args->size, "Image width and height in pixels")->transform(integer_in(8, 16384, "px"))->capture_default_str();
  sub->add_option("--samples", args->samples, "Supersamples per pixel along each axis (anti-aliasing)")
      ->transform(integer_in(1, 64))
      ->capture_default_str();
  sub->add_option("--internal", args->internal, "Internal reflections added by the model (eq. 19)")
      ->transform(integer_in(0, 20))
      ->capture_default_str();
  sub->add_option("--medium", args->medium, "Drop medium (see hydrolux ior --list; const:1.49 for acrylic)")
      ->capture_default_str();
  sub->add_option("--temperature-c", args->temperature_c,
                  "Drop temperature in Celsius, for media with a temperature model (water: 0 to 100) "
                  "[medium's default]")
      ->check(number_in(-273.15, 1000, "C"));
  sub->add_option("--wavelength-nm", args->wavelength_nm, "Vacuum wavelength of the index without --dispersion")
      ->check(number_in(200, 2500))
      ->capture_default_str();
  sub->add_flag("--dispersion", args->dispersion,
                "Per-channel index at 610/550/465 nm: the channels' paths part (colour fringes)");
  sub->add_flag("--background-blur", args->background_blur,
                "Defocus the background: the camera is focused on the drop, the scene is at infinity");
  sub->add_flag("--no-background", args->no_background, "Black background with the drop's coverage in alpha");
  sub->add_option("--exposure-ev", args->exposure_ev, "Exposure adjustment in stops applied to the output")
      ->check(number_in(-30, 30))
      ->capture_default_str();
  sub->add_option("--method", args->method,
                  "model: Garg & Nayar's model (eq. 19); exact: the Fresnel-split ray tracer (every path to --depth)")
      ->check(CLI::IsMember({"model", "exact"}))
      ->capture_default_str();
  sub->add_option("--shape", args->shape,
                  "Drop shape for --method exact: sphere, or beard-chuang (the falling drop's equilibrium shape, "
                  "radius 0.5-4.5 mm, seen from the side)")
      ->check(CLI::IsMember({"sphere", "beard-chuang"}))
      ->capture_default_str();
  sub->add_option("--depth", args->depth, "Surface interactions the exact tracer follows per path")
      ->transform(integer_in(6, 64))
      ->capture_default_str();
  sub->add_option("-o,--output", args->output, "Output image (.exr linear float, or .png sRGB)")->required();
  sub->add_flag("-q,--quiet", args->quiet, "No progress or summary on stderr");
  return {sub,
          [args] { return run_render(*args); },
          {{"wavelength_nm", "--wavelength-nm"},
           {"mu", "--medium (index relative to air)"},
           {"temperature_c", "--temperature-c"},
           {"distance_m", "--distance-m"}}};
}

}  // namespace hydrolux::cli
