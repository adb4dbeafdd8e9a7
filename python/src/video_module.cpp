// hydrolux._video: video files through the same FFmpeg code as `hydrolux rain --video`
// (hydrolux/io/video.hpp, the object library hydrolux_video linked in), read and written through hydrolux's checked inputs and atomic outputs,
// with the CLI's 8-bit sRGB tables. A module of its own, imported only by the code that needs video.
#include <fmt/format.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <memory>
#include <string>

#include "common.hpp"
#include "hydrolux/color/srgb.hpp"
#include "hydrolux/io/files.hpp"
#include "hydrolux/io/video.hpp"

namespace hydrolux::py_bind {
namespace {

const io::VideoApi& api() { return *hydrolux_video_api_v1(); }
const color::Srgb8Tables& tables() {
  static const color::Srgb8Tables t;
  return t;
}

class PyVideoReader {
 public:
  PyVideoReader(const std::string& path, const std::string& label) : input_(path, label) {
    py::gil_scoped_release release;
    reader_ = api().open_reader(
        [this](std::uint64_t off, char* buf, std::size_t n) { return input_.read_at(off, buf, n); }, input_.size(),
        fmt::format("{} {}", label, path), io::VideoLimits{});
  }

  py::dict info() const {
    const auto& i = reader_->info();
    py::dict d;
    d["width"] = i.width, d["height"] = i.height, d["fps_num"] = i.fps_num, d["fps_den"] = i.fps_den;
    d["fps"] = i.fps(), d["frame_count"] = i.frame_count, d["duration_s"] = i.duration_s, d["codec"] = i.codec;
    return d;
  }

  // The next frame as linear float32 (H, W, 3) through the CLI's tables; None after the last.
  py::object read() {
    bool got;
    {
      py::gil_scoped_release release;
      got = reader_->read(frame_);
    }
    if (!got) return py::none();
    py::array_t<float> out({py::ssize_t(frame_.height), py::ssize_t(frame_.width), py::ssize_t(3)});
    tables().to_linear(frame_.rgb.data(), std::size_t(frame_.width) * frame_.height, out.mutable_data());
    return out;
  }

  // Decodes and drops up to n frames; returns how many there were.
  long long skip(long long n) {
    py::gil_scoped_release release;
    long long k = 0;
    while (k < n && reader_->read(frame_)) ++k;
    return k;
  }

 private:
  io::InputFile input_;
  std::unique_ptr<io::VideoReader> reader_;
  io::VideoFrame frame_;
};

class PyVideoWriter {
 public:
  PyVideoWriter(const std::string& path, const py::dict& info, int crf, const std::string& label)
      : out_(path, label) {
    std::string ext = std::filesystem::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    if (std::find(std::begin(io::kVideoExtensions), std::end(io::kVideoExtensions), ext) ==
        std::end(io::kVideoExtensions))
      throw Error(fmt::format("{} {}: expected a .mp4, .mov or .mkv file", label, path));
    io::VideoInfo i;
    i.width = info["width"].cast<int>(), i.height = info["height"].cast<int>();
    i.fps_num = info["fps_num"].cast<int>(), i.fps_den = info["fps_den"].cast<int>();
    i.frame_count = info["frame_count"].cast<std::int64_t>(), i.duration_s = info["duration_s"].cast<double>();
    i.codec = info["codec"].cast<std::string>();
    writer_ = api().open_writer([this](std::uint64_t off, std::string_view bytes) { out_.write_at(off, bytes); }, ext,
                                i, crf, fmt::format("{} {}", label, path));
    frame_.width = i.width, frame_.height = i.height;
  }

  // A frame as 8-bit sRGB (H, W, 3) uint8, or linear floats (H, W, >= 3) encoded by the CLI's tables.
  void write(const py::array& image) {
    if (image.ndim() != 3 || image.shape(2) < 3 || image.shape(0) != frame_.height || image.shape(1) != frame_.width)
      throw Error(fmt::format("frame: expected ({}, {}, 3), got another shape", frame_.height, frame_.width));
    const std::size_t pixels = std::size_t(frame_.width) * frame_.height;
    frame_.rgb.resize(pixels * 3);
    if (image.dtype().is(py::dtype::of<std::uint8_t>())) {
      const auto a = c_array<std::uint8_t>(image, "frame");
      if (a.shape(2) != 3) throw Error("frame: an 8-bit frame has 3 channels");
      std::copy(a.data(), a.data() + pixels * 3, frame_.rgb.begin());
    } else {
      const auto a = c_array<float>(image, "frame");
      tables().to_srgb8(a.data(), pixels, int(a.shape(2)), frame_.rgb.data());
    }
    py::gil_scoped_release release;
    writer_->write(frame_);
  }

  // Flushes the encoder and puts the file in place: nothing exists before.
  void finish() {
    py::gil_scoped_release release;
    writer_->finish();
    out_.commit();
  }

 private:
  io::OutputFile out_;
  std::unique_ptr<io::VideoWriter> writer_;
  io::VideoFrame frame_;
};

// Linear float frames (H, W, >= 3) as the 8-bit sRGB bytes the video encoder is given.
py::array_t<std::uint8_t> to_srgb8(const py::array& image) {
  if (image.ndim() != 3 || image.shape(2) < 3) throw Error("image: expected (height, width, 3 or more channels)");
  const auto a = c_array<float>(image, "image");
  py::array_t<std::uint8_t> out({a.shape(0), a.shape(1), py::ssize_t(3)});
  tables().to_srgb8(a.data(), std::size_t(a.shape(0) * a.shape(1)), int(a.shape(2)), out.mutable_data());
  return out;
}

}  // namespace
}  // namespace hydrolux::py_bind

PYBIND11_MODULE(_video, m) {
  using namespace hydrolux::py_bind;
  register_errors();
  m.doc() = "hydrolux's video files (FFmpeg, as hydrolux rain --video)";
  py::class_<PyVideoReader>(m, "VideoReader")
      .def(py::init<const std::string&, const std::string&>(), py::arg("path"), py::arg("label") = "--video")
      .def("info", &PyVideoReader::info)
      .def("read", &PyVideoReader::read)
      .def("skip", &PyVideoReader::skip, py::arg("frames"));
  py::class_<PyVideoWriter>(m, "VideoWriter")
      .def(py::init<const std::string&, const py::dict&, int, const std::string&>(), py::arg("path"),
           py::arg("info"), py::arg("crf") = 18, py::arg("label") = "-o")
      .def("write", &PyVideoWriter::write, py::arg("frame"))
      .def("finish", &PyVideoWriter::finish);
  m.def("to_srgb8", &to_srgb8, py::arg("image"));
}
