// hydrolux drop render: a rain drop's picture from an environment (Garg & Nayar Figure 8).
#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <memory>

#include "common.hpp"
#include "hydrolux/core/error.hpp"
#include "hydrolux/drop/params.hpp"
#include "hydrolux/drop/render.hpp"
#include "hydrolux/optics/media.hpp"
#include "hydrolux/scatter/drop_shape.hpp"
#include "hydrolux/scene/environment.hpp"
#include "image_plugin.hpp"
#include "params.hpp"
#include "progress.hpp"

namespace hydrolux::cli {

namespace {

// The numbers and switches are drop/params.hpp's; the environment, the medium, the method, the
// shape and the output are this command's.
struct RenderArgs {
  std::shared_ptr<drop::DropRenderRequest> r = std::make_shared<drop::DropRenderRequest>();
  std::string env = "builtin";
  std::string medium = "water";
  std::string method = "model";
  std::string shape = "sphere";
  std::string output;
  bool quiet = false;
};

int run_render(const RenderArgs& a) {
  drop::DropRenderRequest r = *a.r;
  r.method = a.method == "model" ? drop::RenderMethod::model : drop::RenderMethod::exact;
  r.shape = a.shape == "sphere" ? drop::DropShapeKind::sphere : drop::DropShapeKind::beard_chuang;
  // Every file and flag is checked before the work starts: the environment is a regular file, the
  // output's folder takes a new file and the output is not the environment.
  io::FileSet files;
  if (a.env != "builtin") {
    const std::string e = io::lower_extension(a.env);
    if (e != ".exr" && e != ".hdr")
      throw Error(fmt::format("--env {}: expected an equirectangular .exr or .hdr file, or 'builtin'", a.env));
    files.input("--env", a.env);
  }
  const ImageOutput output = declare_output_image(files, "-o", a.output);
  const auto water = medium_flag("--medium", a.medium);
  const auto air = optics::find_medium("air");
  check_temperature_flag(r.temperature_c, {water.get()});
  drop::check_clearance(r, drop::ParamWords::flags);
  if (r.shape == drop::DropShapeKind::beard_chuang) {
    const auto range = scatter::drop_shape_radius_range_m();
    if (r.radius_mm < range[0] * 1e3 || r.radius_mm > range[1] * 1e3)
      throw Error(fmt::format("--radius-mm {:g} is outside the valid range [{:g}, {:g}] mm of the Beard & Chuang shape",
                              r.radius_mm, range[0] * 1e3, range[1] * 1e3));
  }
  if (a.method == "model" && a.shape != "sphere")
    throw Error("--shape " + a.shape + ": the model is for a sphere; use --method exact for other shapes");
  const double blur_rad = drop::background_blur_rad(r, drop::ParamWords::flags);
  const drop::ChannelIndex mu = drop::relative_index(r, *water, *air);
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

  const drop::DropCamera cam = drop::camera_for(r);
  drop::validate(cam);
  ProgressBar bar("drop render", a.quiet);
  const Image img = drop::render_request(r, cam, *env, mu, blur_rad, bar.callback());
  bar.finish();
  write_output_image(output, img);
  files.commit();
  if (!a.quiet)
    fmt::print(stderr, "drop render: wrote {} ({}x{}, drop radius {:.1f} px, mu {:.5f}{})\n", printable(a.output), img.width,
               img.height, cam.drop_radius_px(), mu[1], r.dispersion ? " (green channel)" : "");
  return 0;
}

}  // namespace

Command add_drop_render(CLI::App& drop) {
  auto args = std::make_shared<RenderArgs>();
  auto* sub = add_job_command(drop, "drop_render");
  Command cmd{sub,
              [args] { return run_render(*args); },
              {{"wavelength_nm", "--wavelength-nm"},
               {"mu", "--medium (index relative to air)"},
               {"temperature_c", "--temperature-c"},
               {"distance_m", "--distance-m"}}};
  // The declared parameters in three runs, the medium, the method and the shape between them.
  const auto params = drop::drop_render_params();
  const auto declared = [&](std::size_t from, std::size_t count) {
    add_params(*sub, args->r, params.subspan(from, count), cmd.flags_for_quantity);
  };
  sub->add_option("--env", args->env,
                  "Environment: an equirectangular .exr/.hdr (longitude 0 at the centre column = straight ahead), "
                  "or 'builtin' (a procedural sky, sun, road and landmarks)")
      ->capture_default_str();
  declared(0, 8);  // --radius-mm .. --internal
  sub->add_option("--medium", args->medium, "Drop medium (see hydrolux ior --list; const:1.49 for acrylic)")
      ->capture_default_str();
  declared(8, 6);  // --temperature-c .. --exposure-ev
  sub->add_option("--method", args->method,
                  "model: Garg & Nayar's model (eq. 19); exact: the Fresnel-split ray tracer (every path to --depth)")
      ->check(CLI::IsMember({"model", "exact"}))
      ->capture_default_str();
  sub->add_option("--shape", args->shape,
                  "Drop shape for --method exact: sphere, or beard-chuang (the falling drop's equilibrium shape, "
                  "radius 0.5-4.5 mm, seen from the side)")
      ->check(CLI::IsMember({"sphere", "beard-chuang"}))
      ->capture_default_str();
  declared(14, params.size() - 14);  // --depth
  sub->add_option("-o,--output", args->output, "Output image (.exr linear float, or .png sRGB)")->required();
  sub->add_flag("-q,--quiet", args->quiet, "No progress or summary on stderr");
  return cmd;
}

}  // namespace hydrolux::cli
