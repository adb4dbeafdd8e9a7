// hydrolux drop undistort: a perspective view of the world recovered from the picture inside a rain
// drop (Garg & Nayar Figure 9), by inverting the drop's refraction mapping (drop/undistort.hpp).
#include <fmt/format.h>

#include <array>
#include <cmath>
#include <memory>
#include <optional>
#include <string>

#include "common.hpp"
#include "hydrolux/core/error.hpp"
#include "hydrolux/drop/undistort.hpp"
#include "hydrolux/core/parse.hpp"

namespace hydrolux::cli {

namespace {

struct UndistortArgs {
  std::string image;
  std::string drop_center;
  double drop_radius_px = 0;
  double fov_deg = 60;
  double yaw_deg = 0;
  double pitch_deg = 0;
  double mu = 1.333;
  std::string size;
  std::optional<int> width, height;
  bool no_transmission_correction = false;
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

  drop::UndistortView view;
  view.yaw_deg = a.yaw_deg;
  view.pitch_deg = a.pitch_deg;
  view.fov_deg = a.fov_deg;
  if (!a.size.empty()) {
    const auto wh = parse_size(a.size);
    if (!wh) throw Error(fmt::format("--size '{}': expected WxH", a.size));
    view.width = (*wh)[0];
    view.height = (*wh)[1];
  } else if (a.width || a.height) {
    // One side given: the other follows at the default square aspect.
    view.width = a.width ? *a.width : *a.height;
    view.height = a.height ? *a.height : *a.width;
  }
  drop::validate(view);

  const Image drop_image = read_input_image("--image", a.image);
  const Image out = drop::undistort(drop_image, (*centre)[0], (*centre)[1], a.drop_radius_px, a.mu, view,
                                    !a.no_transmission_correction);
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
  auto* sub = drop.add_subcommand(
      "undistort",
      "Undo a rain drop's distortion (Garg & Nayar Figure 9): the drop refracts a ~165 degree, inverted "
      "view of the world into its image; inverting the refraction mapping gives the perspective view of a "
      "pinhole camera at the drop. The drop is taken as a sphere seen head-on. Near the drop's rim the "
      "view is packed ever tighter, so the result is sharp near the centre of the field only. Output RGBA: "
      "alpha 0 where a direction lies outside the drop's field of view or its image point outside the "
      "input image.");
  sub->add_option("--image", args->image, "Image containing the drop (PNG/JPEG/TIFF as sRGB, EXR as linear)")
      ->required();
  sub->add_option("--drop-center", args->drop_center,
                  "The drop's image centre X,Y in pixels (x right, y down, pixel centres at half-integers)")
      ->required()
      ->check(drop_center_validator());
  sub->add_option("--drop-radius-px", args->drop_radius_px, "The drop's radius on the image in pixels")
      ->required()
      ->check(positive_number(1e6, "px"));
  sub->add_option("--fov-deg", args->fov_deg, "Horizontal field of view of the perspective view")
      ->check(positive_number(179, "deg"))
      ->capture_default_str();
  sub->add_option("--yaw-deg", args->yaw_deg, "View direction turned about the vertical, positive to the right")
      ->check(number_in(-360, 360, "deg"))
      ->capture_default_str();
  sub->add_option("--pitch-deg", args->pitch_deg, "View direction tilted, positive up")
      ->check(number_in(-90, 90, "deg"))
      ->capture_default_str();
  sub->add_option("--mu", args->mu, "Refractive index of the drop relative to the air")
      ->check(number_in(1.0001, 10))
      ->capture_default_str();
  auto* size_opt = sub->add_option("--size", args->size, "Output size WxH in pixels [default: 512x512]")
                       ->check(size_validator());
  auto* width_opt = sub->add_option("--width", args->width, "Output width in pixels (height = width if not given)")
                        ->transform(integer_in(1, 16384, "px"));
  auto* height_opt =
      sub->add_option("--height", args->height, "Output height in pixels (width = height if not given)")
          ->transform(integer_in(1, 16384, "px"));
  size_opt->excludes(width_opt)->excludes(height_opt);
  sub->add_flag("--no-transmission-correction", args->no_transmission_correction,
                "Keep the drop's brightness: do not divide by the refraction transmission (1 - k)^2");
  sub->add_option("-o,--output", args->output, "Output image (.exr linear float RGBA, or .png sRGB RGBA)")
      ->required();
  sub->add_flag("-q,--quiet", args->quiet, "No summary on stderr");
  return {sub,
          [args] { return run_undistort(*args); },
          {{"mu", "--mu"},
           {"radius_px", "--drop-radius-px"},
           {"fov_deg", "--fov-deg"},
           {"yaw_deg", "--yaw-deg"},
           {"pitch_deg", "--pitch-deg"},
           {"width", "--width/--size"},
           {"height", "--height/--size"},
           {"center_x_px", "--drop-center"},
           {"center_y_px", "--drop-center"},
           {"image_width", "--image"},
           {"image_height", "--image"},
           {"image_channels", "--image"}}};
}

}  // namespace hydrolux::cli
