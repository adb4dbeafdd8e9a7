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
#include "hydrolux/scene/environment.hpp"
#include "image_plugin.hpp"
#include "params.hpp"
#include "progress.hpp"

namespace hydrolux::cli {

namespace {

// The declared parameters are drop/params.hpp's; the environment, the medium and the output are this
// command's.
struct RenderArgs {
  std::shared_ptr<drop::DropRenderRequest> r = std::make_shared<drop::DropRenderRequest>();
  std::string env = "builtin";
  std::string medium = "water";
  std::string output;
  bool quiet = false;
};

int run_render(const RenderArgs& a) {
  const drop::DropRenderRequest& r = *a.r;
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
  drop::check_shape(r, drop::ParamWords::flags);
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
  // The declared parameters in two runs, the medium between them.
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
  declared(8, params.size() - 8);  // --temperature-c .. --depth
  sub->add_option("-o,--output", args->output, "Output image (.exr linear float, or .png sRGB)")->required();
  sub->add_flag("-q,--quiet", args->quiet, "No progress or summary on stderr");
  return cmd;
}

}  // namespace hydrolux::cli
