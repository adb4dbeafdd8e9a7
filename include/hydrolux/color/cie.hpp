#pragma once
// Spectral colour: the CIE 1931 standard observer, the light sources hydrolux integrates against,
// and the linear RGB spaces it writes.
//
// Conventions, stated once for hydrolux/color:
// - Wavelengths are vacuum nanometres. Tristimulus values X, Y, Z are the integrals of a spectral
//   power distribution against x_bar, y_bar, z_bar in nm steps (no 683 lm/W factor): Y is a
//   relative luminance.
// - Linear RGB spaces are ITU-R BT.709 (the primaries of sRGB) and BT.2020, both with the D65 white
//   point (x, y) = (0.3127, 0.3290); their XYZ -> RGB matrices are derived from the primaries' and
//   white's chromaticities (SMPTE RP 177), so D65 of luminance Y maps to RGB (Y, Y, Y).
// - A light source's white is carried to D65 by the Bradford chromatic adaptation transform
//   (Lam 1985; the von Kries scaling in the Bradford cone space, as in ICC v4 and CIECAM97s), so
//   that the source itself maps to RGB (1, 1, 1) times its luminance.
//
// Data (data/color/, compiled in):
// - CIE 1931 2-degree observer at 1 nm, 360-830 nm: CIE 015:2004 (via the CVRL database,
//   ciexyz31_1.csv).
// - Sunlight at the ground: ASTM G173-03 direct + circumsolar spectral irradiance (air mass 1.5,
//   W m^-2 nm^-1), 280-1100 nm of its 280-4000 nm.
#include <array>
#include <string>
#include <string_view>

namespace hydrolux::color {

inline constexpr double kCmfMinNm = 360.0;
inline constexpr double kCmfMaxNm = 830.0;

struct Xyz {
  double X = 0, Y = 0, Z = 0;
};

// x_bar, y_bar, z_bar at `nm`: the 1 nm table, linearly interpolated between its rows; 0 outside
// [360, 830] nm (the functions are below 1e-4 of their peaks at both ends).
Xyz cie1931(double nm);

// Chromaticity (x, y) = (X, Y) / (X + Y + Z); (1/3, 1/3) for a black (all-zero) input.
std::array<double, 2> chromaticity(const Xyz& c);

// ---- light sources -------------------------------------------------------------------------

// A spectral power distribution, relative: only ratios between wavelengths matter to colour, and
// the Lee tables divide by the source's own luminance.
//   "astm-g173-direct": ASTM G173-03 direct + circumsolar (W m^-2 nm^-1), 280-1100 nm here;
//   "blackbody:T": Planck's law at T kelvin (T in [1000, 100000]), scaled to 1 at 560 nm;
//   "equal-energy": 1 at every wavelength (CIE illuminant E).
class Illuminant {
 public:
  // Throws UnknownNameError for an unknown name, DomainError ("temperature_k") for T.
  static Illuminant parse(std::string_view text);
  static Illuminant astm_g173_direct();
  static Illuminant blackbody(double kelvin);
  static Illuminant equal_energy();

  // The source's spectral power at `nm`. DomainError ("wavelength_nm") outside its range.
  double operator()(double nm) const;
  const std::string& name() const { return name_; }
  // The wavelengths where it is defined.
  std::array<double, 2> range_nm() const { return range_; }

 private:
  enum class Kind { table, blackbody, flat };
  Kind kind_ = Kind::flat;
  double kelvin_ = 0;
  std::string name_;
  std::array<double, 2> range_{0, 1e9};
};

// The tristimulus values of a source between lo_nm and hi_nm, by the trapezoid rule on a 1 nm grid
// (the CIE's own tabulation step): X = sum S(l) x_bar(l) dl.
Xyz integrate_xyz(const Illuminant& s, double lo_nm = kCmfMinNm, double hi_nm = kCmfMaxNm);

// ---- colour spaces -------------------------------------------------------------------------

using Mat3 = std::array<std::array<double, 3>, 3>;
using Rgb = std::array<double, 3>;

enum class RgbSpace { rec709, rec2020 };

// "rec709" (alias "srgb": the same primaries, linear), "rec2020". UnknownNameError otherwise.
RgbSpace parse_rgb_space(std::string_view text);
std::string_view rgb_space_name(RgbSpace s);

// D65 with Y = 1, from its chromaticity (0.3127, 0.3290).
Xyz d65_white();

// Linear RGB from XYZ (both relative to the same white, D65).
Mat3 xyz_to_rgb_matrix(RgbSpace s);
// The luminance of a linear RGB value: the Y row of the inverse matrix (Rec.709: 0.2126, 0.7152,
// 0.0722).
Rgb luminance_weights(RgbSpace s);

// The Bradford transform that carries colours seen under `from` white to their corresponding
// colours under `to` white (whites of any luminance; only their chromaticities matter).
Mat3 bradford_adaptation(const Xyz& from, const Xyz& to);

Mat3 multiply(const Mat3& a, const Mat3& b);
Rgb matmul(const Mat3& m, const Xyz& c);

// Into the gamut, toward the white point at constant luminance: an RGB value with a negative
// component (a spectral colour outside the primaries' triangle) becomes Y (1,1,1) + s (rgb - Y
// (1,1,1)) with the largest s in [0, 1] that makes every component >= 0, Y its luminance (Lee &
// Laven's desaturation). Values inside the gamut, and values above 1 (HDR), are left as they are.
// A value of negative luminance (not a physical colour) becomes black.
Rgb desaturate_into_gamut(const Rgb& rgb, RgbSpace s);

}  // namespace hydrolux::color
