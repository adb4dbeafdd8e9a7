#include "io/png_codec.hpp"

#include <libdeflate.h>

#include <algorithm>
#include <array>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <stdexcept>

namespace hydrolux::io::png {

namespace {

// The PNG specification (W3C, 2003; third edition 2025): the signature, the chunk types used here,
// the five filter types.
constexpr std::string_view kSignature = "\x89PNG\r\n\x1a\n";
enum Filter : std::uint8_t { kNone = 0, kSub = 1, kUp = 2, kAverage = 3, kPaeth = 4 };
constexpr std::size_t kIdatBytes = std::size_t(1) << 20;  // image data split into chunks of 1 MiB
constexpr std::uint32_t kLinearGama = 100000;              // gAMA's value of gamma 1.0 (linear codes)

std::uint32_t be32(std::string_view b, std::size_t at) {
  return std::uint32_t(static_cast<unsigned char>(b[at])) << 24 | std::uint32_t(static_cast<unsigned char>(b[at + 1])) << 16 |
         std::uint32_t(static_cast<unsigned char>(b[at + 2])) << 8 | std::uint32_t(static_cast<unsigned char>(b[at + 3]));
}

void put32(std::string& out, std::uint32_t v) {
  const char bytes[4] = {char(v >> 24), char(v >> 16), char(v >> 8), char(v)};
  out.append(bytes, 4);
}

void put_chunk(std::string& out, const char (&type)[5], const void* data, std::size_t size) {
  put32(out, std::uint32_t(size));
  const std::size_t start = out.size();
  out.append(type, 4);
  if (size > 0) out.append(static_cast<const char*>(data), size);
  put32(out, libdeflate_crc32(0, out.data() + start, size + 4));
}

std::uint8_t paeth(int a, int b, int c) {  // left, up, upper left
  const int p = a + b - c, pa = std::abs(p - a), pb = std::abs(p - b), pc = std::abs(p - c);
  return std::uint8_t(pa <= pb && pa <= pc ? a : pb <= pc ? b : c);
}

// One row filtered with `type` into out (n bytes; prev is the row above, zeros for the first).
void filter_row(Filter type, const std::uint8_t* row, const std::uint8_t* prev, std::size_t n, std::size_t bpp,
                std::uint8_t* out) {
  switch (type) {
    case kNone: std::memcpy(out, row, n); break;
    case kSub:
      for (std::size_t i = 0; i < n; ++i) out[i] = std::uint8_t(row[i] - (i >= bpp ? row[i - bpp] : 0));
      break;
    case kUp:
      for (std::size_t i = 0; i < n; ++i) out[i] = std::uint8_t(row[i] - prev[i]);
      break;
    case kAverage:
      for (std::size_t i = 0; i < n; ++i) out[i] = std::uint8_t(row[i] - ((i >= bpp ? row[i - bpp] : 0) + prev[i]) / 2);
      break;
    case kPaeth:
      for (std::size_t i = 0; i < n; ++i)
        out[i] = std::uint8_t(row[i] - (i >= bpp ? paeth(row[i - bpp], prev[i], prev[i - bpp]) : prev[i]));
      break;
  }
}

// The row back from its filtered bytes, in place (row holds the filtered bytes on entry).
bool unfilter_row(std::uint8_t type, std::uint8_t* row, const std::uint8_t* prev, std::size_t n, std::size_t bpp) {
  switch (type) {
    case kNone: return true;
    case kSub:
      for (std::size_t i = bpp; i < n; ++i) row[i] = std::uint8_t(row[i] + row[i - bpp]);
      return true;
    case kUp:
      for (std::size_t i = 0; i < n; ++i) row[i] = std::uint8_t(row[i] + prev[i]);
      return true;
    case kAverage:
      for (std::size_t i = 0; i < bpp; ++i) row[i] = std::uint8_t(row[i] + prev[i] / 2);
      for (std::size_t i = bpp; i < n; ++i) row[i] = std::uint8_t(row[i] + (row[i - bpp] + prev[i]) / 2);
      return true;
    case kPaeth:
      for (std::size_t i = 0; i < bpp; ++i) row[i] = std::uint8_t(row[i] + prev[i]);
      for (std::size_t i = bpp; i < n; ++i) row[i] = std::uint8_t(row[i] + paeth(row[i - bpp], prev[i], prev[i - bpp]));
      return true;
    default: return false;
  }
}

// The PNG specification's heuristic for choosing a row's filter: the least sum of the filtered
// bytes taken as signed.
std::uint64_t signed_sum(const std::uint8_t* b, std::size_t n) {
  std::uint64_t s = 0;
  for (std::size_t i = 0; i < n; ++i) s += std::uint64_t(std::abs(int(static_cast<std::int8_t>(b[i]))));
  return s;
}

struct CompressorDeleter {
  void operator()(libdeflate_compressor* c) const { libdeflate_free_compressor(c); }
};
struct DecompressorDeleter {
  void operator()(libdeflate_decompressor* d) const { libdeflate_free_decompressor(d); }
};

}  // namespace

std::string encode(const std::uint8_t* samples, int width, int height, int channels, int bits, int level,
                   bool linear) {
  if (width <= 0 || height <= 0 || channels < 1 || channels > 4 || (bits != 8 && bits != 16) || level < 0 || level > 12)
    throw std::invalid_argument("png::encode: bad dimensions, bit depth or level");
  static constexpr std::uint8_t kColourType[] = {0, 0, 4, 2, 6};  // by channels: grey, grey+alpha, RGB, RGBA
  const std::size_t bpp = std::size_t(channels) * std::size_t(bits / 8);
  const std::size_t row = bpp * std::size_t(width), h = std::size_t(height);

  // Each row with its filter byte in front, as the deflate stream carries it.
  std::vector<std::uint8_t> filtered(h * (row + 1));
  const std::vector<std::uint8_t> zeros(row, 0);
  std::vector<std::uint8_t> trial(level >= 3 ? row : 0);
  for (std::size_t y = 0; y < h; ++y) {
    const std::uint8_t* cur = samples + y * row;
    const std::uint8_t* prev = y > 0 ? cur - row : zeros.data();
    std::uint8_t* out = filtered.data() + y * (row + 1);
    Filter chosen = level == 0 ? kNone : kUp;
    if (level >= 3) {
      std::uint64_t best = ~std::uint64_t(0);
      for (const Filter f : {kNone, kSub, kUp, kAverage, kPaeth}) {
        filter_row(f, cur, prev, row, bpp, trial.data());
        if (const std::uint64_t s = signed_sum(trial.data(), row); s < best) best = s, chosen = f;
      }
    }
    out[0] = chosen;
    filter_row(chosen, cur, prev, row, bpp, out + 1);
  }

  const std::unique_ptr<libdeflate_compressor, CompressorDeleter> compressor(libdeflate_alloc_compressor(level));
  if (!compressor) throw std::bad_alloc();
  std::vector<std::uint8_t> z(libdeflate_zlib_compress_bound(compressor.get(), filtered.size()));
  const std::size_t z_bytes =
      libdeflate_zlib_compress(compressor.get(), filtered.data(), filtered.size(), z.data(), z.size());
  if (z_bytes == 0) throw std::runtime_error("png::encode: the compressed data did not fit its bound");

  std::string file;
  file.reserve(z_bytes + z_bytes / kIdatBytes * 12 + 200);
  file.append(kSignature);
  std::string ihdr;
  put32(ihdr, std::uint32_t(width));
  put32(ihdr, std::uint32_t(height));
  ihdr += char(bits);
  ihdr += char(kColourType[channels]);
  ihdr.append(3, '\0');  // deflate, the adaptive filter method, no interlace
  put_chunk(file, "IHDR", ihdr.data(), ihdr.size());
  if (linear) {
    // Linear codes (data, not colour): a gamma of 1.0 alone, as the specification says it.
    std::string gama;
    put32(gama, kLinearGama);
    put_chunk(file, "gAMA", gama.data(), gama.size());
  } else {
    // sRGB (perceptual intent) with the gAMA and cHRM values the specification gives for it, for
    // readers that know only those.
    const char intent = 0;
    put_chunk(file, "sRGB", &intent, 1);
    std::string gama;
    put32(gama, 45455);
    put_chunk(file, "gAMA", gama.data(), gama.size());
    std::string chrm;
    for (const std::uint32_t v : {31270u, 32900u, 64000u, 33000u, 30000u, 60000u, 15000u, 6000u}) put32(chrm, v);
    put_chunk(file, "cHRM", chrm.data(), chrm.size());
  }
  for (std::size_t at = 0; at < z_bytes; at += kIdatBytes)
    put_chunk(file, "IDAT", z.data() + at, std::min(kIdatBytes, z_bytes - at));
  put_chunk(file, "IEND", nullptr, 0);
  return file;
}

bool declares_linear(std::string_view file) {
  if (file.size() < kSignature.size() || file.substr(0, kSignature.size()) != kSignature) return false;
  bool gamma_one = false;
  for (std::size_t pos = kSignature.size(); pos + 12 <= file.size();) {
    const std::uint32_t length = be32(file, pos);
    if (file.size() - pos - 12 < length) return false;
    const std::string_view type = file.substr(pos + 4, 4);
    if (type == "IDAT" || type == "IEND") break;  // the colour chunks come before the image data
    if (type == "sRGB" || type == "iCCP") return false;
    if (type == "gAMA") gamma_one = length == 4 && be32(file, pos + 8) == kLinearGama;
    pos += 12 + std::size_t(length);
  }
  return gamma_one;
}

std::optional<Header> plain_header(std::string_view file) {
  if (file.size() < kSignature.size() + 25 || file.substr(0, kSignature.size()) != kSignature) return std::nullopt;
  std::size_t pos = kSignature.size();
  if (be32(file, pos) != 13 || file.substr(pos + 4, 4) != "IHDR") return std::nullopt;
  const auto byte = [&](std::size_t at) { return static_cast<unsigned char>(file[pos + 8 + at]); };
  Header h;
  h.width = int(std::min<std::uint32_t>(be32(file, pos + 8), 0x7fffffffu));
  h.height = int(std::min<std::uint32_t>(be32(file, pos + 12), 0x7fffffffu));
  h.bits = byte(8);
  const int colour = byte(9);
  if ((h.bits != 8 && h.bits != 16) || (colour != 0 && colour != 2) || byte(10) != 0 || byte(11) != 0 || byte(12) != 0)
    return std::nullopt;
  h.channels = colour == 2 ? 3 : 1;
  h.linear = declares_linear(file);
  // Transparency (tRNS) would add an alpha channel, a palette is only a suggestion here but rare:
  // both to the general reader.
  for (pos += 25; pos + 8 <= file.size();) {
    const std::uint32_t length = be32(file, pos);
    const std::string_view type = file.substr(pos + 4, 4);
    if (type == "tRNS" || type == "PLTE") return std::nullopt;
    if (type == "IEND") break;
    pos += 12 + std::size_t(length);
  }
  return h;
}

bool read_samples(std::string_view file, const Header& h, std::vector<std::uint8_t>& samples) {
  const std::size_t bpp = std::size_t(h.channels) * std::size_t(h.bits / 8);
  const std::size_t row = bpp * std::size_t(h.width), rows = std::size_t(h.height);
  // Every chunk's CRC (over its type and data), the image data gathered.
  std::string idat;
  for (std::size_t pos = kSignature.size(); pos + 12 <= file.size();) {
    const std::size_t length = be32(file, pos);
    if (file.size() - pos - 12 < length) return false;
    if (libdeflate_crc32(0, file.data() + pos + 4, length + 4) != be32(file, pos + 8 + length)) return false;
    const std::string_view type = file.substr(pos + 4, 4);
    if (type == "IDAT") idat.append(file.substr(pos + 8, length));
    pos += 12 + length;
    if (type == "IEND") break;
  }
  std::vector<std::uint8_t> raw(rows * (row + 1));
  const std::unique_ptr<libdeflate_decompressor, DecompressorDeleter> d(libdeflate_alloc_decompressor());
  if (!d) throw std::bad_alloc();
  std::size_t in_bytes = 0;
  // Exactly the rows (no short or long stream), and the stream ends the image data.
  if (libdeflate_zlib_decompress_ex(d.get(), idat.data(), idat.size(), raw.data(), raw.size(), &in_bytes, nullptr) !=
          LIBDEFLATE_SUCCESS ||
      in_bytes != idat.size())
    return false;
  samples.resize(rows * row);
  const std::vector<std::uint8_t> zeros(row, 0);
  for (std::size_t y = 0; y < rows; ++y) {
    std::uint8_t* out = samples.data() + y * row;
    std::memcpy(out, raw.data() + y * (row + 1) + 1, row);
    if (!unfilter_row(raw[y * (row + 1)], out, y > 0 ? out - row : zeros.data(), row, bpp)) return false;
  }
  return true;
}

}  // namespace hydrolux::io::png
