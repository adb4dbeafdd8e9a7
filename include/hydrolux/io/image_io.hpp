#pragma once
// Image files through OpenImageIO, in memory: the bytes are read and written by io/files.hpp (only
// regular files, atomic checked writes), and OpenImageIO only encodes and decodes.
//
// Written: .exr linear float (scene-referred), 32-bit float, zip-compressed; .png display-referred,
// the sRGB curve applied and quantised to 8 or 16 bits, with the sRGB chunk; data that is not colour
// (Image::non_colour: coverage masks) quantised linearly, with gAMA 1.0 and no sRGB chunk. Both are deterministic: the same image gives
// the same bytes (no time stamp: OpenImageIO's EXR DateTime/capDate is written empty).
// Read: PNG, OpenEXR, Radiance HDR, PNM (PBM/PGM/PPM/PFM), JPEG and TIFF, told apart by their first
// bytes (never by probing every reader). EXR, HDR and PFM are linear, and so is a PNG that declares
// it (gAMA 1.0 and no sRGB or iCCP chunk: what hydrolux writes for masks), read as code / max; other
// 8- and 16-bit files are taken as sRGB-encoded and decoded to linear (alpha stays linear), through a
// table of every code holding color::srgb_decode of the code's value (the same floats as the curve,
// without a pow each). DecodedImage::linear says which.
//
// A header is never trusted: width x height x channels is checked against ImageLimits, and for
// the formats whose compression has a known maximum ratio (PNG, PNM, HDR, JPEG) against the size
// of the file, before any pixel memory is allocated. Messages the codec libraries print on stderr
// (libpng's "libpng error: ...") are captured during decoding: they become part of the one-line
// error, or a warning returned with the image.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "hydrolux/core/image.hpp"
#include "hydrolux/io/files.hpp"

namespace hydrolux::io {

enum class ImageFormat { png, exr, hdr, pnm, jpeg, tiff };

std::string_view format_name(ImageFormat f);

// zlib's level for PNG files: 0 stores the rows uncompressed, 1 is the fastest compression, 9 the
// smallest file; every level decodes to the same pixels. Levels 1 and 2 also filter every row with
// libpng's Up filter instead of trying all five on each row (which costs as much as the deflate at
// level 1); level 0 leaves rows unfiltered; 3-9 keep libpng's adaptive filtering, and 6 (zlib's
// default) writes the bytes hydrolux wrote before the level was an option. The default, 1, is the
// fastest that compresses: BENCHMARKS.md ("Rain over a folder of frames, end to end") has its time
// and size against the others on 1920 x 1080 frames.
inline constexpr int kDefaultPngCompression = 1;
inline constexpr int kMaxPngCompression = 9;

struct PngOptions {
  int bits = 8;  // 8 or 16
  int compression = kDefaultPngCompression;  // libdeflate's level, 0 .. kMaxPngCompression
};

// What a decoded image may claim. The defaults take a 16384 x 16384 RGBA image (4 GiB as float),
// about the largest a 24 GiB machine decodes comfortably with OpenImageIO's own buffers.
struct ImageLimits {
  std::int64_t max_side = 65536;                    // width or height, pixels
  std::int64_t max_pixels = std::int64_t(1) << 28;  // width x height: 268 million
  std::int64_t max_values = std::int64_t(1) << 30;  // width x height x channels: 4 GiB as float
  int max_channels = 16;
  // A progressive JPEG is decoded scan by scan over the whole image; encoders write about 10
  // (libjpeg's default progression) to 20 (mozjpeg); a small file with thousands is a time bomb.
  int max_jpeg_scans = 100;
  std::uint64_t max_file_bytes = kMaxInputBytes;
  // Called with the header's width, height and channels once they are within the limits above and
  // before any pixel is allocated; it may throw (a job refusing a frame its memory cannot hold).
  std::function<void(std::int64_t width, std::int64_t height, std::int64_t channels)> before_pixels;
};

struct DecodedImage {
  Image image;
  ImageFormat format = ImageFormat::png;
  std::vector<std::string> warnings;  // what the codec said on a successful decode, one line each
  // The file's channel names in the image's channel order (OpenEXR's, e.g. "Q.X"; the others' as the
  // codec names them). Kept here, not on the image, so a caller's new image never inherits them.
  std::vector<std::string> channel_names;
  // The file holds linear values: a float format (EXR, HDR, PFM, float TIFF) or a PNG that declares
  // linear codes (gAMA 1.0, no sRGB chunk), decoded without the sRGB curve. False: the codes were
  // decoded through the sRGB curve.
  bool linear = false;
};

// An image coder passed in by a caller that loads the codecs itself (the CLI's image plugin keeps
// OpenImageIO out of commands that do not read or write images): decode_image and encode_image.
struct ImageCodec {
  DecodedImage (*decode)(std::string_view bytes, std::string_view origin, const ImageLimits& limits) = nullptr;
  std::string (*encode)(const Image& image, ImageFormat format, PngOptions png) = nullptr;
};

// An image file given as `label` (a flag), read whole through the checked path (files.hpp) and
// decoded by `codec`; each warning of the codec goes to `warn` as "<label> <path>: <warning>".
DecodedImage read_decoded(const ImageCodec& codec, std::string_view label, const std::filesystem::path& path,
                          const std::function<void(const std::string&)>& warn);

// The format from the first bytes: PNG, EXR, Radiance HDR (#?RADIANCE / #?RGBE), PNM (P1-P6,
// Pf/PF), JPEG, TIFF; nullopt otherwise.
std::optional<ImageFormat> sniff_image_format(std::string_view bytes);

// Decodes an image held in memory. `origin` names it in errors. Throws IoError for an unknown
// format, a header claiming more than `limits` or more than the bytes can hold, or malformed or
// truncated data; the message is one line.
DecodedImage decode_image(std::string_view bytes, std::string_view origin, const ImageLimits& limits = {});

// The smallest number of bytes a file of this format can encode width x height x channels values
// of `bits` bits in (0 where the format's compression has no useful bound: EXR, TIFF). `pnm_magic`
// is the PNM sub-format ('1'..'6', 'f', 'F').
std::uint64_t min_encoded_bytes(ImageFormat f, std::int64_t width, std::int64_t height, int channels, int bits,
                                char pnm_magic = '6');

// A file's structure walked without its codec, before the codec sees the file: an empty string if
// it is whole and its header within `limits`, else why not ("the file ends inside the IDAT chunk").
// The codecs trust what these check, so a hostile file is refused here in one line:
// - PNG: the chunks (length, type, data, CRC) up to IEND; IHDR's size within the limits, and the
//   IDAT chunks large enough for it at deflate's best ratio (1032:1), from the stored bit depth and
//   colour type (a 1-bit or palette image is 8-24 times smaller than its decoded RGB).
// - OpenEXR: the header (magic, version and flags, each part's attributes as name, type, size,
//   value). OpenEXR 3.1 sizes a string attribute by its declared length (1.8 GB for a 1 kB file,
//   found by fuzz_image) and seeks through its chunk offset table: every attribute must fit in the
//   file, each part's data window be within the limits, the offset table of the chunks it needs fit
//   in the file and each offset point inside it. Deep (non-image) files are refused.
// - JPEG: the marker segments and entropy-coded scans up to EOI (a truncated file is refused, not
//   decoded grey), the frame size within the limits and, for Huffman coding, the file large enough
//   for one bit a block; at most max_jpeg_scans scans (a progressive JPEG is decoded while it is
//   opened). DNL-defined heights and arithmetic coding (no bytes-a-block bound) are refused.
// - TIFF (and BigTIFF): the first image directory (a repeated tag counts once, as in libtiff), its
//   values inside the file; size, samples and bits within the limits; tiles multiples of 16 and no
//   larger in area than the image or 512 x 512; every strip or tile the image needs inside the
//   file (a truncated TIFF is refused), together no more than the file, and enough bytes for the
//   image at its compression's best ratio.
// - OpenEXR tiles are bounded the same way, and its offset table counted over every mipmap or
//   ripmap level; a multipart file's chunkCount must agree with each part's window.
// - Radiance HDR and PNM have no structure to walk: their bound against the file size is checked
//   from the codec's header (min_encoded_bytes).
std::string image_structure_problem(ImageFormat format, std::string_view bytes, const ImageLimits& limits);
std::string png_structure_problem(std::string_view bytes, const ImageLimits& limits);
std::string exr_header_problem(std::string_view bytes, const ImageLimits& limits);
std::string jpeg_structure_problem(std::string_view bytes, const ImageLimits& limits);
std::string tiff_structure_problem(std::string_view bytes, const ImageLimits& limits);

// A JPEG that passed jpeg_structure_problem, without its metadata segments (APP1-APP13, APP15:
// Exif, XMP, ICC, IPTC; and COM), which hydrolux does not use. OpenImageIO 2.4 parses them while
// opening a file, and fuzz_image found it reading past a saved marker there (a heap overflow in
// JpgInput::open); what it never sees it cannot misread. APP0 (JFIF) and APP14 (Adobe), which
// change how the pixels decode, are kept.
std::string jpeg_without_metadata(std::string_view bytes);

// A coverage mask (1 channel, alpha in [0, 1]) as hydrolux writes it: EXR linear, channel "Y"; PNG
// with linear codes alpha x 65535 (Image::non_colour: gAMA 1.0 and no sRGB chunk, so that every
// reader, hydrolux's own too, reads back alpha within half a code). Encode the result with
// PngOptions{16} for PNG.
Image coverage_for_encoding(const Image& alpha, ImageFormat format);

// A depth map as camera z in metres for a width x height frame (hydrolux rain --depth, the Python
// batch's --depth-dir): an EXR (or another linear format) holds metres in its first channel; a PNG,
// TIFF or PNM holds 16-bit codes times `scale_m` (the decoder hands them over as code / max for a
// PNG that declares linear codes, else through the sRGB curve, which round-trips to well under half
// a code; an 8-bit file's codes are multiples of 257),
// code 0 meaning no geometry (infinity). Another resolution with the frame's aspect is sampled at the
// nearest pixel. Error naming `origin` for another aspect, a map smaller than 1/kMinDepthMapFraction
// of the frame a side, or a JPEG (lossy codes are not depths).
inline constexpr int kMinDepthMapFraction = 16;
Image depth_from_decoded(const DecodedImage& decoded, double scale_m, int width, int height, std::string_view origin);
inline constexpr const char* kJpegDepthRefusal = ": a JPEG cannot hold depth faithfully; give a 16-bit PNG or an EXR";

// The 8-bit sRGB code of a linear value by table, the same code as
// std::lround(color::srgb_encode(double(linear)) * 255) for every float (0 for NaN and values <= 0,
// 255 for values >= 1): what encode_image writes into an 8-bit PNG's colour channels.
std::uint8_t srgb8_code(float linear) noexcept;
// `n` linear values to 8-bit sRGB codes (srgb8_code each).
void srgb8_codes(const float* linear, std::size_t n, std::uint8_t* codes) noexcept;

// Encodes to PNG or EXR bytes (IoError for other formats, an inconsistent image or a PNG
// compression level outside 0 .. kMaxPngCompression).
std::string encode_image(const Image& image, ImageFormat format, PngOptions png = {});

// The format an output file name asks for: .png or .exr (any case). Throws IoError naming
// `label` and the path otherwise.
ImageFormat output_image_format(const std::filesystem::path& path, std::string_view label = {});

// read_file + decode_image; warnings are dropped (use decode_image to see them).
Image read_image(const std::filesystem::path& path, const ImageLimits& limits = {}, std::string_view label = {});

// encode_image + write_file: checked and atomic (files.hpp).
void write_image(const std::filesystem::path& path, const Image& image, PngOptions png = {});

}  // namespace hydrolux::io
