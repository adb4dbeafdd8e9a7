// hydrolux drop undistort: a perspective view of the world recovered from the picture inside a rain
// drop (Garg & Nayar Figure 9), by inverting the drop's refraction mapping (drop/undistort.hpp).
#include <fmt/format.h>

#include <array>
#include <cmath>
#include <memory>
#include <optional>
#include <string>

#include "common.hpp"
#include "params.hpp"
#include "hydrolux/core/error.hpp"
#include "hydrolux/drop/undistort.hpp"
#include "hydrolux/core/parse.hpp"

namespace hydrolux::cli {

namespace {

struct UndistortArgs {
  std::shared_ptr<drop::UndistortRequest> request = std::make_shared<drop::UndistortRequest>();
  std::string image;
  std::string drop_center;
  std::string size;
  std::string output;
  bool quiet = false;
};

// --drop-center "X,Y": the drop's image centre in pixels (pixel centres at half-integers, y down).
CLI::Validator drop_center_validator() {
  return CLI::Validator(
      [](std::string& s) -> std::string {
        if (!parse::pair(s, ',')) return fmt::format("'{}' is not X,Y (two numbers in pixels, e.g. 256,240.5)", s);
        return {};
      },
      "X,Y");
}

int run_undistort(const UndistortArgs& a) {
  // Everything that can be checked without reading or computing, first: the input is a regular
  // file, the output's folder takes a new file and the output is not the input.
  io::FileSet files;
  files.input("--image", a.image);
  const ImageOutput output = declare_output_image(files, "-o", a.output);
  const auto centre = parse::pair(a.drop_center, ',');
  if (!centre) throw Error(fmt::format("--drop-center '{}': expected X,Y in pixels", a.drop_center));

  drop::UndistortRequest request = *a.request;
  if (!a.size.empty()) {
    const auto wh = parse_size(a.size);
    if (!wh) throw Error(fmt::format("--size '{}': expected WxH", a.size));
    request.width = (*wh)[0];
    request.height = (*wh)[1];
  }
  const drop::UndistortView view = request.view();
  drop::validate(view);

  const Image drop_image = read_input_image("--image", a.image);
  const Image out = drop::undistort(drop_image, (*centre)[0], (*centre)[1], *request.drop_radius_px, request.mu, view,
                                    request.transmission_correction);
  write_output_image(output, out);
  files.commit();

  if (!a.quiet) {
    fmt::print(stderr,
               "drop undistort: wrote {} ({}x{}, fov {:g} deg, yaw {:g}, pitch {:g}; {:.1f}% of the pixels "
               "seen through the drop)\n",
               printable(a.output), out.width, out.height, view.fov_deg, view.yaw_deg, view.pitch_deg,
               100.0 * drop::resolved_fraction(out));
  }
  return 0;
}

}  // namespace

Command add_drop_undistort(CLI::App& drop) {
  auto args = std::make_shared<UndistortArgs>();
  auto* sub = add_job_command(drop, "drop_undistort");
  Command cmd{sub, [args] { return run_undistort(*args); }, {}};
  sub->add_option("--image", args->image, "Image containing the drop (PNG/JPEG/TIFF as sRGB, EXR as linear)")
      ->required();
  sub->add_option("--drop-center", args->drop_center,
                  "The drop's image centre X,Y in pixels (x right, y down, pixel centres at half-integers)")
      ->required()
      ->check(drop_center_validator());
  add_params(*sub, args->request, drop::undistort_params(), cmd.flags_for_quantity);
  sub->get_option("--drop-radius-px")->required();
  sub->add_option("--size", args->size, "Output size WxH in pixels [default: 512x512]")
      ->check(size_validator())
      ->excludes("--width")
      ->excludes("--height");
  sub->add_option("-o,--output", args->output, "Output image (.exr linear float RGBA, or .png sRGB RGBA)")
      ->required();
  sub->add_flag("-q,--quiet", args->quiet, "No summary on stderr");
  // The library's names of what the flags give, where they are not a flag of their own.
  cmd.flags_for_quantity["width"] = "--width/--size";
  cmd.flags_for_quantity["height"] = "--height/--size";
  cmd.flags_for_quantity.insert({{"radius_px", "--drop-radius-px"},
                                 {"center_x_px", "--drop-center"},
                                 {"center_y_px", "--drop-center"},
                                 {"image_width", "--image"},
                                 {"image_height", "--image"},
                                 {"image_channels", "--image"}});
  return cmd;
}

}  // namespace hydrolux::cli
