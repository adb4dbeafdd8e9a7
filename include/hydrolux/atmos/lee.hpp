#pragma once
// Lee diagrams: the colour of sunlight scattered by water drops over scattering angle and drop
// radius (R. L. Lee, Appl. Opt. 37, 5221, 1998), computed spectrally in absolute units, and the
// corona (forward) and glory (backward) tables of cloud droplets in the same form. The equations,
// the sampling and the checks are in docs/lee.md.
//
// What a table holds. Column c is a population of drops (a gamma distribution of number-mean
// radius radius_um[c] and relative standard deviation `size_spread`, or drops of that one radius);
// row r a scattering angle theta (0 = forward, the sun behind the drop; 180 = the antisolar point).
// The value is
//     T(theta) = <dsigma_sca/dOmega> / <pi a^2>   [sr^-1]
// the drops' differential scattering cross-section per unit of their projected area, averaged over
// the population (ratio of the two averages), over the sun's disk, and over wavelength weighted by
// the sun's spectrum and the CIE 1931 observer. It is the radiance scattered once by a thin layer
// of these drops per unit incident irradiance and per unit of the layer's projected-area optical
// depth tau_geo = path * sum pi a^2 n(a): L = E_sun * tau_geo * T. (For drops much larger than the
// wavelength Q_ext -> 2, so tau_geo = tau_ext / 2; over the whole sphere T integrates to Q_sca.)
// Nothing is normalised per column: rainbows, fogbows, coronas and glories keep their brightness
// ratios. Colour: X, Y, Z relative to the sun's luminance (a colourless T gives Y = T), and linear
// RGB after the sun's white is adapted to D65 (Bradford), so that a wavelength-independent T is
// RGB (T, T, T): sunlight is white.
//
// Integration (docs/lee.md): K wavelengths at the midpoints of K equal steps (weights S x_bar dl);
// the population on a grid in ln a shared by every column (denser where the size parameter is
// small, shifted by a different fraction of a step at each wavelength, so that no grid resonates
// with the Mie ripple). Each evaluation (one wavelength, one radius) samples every row's cell -- the
// interval of one row spacing around the row on its axis (angle or cosine) -- at a jittered point,
// and the sun's disk is a fixed kernel from cells to rows (exact spherical angles, 2048 points of
// the disk, 16,384 within 4 sun radii of 0 and 180 degrees). So a row holds the average over its
// cell convolved with the disk, centred on its sample position: the right value for a texel, and
// free of aliasing from fringes finer than the table; a table of one row takes one point of the disk
// per evaluation instead. `sampling` multiplies every rate (K, the radius grid's density); tests
// check that doubling it changes the standard table by less than 1% RMS in luminance.
#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "hydrolux/color/cie.hpp"
#include "hydrolux/core/error.hpp"
#include "hydrolux/core/progress.hpp"
#include "hydrolux/core/vec.hpp"
#include "hydrolux/scatter/theories.hpp"

namespace hydrolux::optics {
class Medium;
}

namespace hydrolux::atmos {

enum class LeeTableKind { rainbow, corona, glory };
enum class AngleAxis { angle, cosine };
enum class RadiusScale { log, linear };

std::string_view table_kind_name(LeeTableKind k);
// "rainbow", "corona" or "glory"; UnknownNameError "table 'x': expected rainbow, corona or glory".
LeeTableKind parse_table_kind(std::string_view name);
std::string_view angle_axis_name(AngleAxis a);
std::string_view radius_scale_name(RadiusScale s);

// The sun's angular diameter (0.53 degrees: Allen's Astrophysical Quantities, 31.99 arcmin at 1 AU)
// and the linear limb-darkening coefficient used when limb darkening is on: I(mu) / I(1) =
// 1 - u (1 - mu), u = 0.6 for the visible (Cox, Allen's Astrophysical Quantities, 4th ed., 2000,
// section 14.7; u runs from 0.8 at 400 nm to 0.5 at 800 nm, and one grey value is used here).
inline constexpr double kSunDiskDeg = 0.53;
inline constexpr double kLimbDarkeningU = 0.6;

// The radii a table may hold, micrometres. The largest a given spec can compute is usually smaller:
// see max_radius_um.
inline constexpr double kMinRadiusUm = 0.1, kMaxRadiusUm = 5000;

// The drops' shape (docs/non-spherical.md): spheres (the default), oblate spheroids of one axis
// ratio (polar / equatorial; symmetry axis vertical), or Beard & Chuang's falling drops, whose
// axis ratio follows their radius (scatter/drop_shape.hpp; below its smallest radius, 0.5 mm, the
// departure from the sphere is scaled as a^2, the trend of its coefficients).
struct DropShapeSpec {
  enum class Kind { sphere, spheroid, beard_chuang };
  Kind kind = Kind::sphere;
  double axis_ratio = 1;  // spheroid only
  bool spherical() const { return kind == Kind::sphere; }
};
// The axis ratios a spheroid may have: [kMinBowAxisRatio, 1], the flattening whose bows the
// plane-section method describes. Below it the primary's fold meets the hyperbolic umbilic (width /
// height 1.31 in our 3-D trace and Marston and Trinh's, Q = 0.763), the one-fold Airy profile of the
// section collapses onto 180 degrees at the top of the bow (its 1/sin term grows without bound: at
// Q = 0.709, 1500 times a sphere's peak) and the secondary's section loses its ray (an all-zero table
// at Q <= 0.72): docs/non-spherical.md.
inline constexpr double kMinBowAxisRatio = 0.77;
// "sphere", "spheroid:Q" (kMinBowAxisRatio <= Q <= 1) or "beard-chuang". UnknownNameError for another
// name, DomainError ("axis_ratio") for Q outside [kMinBowAxisRatio, 1], one message for every door.
DropShapeSpec parse_drop_shape(std::string_view text);
std::string drop_shape_name(const DropShapeSpec& s);
// The axis ratio of a drop of equal-volume radius radius_um (1 for spheres). For beard-chuang
// beyond the shape table's largest radius (4.5 mm) the table's last shape is used.
double drop_axis_ratio(const DropShapeSpec& s, double radius_um);

struct LeeSpec {
  LeeTableKind table = LeeTableKind::rainbow;
  scatter::Theory theory{scatter::TheoryKind::Mie, 0};
  // Columns: radius_um from radius_min_um to radius_max_um inclusive (one column: radius_min_um).
  double radius_min_um = 5, radius_max_um = 800;
  int columns = 512;
  RadiusScale radius_scale = RadiusScale::log;
  // Rows: theta (or cos theta) from angle_min_deg to angle_max_deg inclusive, increasing downward.
  double angle_min_deg = 90, angle_max_deg = 180;
  int rows = 1024;
  AngleAxis axis = AngleAxis::angle;
  double sun_disk_deg = kSunDiskDeg;  // angular diameter; 0 = a point
  bool limb_darkening = false;
  double size_spread = 0.1;  // relative standard deviation of the gamma distribution; 0 = one radius
  double wavelength_min_nm = 380, wavelength_max_nm = 780;
  int wavelengths = 0;  // 0: one every 10 nm / sampling
  std::string drop_medium = "water", surrounding_medium = "air";
  std::optional<double> temperature_c;  // the drop medium's default when unset
  color::Illuminant sun = color::Illuminant::astm_g173_direct();
  color::RgbSpace rgb_space = color::RgbSpace::rec709;
  double sampling = 1;  // multiplies every sampling rate
  // Automatic sampling (a request without one): where the table at `sampling` estimates its error
  // above kLeeErrorTolerance, it is computed again at the sampling that would meet it
  // (sampling_for_tolerance), at most sampling_most, within the memory available. 0: `sampling` as given.
  double sampling_most = 0;
  std::uint64_t seed = 1;
  int threads = 0;  // 0: every core
  // Non-spherical drops (Airy theory of the plane section: docs/non-spherical.md). The bow's point
  // is fixed by the sun's elevation and the position angle around the antisolar point (0 at the
  // top, 90 at the side, 180 at the bottom); the drops' axes are vertical, or tilted by a 2-D
  // Gaussian of standard deviation canting_deg per component. Spheres ignore all three.
  DropShapeSpec shape;
  double sun_elevation_deg = 0, position_deg = 0, canting_deg = 0;
  // Also the Stokes Q (LeeTable::q_xyz). Off: the table, its files and its cost are those without.
  bool stokes = false;
};

// The defaults of each kind: rainbow 5-800 um over 90-180 degrees; corona 1-50 um over 0-20; glory
// 1-50 um over 160-180.
LeeSpec default_lee_spec(LeeTableKind kind);

// One radius's profile: one column of drops of exactly `radius_um` (no spread) over [a0, a1]
// degrees in `rows` rows, the kind's other defaults.
LeeSpec profile_spec(LeeTableKind kind, double radius_um, double a0, double a1, int rows);

// A table as a door asks for it (hydrolux lee, Python's hydrolux.lee): named values, each parsed by
// the door in its own words; what is unset is the kind's default (default_lee_spec). The numbers and
// switches are declared parameters (lee_params.hpp): their ranges and defaults are written once,
// and the defaults are the initializers here. The spectrum (wavelengths), the media, the sun and the
// colour space are left to the door to set on the spec make_lee_spec returns, in the order its
// messages come in (the temperature is carried over; the door checks it against its medium).
struct LeeRequest {
  LeeTableKind table = LeeTableKind::rainbow;
  scatter::Theory theory{scatter::TheoryKind::Mie, 0};
  std::optional<std::array<double, 2>> radius_um;  // A <= B; A == B: one radius, one column
  std::optional<std::array<double, 2>> angle_deg;  // A <= B
  std::optional<std::array<int, 2>> size;          // columns, rows
  RadiusScale radius_scale = RadiusScale::log;
  AngleAxis axis = AngleAxis::angle;
  double sun_disk_deg = kSunDiskDeg;
  bool limb_darkening = false;
  double size_spread = 0.1;
  std::optional<double> sampling;  // unset: automatic, from 1 up to kAutoSamplingMost (LeeSpec::sampling_most)
  std::uint64_t seed = 1;
  int threads = 0;
  std::optional<double> temperature_c;  // the drop medium's default when unset
  std::string shape = "sphere";         // parse_drop_shape's names
  double sun_elevation_deg = 0, position_deg = 0, canting_deg = 0;
  bool stokes = false;  // LeeSpec::stokes
  // One radius given (A == B): the table has one column.
  bool one_radius() const { return radius_um && (*radius_um)[0] == (*radius_um)[1]; }
};

// A request whose shape contradicts itself. what() says it in the library's (and Python's) names;
// the CLI says it in its flags'.
class LeeShapeError : public Error {
 public:
  enum class Rule {
    one_radius_columns,  // one radius makes one column, and the size asks for more
    one_angle_rows,      // equal angles make one row, and the table has more
  };
  LeeShapeError(Rule rule, int columns, int rows);
  Rule rule() const noexcept { return rule_; }
  int columns() const noexcept { return columns_; }
  int rows() const noexcept { return rows_; }

 private:
  Rule rule_;
  int columns_, rows_;
};

// The spec of a request: the kind's defaults, the radii and angles given (one radius: one column),
// the size (columns, rows), and the rest as given. Throws LeeShapeError (a single radius with more
// than one column; equal angles with more than one row) and Error for a parameter of non-spherical drops set for spheres, which would ignore it
// (lee_params.hpp, shape_only_message). Not validated: the caller adds what it sets and calls
// validate().
LeeSpec make_lee_spec(const LeeRequest& request);

// Checks a spec before any work: DomainError naming the quantity ("radius_um", "angle_deg",
// "columns", "rows", "sun_disk_deg", "size_spread", "wavelength_nm", "wavelengths", "sampling",
// "size_parameter", "temperature_c", "axis_ratio", "sun_elevation_deg", "position_deg",
// "canting_deg") or Error for a theory that cannot make the table (Airy theory has no corona or
// glory; non-spherical drops need Airy theory and a rainbow table).
void validate(const LeeSpec& spec);

// The largest radius (um, a whole number, at most kMaxRadiusUm) that validate() accepts for this
// spec's theory, size spread, shortest wavelength and surrounding medium: the size parameter
// 2 pi r n / lambda of the population's largest drop (kTailSigmas spreads above the radius) at the
// shortest wavelength must stay within the theory's limit (1e5 for Mie and Debye). With the
// defaults (Mie, spread 0.1, 380 nm) that is 2695 um; with no spread 6048, so kMaxRadiusUm.
double max_radius_um(const LeeSpec& spec);
// The largest whole radius (um) whose population keeps the method's axis ratio (kMinBowAxisRatio)
// at its largest drop: for beard-chuang drops ~888 um with the 10% spread; kMaxRadiusUm for other
// shapes. validate() refuses larger columns with this bound.
double max_shape_radius_um(const LeeSpec& spec);

// The peak memory, in bytes, of computing the table and writing its files (hydrolux lee, export),
// so that a table too large for the machine is refused before the work: the arrays
// compute_lee_table and lee_images allocate, counted from their sizes, plus the encoders' buffers
// and a fixed part, both measured: the peak resident set (/usr/bin/time -v) of `hydrolux lee
// --radius-um 1:2 --size-spread 0 --sun-disk-deg 0 --wavelengths-nm 500:600:2 --sampling 0.25` was
// 270 MB at 1024x1024 and 687 MB at 2048x2048: 135.7 bytes a pixel, of which the arrays account
// for 116 (these squares have as many nodes and cells as columns and rows), leaving 20 for the
// encoders; the fixed part is 134 MB (taken as 150). Expects a spec that passes validate().
inline constexpr double kLeeEncoderBytesPerPixel = 20, kLeeFixedBytes = 150e6;
double estimated_bytes(const LeeSpec& spec);

// Refuses, before the work, tables whose computation would not fit in `available` bytes of memory
// (available_memory_bytes(), core/memory.hpp, unless a caller gives it): the largest estimated_bytes
// of `specs`, which are computed one after the other. The one check every door makes (hydrolux lee
// and export, hydrolux.lee): an Error of one line naming the size as the door calls it and as given
// (`size_text`), both byte counts and a size that would fit, in the first spec's terms (the others
// scale with it): "--size 8192x8192: the rainbow table needs about 9.2 GB of memory and 3.1 GB is
// available; about --size 4800x4800 would fit" (SizeSyntax::cli), or "size (8192, 8192): ...;
// about size=(4800, 4800) would fit" (SizeSyntax::python).
enum class SizeSyntax { cli, python };
void check_table_memory(const std::vector<const LeeSpec*>& specs, const std::string& size_text, SizeSyntax syntax,
                        std::optional<std::uint64_t> available = std::nullopt);

// The sample positions: radius_um per column, theta in degrees and its cosine per row.
std::vector<double> column_radii_um(const LeeSpec& spec);
std::vector<double> row_angles_deg(const LeeSpec& spec);

struct LeeWork {
  std::int64_t evaluations = 0;  // single-drop solutions (one wavelength, one radius, every row)
  std::int64_t terms = 0;        // partial waves (Mie, Debye) summed over the evaluations
  std::int64_t term_angles = 0;  // terms x rows: the amplitude sums' inner loop count
  int wavelengths = 0;           // K
  int radius_nodes = 0;          // radii per wavelength (the shared grid, or the columns)
  int cells = 0;                 // angles per evaluation: the rows' cells and a margin for the disk
};

// The axes of canted drops (LeeSpec::canting_deg) for one evaluation of a table (one radius node at
// one wavelength): kCantingAxes axes of equal weight whose tilt components (tx, tz) are independent
// normals of standard deviation canting_deg (the axis normalize(tan tx, 1, tan tz); each component
// held within 89 degrees), by Box-Muller from a 3 x 3 stratified grid of the unit square shifted by
// (su, sv) in [0, 1)^2. With a uniform shift each axis is an exact draw; each evaluation of a table
// takes the next shift of a 2-D low-discrepancy sequence (docs/non-spherical.md, "Canting").
inline constexpr int kCantingAxes = 9;
std::array<Vec3, kCantingAxes> canting_axes(double canting_deg, double su, double sv);
// The axes that evaluation n (n = node j * wavelengths + wavelength k) of spec's table takes, from
// its seed: canting_axes at that evaluation's shift.
std::array<Vec3, kCantingAxes> evaluation_canting_axes(const LeeSpec& spec, double n);

// A table's estimated error, from the table itself: its wavelengths split into the even- and the
// odd-numbered, each half a table of its own (its sum scaled to the whole's luminance weight) with its
// own wavelengths, radius grids and cell points; half their difference estimates the whole table's
// error at each pixel where that error is noise-like (the sampling's), and overstates it where the
// halves differ by a smooth bias. Root mean square over the table, relative to that of the luminance
// Y; Q (stokes) in the same units, relative to I's luminance. Unset with one wavelength.
struct LeeError {
  std::optional<double> luminance_rms, q_rms;
};
// Above this estimated luminance error (relative RMS) a table says so in its notes, naming the
// sampling that would meet it (the error falls about as 1 / sampling: docs/lee.md, "The table's error").
inline constexpr double kLeeErrorTolerance = 0.01;
// The most an automatic sampling (LeeSpec::sampling_most) goes to: 4 costs up to 16 times the table at
// 1 (more wavelengths and radius nodes alike); beyond it the table's note names the sampling to give.
inline constexpr double kAutoSamplingMost = 4;
// The sampling that would bring a table of estimated error `error` at `sampling` within
// kLeeErrorTolerance, were the error to fall as sampling^-order: `sampling` doubled while
// error * (sampling / need)^order is above it, at most `most`.
double sampling_for_tolerance(double error, double sampling, double most, double order = 1);

struct LeeTable {
  LeeSpec spec;
  std::vector<double> radius_um;  // per column
  std::vector<double> angle_deg;  // per row
  std::vector<double> cos_angle;  // per row
  // X, Y, Z per pixel, (row * columns + column) * 3, relative to the sun's luminance (sr^-1).
  std::vector<double> xyz;
  // With spec.stokes (else empty): the Stokes Q, in the same layout and units as xyz and integrated
  // exactly as I (spectrum x observer, sizes, the sun's disk). Basis: the scattering plane (the
  // plane of the sun, the drop and the observer), Q = (|S1|^2 - |S2|^2) / 2 per the same
  // normalisation as I = (|S1|^2 + |S2|^2) / 2 (S1 perpendicular, S2 parallel: Bohren & Huffman):
  // Q > 0 when the light is polarised perpendicular to the scattering plane, i.e. tangential to the
  // bow. U = 0 in this basis (spheres, and the plane-section Airy bows of non-spherical drops, which
  // keep the two polarisations' weights only), and V = 0. Its X, Y, Z are Q weighted by x_bar,
  // y_bar, z_bar like I's; Q_Y / I_Y (dolp) is the luminance-weighted degree of linear polarisation.
  std::vector<double> q_xyz;
  color::Xyz sun_white;                // the sun's XYZ over the sampled wavelengths, Y = 1
  color::Mat3 xyz_to_rgb{};            // Bradford (sun -> D65) then XYZ -> linear RGB
  std::vector<double> wavelengths_nm;  // the K sampled wavelengths
  LeeWork work;
  // lee_resolution_notes(spec), and the table's estimated error where it is above kLeeErrorTolerance
  std::vector<std::string> notes;
  LeeError error;
  // With automatic sampling (spec.sampling_most) and a second pass: the first pass's sampling and
  // estimated error (spec.sampling is the second's).
  std::optional<double> first_sampling, first_error;

  int columns() const { return int(radius_um.size()); }
  int rows() const { return int(angle_deg.size()); }
  color::Xyz at(int row, int column) const;
  // With stokes: Q's X, Y, Z, and dolp = Q_Y / I_Y (signed: > 0 tangential to the bow; 0 where
  // I_Y = 0). Without: Error.
  color::Xyz q_at(int row, int column) const;
  double dolp(int row, int column) const;
  // Linear RGB, unmapped (may have negative components) or desaturated into the gamut.
  color::Rgb rgb(int row, int column, bool into_gamut = true) const;
};

// Computes a table. `progress` is called after each wavelength with the fraction of the work done
// (with automatic sampling's second pass, from the first pass's share of the work, 1 / (1 + (s2 / s1)^2),
// to 1, its label naming the sampling). Automatic
// sampling's second pass is made where its estimated_bytes fit in `available` (available_memory_bytes()
// unless given); where not, the table says so in a note.
LeeTable compute_lee_table(const LeeSpec& spec, const ProgressFn& progress = {},
                           std::optional<std::uint64_t> available = std::nullopt);

// What a rainbow table cannot resolve at its settings, one line each, naming the parameters that fix
// it between braces ({size}, {angle_deg}, {theory}, {radius_um}, {size_spread}: core/error.hpp's
// spell_quantities), empty when nothing (cheap: from the spec alone; compute_lee_table keeps them
// in LeeTable::notes, and the sidecar, the profile and the doors say them):
// - rows wider than a quarter of the spacing of the first supernumeraries (Airy's z = 3.25 to 4.82,
//   at the shortest wavelength) of the largest drops whose fringes the sun's disk leaves (spacing at
//   least the disk's diameter), at a bow in the angle range: the fringes are aliased;
// - Airy theory below x = kAiryMinX (the columns' drops at the longest wavelength), where its first
//   supernumerary is ~20% off Mie's (docs/rainbow-theories.md, "Validity");
// - without a size spread, neighbouring columns so far apart in radius (more than kMaxFringeJump
//   of the spacing) that the second supernumerary jumps by more than half its spacing between them.
inline constexpr double kAiryMinX = 1000;
std::vector<std::string> lee_resolution_notes(const LeeSpec& spec);
// The spacing in degrees between the first two supernumeraries (Airy's maxima at z = 3.248198 and
// 4.820099, A&S Table 10.13) of the order-p bow of drops of size parameter x and real index n.
double supernumerary_spacing_deg(double n, double x, int p);

// The table as images: RGB (gamut-mapped linear RGB) followed by X, Y, Z (unmapped), 6 channels;
// and the display version, by Reinhard et al.'s photographic operator (SIGGRAPH 2002) on
// luminance with the hue kept: exposure = 0.18 / the log-average luminance (of pixels above 1e-6
// of the peak), L' = L (1 + L / W^2) / (1 + L) with the white W the 99.9th percentile of the exposed
// luminance (at least 1), clipped to [0, 1]; the sRGB curve is applied when the PNG is encoded.
struct LeeImages {
  std::vector<float> linear;   // rows x columns x 6: R, G, B, X, Y, Z
  std::vector<float> display;  // rows x columns x 3: linear display values in [0, 1]
  double exposure = 1, white = 1;
};
// `exposure` and `white` > 0 replace the automatic ones (to show several tables on one scale).
LeeImages lee_images(const LeeTable& t, double exposure = 0, double white = 0);

}  // namespace hydrolux::atmos
