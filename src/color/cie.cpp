#include "hydrolux/color/cie.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cmath>

#include "hydrolux/core/embedded_data.hpp"
#include "hydrolux/core/error.hpp"
#include "hydrolux/core/table.hpp"

namespace hydrolux::color {

namespace {

constexpr const char* kCmfFile = "color/cie1931_2deg_xyz.csv";
constexpr const char* kSunFile = "color/astm_g173_direct.csv";

const Table& cmf_table() {
  static const Table t = parse_table(embedded_file(kCmfFile), kCmfFile);
  return t;
}

const Table& sun_table() {
  static const Table t = parse_table(embedded_file(kSunFile), kSunFile);
  return t;
}

Mat3 inverse(const Mat3& m) {
  const double det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
                     m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                     m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
  if (!(std::abs(det) > 0)) throw Error("singular colour matrix");
  Mat3 r{};
  r[0][0] = (m[1][1] * m[2][2] - m[1][2] * m[2][1]) / det;
  r[0][1] = (m[0][2] * m[2][1] - m[0][1] * m[2][2]) / det;
  r[0][2] = (m[0][1] * m[1][2] - m[0][2] * m[1][1]) / det;
  r[1][0] = (m[1][2] * m[2][0] - m[1][0] * m[2][2]) / det;
  r[1][1] = (m[0][0] * m[2][2] - m[0][2] * m[2][0]) / det;
  r[1][2] = (m[0][2] * m[1][0] - m[0][0] * m[1][2]) / det;
  r[2][0] = (m[1][0] * m[2][1] - m[1][1] * m[2][0]) / det;
  r[2][1] = (m[0][1] * m[2][0] - m[0][0] * m[2][1]) / det;
  r[2][2] = (m[0][0] * m[1][1] - m[0][1] * m[1][0]) / det;
  return r;
}

Xyz from_chromaticity(double x, double y) { return {x / y, 1.0, (1.0 - x - y) / y}; }

// RGB -> XYZ from the primaries' chromaticities and the white's (SMPTE RP 177-1993): the columns
// are the primaries' XYZ, each scaled so that RGB (1, 1, 1) is the white with Y = 1.
Mat3 rgb_to_xyz_matrix(RgbSpace s) {
  struct Primaries {
    double r[2], g[2], b[2];
  };
  // ITU-R BT.709-6 and BT.2020-2, table "colorimetry": primaries' (x, y).
  const Primaries p = s == RgbSpace::rec709 ? Primaries{{0.640, 0.330}, {0.300, 0.600}, {0.150, 0.060}}
                                            : Primaries{{0.708, 0.292}, {0.170, 0.797}, {0.131, 0.046}};
  const Xyz r = from_chromaticity(p.r[0], p.r[1]), g = from_chromaticity(p.g[0], p.g[1]),
            b = from_chromaticity(p.b[0], p.b[1]);
  const Mat3 prim{{{r.X, g.X, b.X}, {r.Y, g.Y, b.Y}, {r.Z, g.Z, b.Z}}};
  const Rgb scale = matmul(inverse(prim), d65_white());
  Mat3 m{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) m[i][j] = prim[i][j] * scale[j];
  return m;
}

}  // namespace

Xyz cie1931(double nm) {
  const Table& t = cmf_table();
  const auto wl = t.column("wavelength_nm");
  if (!(nm >= wl.front() && nm <= wl.back())) return {};
  // 1 nm rows: index directly, then interpolate within the row.
  const double pos = nm - wl.front();
  std::size_t i = std::min(std::size_t(pos), wl.size() - 2);
  const double f = pos - double(i);
  const auto lerp = [&](std::string_view c) {
    const auto v = t.column(c);
    return v[i] + f * (v[i + 1] - v[i]);
  };
  return {lerp("x_bar"), lerp("y_bar"), lerp("z_bar")};
}

std::array<double, 2> chromaticity(const Xyz& c) {
  const double s = c.X + c.Y + c.Z;
  if (!(s != 0)) return {1.0 / 3, 1.0 / 3};
  return {c.X / s, c.Y / s};
}

// ---- illuminants ----

Illuminant Illuminant::astm_g173_direct() {
  Illuminant s;
  s.kind_ = Kind::table;
  s.name_ = "astm-g173-direct";
  const auto wl = sun_table().column("wavelength_nm");
  s.range_ = {wl.front(), wl.back()};
  return s;
}

Illuminant Illuminant::blackbody(double kelvin) {
  require_in_range("temperature_k", kelvin, 1000.0, 100000.0, "a blackbody source");
  Illuminant s;
  s.kind_ = Kind::blackbody;
  s.kelvin_ = kelvin;
  s.name_ = fmt::format("blackbody:{:g}", kelvin);
  s.range_ = {10, 1e5};  // nm: Planck's law holds anywhere; this keeps l^5 and the exponent finite
  return s;
}

Illuminant Illuminant::equal_energy() {
  Illuminant s;
  s.kind_ = Kind::flat;
  s.name_ = "equal-energy";
  return s;
}

Illuminant Illuminant::parse(std::string_view text) {
  if (text == "astm-g173-direct") return astm_g173_direct();
  if (text == "equal-energy") return equal_energy();
  constexpr std::string_view bb = "blackbody:";
  if (text.substr(0, bb.size()) == bb) {
    const std::string_view num = text.substr(bb.size());
    double k = 0;
    const auto [ptr, ec] = std::from_chars(num.data(), num.data() + num.size(), k);
    if (ec == std::errc() && ptr == num.data() + num.size()) return blackbody(k);
  }
  throw UnknownNameError(fmt::format("unknown light source '{}'; valid: astm-g173-direct, blackbody:T (T in kelvin, "
                                     "1000-100000), equal-energy",
                                     text));
}

double Illuminant::operator()(double nm) const {
  switch (kind_) {
    case Kind::flat: return 1.0;
    case Kind::table: {
      require_in_range("wavelength_nm", nm, range_[0], range_[1], "the ASTM G173-03 table");
      const Table& t = sun_table();
      return interpolate_linear(t.column("wavelength_nm"), t.column("direct_circumsolar_w_m2_nm"), nm);
    }
    case Kind::blackbody: {
      require_in_range("wavelength_nm", nm, range_[0], range_[1], name_);
      // Planck: B ~ l^-5 / (exp(c2 / (l T)) - 1), c2 = h c / k_B = 1.438776877e-2 m K (CODATA 2018).
      constexpr double c2_nm_k = 1.438776877e7;
      const auto planck = [&](double l) { return 1.0 / (std::pow(l, 5) * std::expm1(c2_nm_k / (l * kelvin_))); };
      return planck(nm) / planck(560.0);
    }
  }
  return 0;
}

Xyz integrate_xyz(const Illuminant& s, double lo_nm, double hi_nm) {
  Xyz sum;
  const int steps = std::max(1, int(std::lround(hi_nm - lo_nm)));
  const double h = (hi_nm - lo_nm) / steps;
  for (int i = 0; i <= steps; ++i) {
    const double nm = lo_nm + i * h;
    const double w = (i == 0 || i == steps ? 0.5 : 1.0) * h * s(nm);
    const Xyz c = cie1931(nm);
    sum.X += w * c.X;
    sum.Y += w * c.Y;
    sum.Z += w * c.Z;
  }
  return sum;
}

// ---- colour spaces ----

RgbSpace parse_rgb_space(std::string_view text) {
  if (text == "rec709" || text == "srgb") return RgbSpace::rec709;
  if (text == "rec2020") return RgbSpace::rec2020;
  throw UnknownNameError(fmt::format("unknown colour space '{}'; valid: rec709 (srgb), rec2020", text));
}

std::string_view rgb_space_name(RgbSpace s) { return s == RgbSpace::rec709 ? "rec709" : "rec2020"; }

Xyz d65_white() { return from_chromaticity(0.3127, 0.3290); }

Mat3 xyz_to_rgb_matrix(RgbSpace s) { return inverse(rgb_to_xyz_matrix(s)); }

Rgb luminance_weights(RgbSpace s) { return rgb_to_xyz_matrix(s)[1]; }

Mat3 bradford_adaptation(const Xyz& from, const Xyz& to) {
  // Lam (1985) as given by Lindbloom and in ICC.1:2010 Annex E.
  const Mat3 mb{{{0.8951, 0.2664, -0.1614}, {-0.7502, 1.7135, 0.0367}, {0.0389, -0.0685, 1.0296}}};
  const Xyz f{from.X / from.Y, 1.0, from.Z / from.Y};
  const Xyz t{to.X / to.Y, 1.0, to.Z / to.Y};
  const Rgb cf = matmul(mb, f), ct = matmul(mb, t);
  Mat3 d{};
  for (int i = 0; i < 3; ++i) d[i][i] = ct[i] / cf[i];
  return multiply(inverse(mb), multiply(d, mb));
}

Mat3 multiply(const Mat3& a, const Mat3& b) {
  Mat3 r{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k) r[i][j] += a[i][k] * b[k][j];
  return r;
}

Rgb matmul(const Mat3& m, const Xyz& c) {
  return {m[0][0] * c.X + m[0][1] * c.Y + m[0][2] * c.Z, m[1][0] * c.X + m[1][1] * c.Y + m[1][2] * c.Z,
          m[2][0] * c.X + m[2][1] * c.Y + m[2][2] * c.Z};
}

Rgb desaturate_into_gamut(const Rgb& rgb, RgbSpace s) {
  const Rgb w = luminance_weights(s);
  const double y = w[0] * rgb[0] + w[1] * rgb[1] + w[2] * rgb[2];
  if (!(y > 0)) return {0, 0, 0};
  double scale = 1;
  for (double c : rgb)
    if (c < 0) scale = std::min(scale, y / (y - c));  // y + scale (c - y) = 0
  if (scale >= 1) return rgb;
  Rgb out;
  for (int i = 0; i < 3; ++i) out[i] = std::max(0.0, y + scale * (rgb[i] - y));
  return out;
}

}  // namespace hydrolux::color
