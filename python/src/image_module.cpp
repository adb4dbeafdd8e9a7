// hydrolux._image: image files through the library's codecs (OpenImageIO behind hydrolux's own
// checks) and its safe output path. A module of its own so that `import hydrolux` does not load
// OpenImageIO's ~260 libraries; hydrolux imports it on first use.
#include <fmt/format.h>
#include <pybind11/stl.h>

#include <string>

#include "common.hpp"
#include "hydrolux/io/files.hpp"
#include "hydrolux/io/image_io.hpp"
#include "hydrolux/rain/params.hpp"

namespace hydrolux::py_bind {
namespace {

io::ImageFormat format_arg(const std::string& name) {
  if (name == "png") return io::ImageFormat::png;
  if (name == "exr") return io::ImageFormat::exr;
  throw UnknownNameError(fmt::format("format '{}': images are written as png or exr", name));
}

std::string short_name(io::ImageFormat f) {
  switch (f) {
    case io::ImageFormat::png: return "png";
    case io::ImageFormat::exr: return "exr";
    case io::ImageFormat::hdr: return "hdr";
    case io::ImageFormat::pnm: return "pnm";
    case io::ImageFormat::jpeg: return "jpeg";
    case io::ImageFormat::tiff: return "tiff";
  }
  return "?";
}

py::tuple read_image(const std::string& path) {
  std::string bytes;
  io::DecodedImage d;
  {
    py::gil_scoped_release release;
    bytes = io::read_file(path, io::ImageLimits{}.max_file_bytes, "path");
    d = io::decode_image(bytes, path);
  }
  return py::make_tuple(to_array(d.image), short_name(d.format), d.warnings, d.linear);
}

// A depth map for a width x height frame (io::depth_from_decoded), as hydrolux rain reads --depth.
py::array_t<float> read_depth(const std::string& path, double scale_m, int width, int height, const std::string& label) {
  rain::rain_param("depth_scale_m").check(scale_m);  // the declared range (rain/params.cpp)
  Image depth;
  {
    py::gil_scoped_release release;
    const std::string bytes = io::read_file(path, io::ImageLimits{}.max_file_bytes, label);
    const std::string origin = fmt::format("{} {}", label, path);
    if (io::sniff_image_format(bytes) == io::ImageFormat::jpeg) throw Error(origin + io::kJpegDepthRefusal);
    depth = io::depth_from_decoded(io::decode_image(bytes, origin), scale_m, width, height, origin);
  }
  return to_array(depth);
}

// The bytes of a PNG or EXR (a coverage mask through io::coverage_for_encoding), as the CLI writes them.
std::string encode_bytes(const py::array& image, io::ImageFormat f, py::handle bits_arg, bool coverage,
                         py::handle compression_arg = py::none(), bool linear = false) {
  const int bits = int(whole_arg(bits_arg, "bits", 8, 16));
  const int compression = compression_arg.is_none()
                              ? io::kDefaultPngCompression
                              : int(whole_arg(compression_arg, "compression", 0, io::kMaxPngCompression));
  if (bits != 8 && bits != 16) throw Error(fmt::format("bits: {} is not 8 or 16 (PNG's sample sizes)", bits));
  Image img = to_image(image, "image");
  if (linear && img.channels != 1 && img.channels != 3)
    throw Error(fmt::format("linear: data is written with 1 or 3 channels, not {} (a PNG's alpha channel is read "
                            "back associated with the others)",
                            img.channels));
  img.non_colour = linear;
  if (coverage && img.channels != 1) throw Error("coverage: a coverage mask has one channel");
  py::gil_scoped_release release;
  if (coverage) img = io::coverage_for_encoding(img, f);
  return io::encode_image(img, f, io::PngOptions{bits, compression});
}

// `compression`: the PNG's zlib level (None: the CLI's default, io::kDefaultPngCompression).
py::bytes encode(const py::array& image, const std::string& format, py::handle bits, bool coverage,
                 py::handle compression) {
  return py::bytes(encode_bytes(image, format_arg(format), bits, coverage, compression));
}

// `linear`: the values are data, not colour (Image::non_colour): a PNG holds them linearly.
void write_image(const std::string& path, const py::array& image, py::handle bits, py::handle linear_arg) {
  const bool linear = flag_arg(linear_arg, "linear");
  const std::string bytes = encode_bytes(image, io::output_image_format(path, "path"), bits, false, py::none(), linear);
  py::gil_scoped_release release;
  io::write_file(path, bytes, "path");
}

}  // namespace
}  // namespace hydrolux::py_bind

PYBIND11_MODULE(_image, m) {
  using namespace hydrolux::py_bind;
  register_errors();
  m.doc() = "hydrolux's image files (use hydrolux.read_image / write_image)";
  m.def("read", &read_image, py::arg("path"));
  m.def("read_depth", &read_depth, py::arg("path"), py::arg("scale_m"), py::arg("width"), py::arg("height"),
        py::arg("label"));
  m.def("encode", &encode, py::arg("image"), py::arg("format"), py::arg("bits"), py::arg("coverage"),
        py::arg("compression") = py::none());
  m.def("write", &write_image, py::arg("path"), py::arg("image"), py::arg("bits"), py::arg("linear") = false);
}
