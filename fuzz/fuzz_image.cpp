// libFuzzer target: image decoding through hydrolux's read path (io::decode_image): format sniffing,
// the header checks against limits and the file size, OpenImageIO's codecs reading from memory.
// Small limits keep a run within the fuzzer's memory budget; an accepted image must honour them.
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "hydrolux/core/error.hpp"
#include "hydrolux/io/image_io.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace hydrolux;
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  io::ImageLimits limits;
  limits.max_side = 8192;
  limits.max_pixels = std::int64_t(1) << 21;
  limits.max_values = std::int64_t(1) << 22;
  limits.max_channels = 8;
  try {
    const auto decoded = io::decode_image(bytes, "fuzz", limits);
    const Image& img = decoded.image;
    if (img.width <= 0 || img.height <= 0 || img.channels <= 0 || img.width > limits.max_side ||
        img.height > limits.max_side || std::int64_t(img.width) * img.height > limits.max_pixels ||
        img.pixels.size() != std::size_t(img.width) * std::size_t(img.height) * std::size_t(img.channels))
      std::abort();  // an image outside the limits, or of inconsistent size, got through
  } catch (const Error&) {
    // IoError: refused with a message. Anything else (bad_alloc, a crash) is a finding.
  }
  return 0;
}
