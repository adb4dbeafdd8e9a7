#include "hydrolux/atmos/lee.hpp"

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <functional>
#include <cmath>
#include <utility>

#include "hydrolux/atmos/lee_params.hpp"
#include "hydrolux/core/error.hpp"
#include "hydrolux/core/math.hpp"
#include "hydrolux/core/memory.hpp"
#include "hydrolux/core/parse.hpp"
#include "hydrolux/core/vec.hpp"
#include "hydrolux/optics/media.hpp"
#include "hydrolux/scatter/airy.hpp"
#include "hydrolux/scatter/amplitudes.hpp"
#include "hydrolux/scatter/debye.hpp"
#include "hydrolux/scatter/drop_shape.hpp"
#include "hydrolux/scatter/ellipse_rainbow.hpp"
#include "hydrolux/scatter/geometric.hpp"
#include "hydrolux/scatter/mie.hpp"
#include "hydrolux/scatter/size_distribution.hpp"
#include "hydrolux/scatter/sphere.hpp"
#include "hydrolux/scatter/spheroid_bow.hpp"

namespace hydrolux::atmos {

namespace {

constexpr int kMaxSide = 16384;
// The population's grid reaches kTailSigmas relative widths beyond the outer columns (the gamma
// weight there is below 1e-13 of its peak for spread <= 0.5) and nodes are spread / kNodesPerWidth
// apart in ln a.
constexpr double kTailSigmas = 8;
constexpr double kNodesPerWidth = 6;
constexpr double kDenseSizeParameter = 8000;
constexpr double kDenseFactor = 16;
// The sun's disk in the kernel from cells to rows (make_angle_cells): kDiskPoints points per row, and
// kDiskPointsNearAxis within kDiskAxisRadii sun radii of 0 or 180 degrees, where the disk covers the
// axis and its share per cell converges slowest. Against 131,072 points, a corona table of 1024 rows
// over 0-20 degrees was 9e-4 off in luminance RMS with 2048 points everywhere (1% in single rows within
// 0.3 degrees of the axis; 1.2e-4 beyond 1 degree), against its stated 3.2e-4; 16,384 points: 1.7e-4
// (BENCHMARKS.md).
constexpr int kDiskPoints = 2048;
constexpr int kDiskPointsNearAxis = 16384;
constexpr double kDiskAxisRadii = 4;
constexpr double kKey = 0.18;
// Nodes where a column's weight is below this fraction of its peak are left out of it (the tails
// left out hold less than 1e-8 of its drops' area).
constexpr double kNegligibleWeight = 1e-9;

// The wave theories (Mie, one Debye order) sum partial waves over cos theta; their intensity has the
// Mie ripple. Airy theory and geometric optics take theta and have none.
bool is_wave_theory(const scatter::Theory& t) {
  return t.kind == scatter::TheoryKind::Mie || t.kind == scatter::TheoryKind::Debye;
}

// Stokes Q in Airy theory of spheres: every drop's Q is its I times one degree of polarisation,
// (|eps_1|^2 - |eps_2|^2) / (|eps_1|^2 + |eps_2|^2) of the Fresnel factors at the rainbow ray, which
// depend on the index and the order only (not on the size, the angle or the absorption), so each
// column's Q is this fraction of its I, wavelength by wavelength: no node values of Q are needed
// (the same fraction airy_rainbow's eps give each node; Q's values then differ from those of a sum
// of their own by rounding, < 1e-15 relative).
bool q_is_fraction_of_i(const LeeSpec& spec) {
  return spec.theory.kind == scatter::TheoryKind::Airy && spec.shape.spherical();
}
double airy_polarisation(scatter::Complex m, int p) {
  const scatter::RayFresnelFactors eps =
      scatter::ray_fresnel_factors(scatter::Complex(m.real(), 0), p, scatter::rainbow_ray(m.real(), p).theta_i);
  const double e1 = std::norm(eps.perpendicular), e2 = std::norm(eps.parallel);
  return e1 + e2 > 0 ? (e1 - e2) / (e1 + e2) : 0.0;
}

// Fractional part of a + b n, for the low-discrepancy sequences.
double frac(double v) { return v - std::floor(v); }

// A 64-bit mix of the seed (splitmix64's finaliser), to a fraction in [0, 1).
double seed_fraction(std::uint64_t seed, std::uint64_t stream) {
  std::uint64_t z = seed * 0x9E3779B97F4A7C15ull + stream * 0xBF58476D1CE4E5B9ull + 0x94D049BB133111EBull;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  z ^= z >> 31;
  return double(z >> 11) * 0x1.0p-53;
}

int wavelength_count(const LeeSpec& s) {
  if (s.wavelength_max_nm == s.wavelength_min_nm) return 1;
  const double base = s.wavelengths > 0 ? s.wavelengths : std::ceil((s.wavelength_max_nm - s.wavelength_min_nm) / 10.0);
  return std::max(1, int(std::lround(base * s.sampling)));
}

// The radius grid shared by the columns (spread > 0): nodes in ln a with a density of
// kNodesPerWidth / spread nodes per unit ln a, raised by kDenseSizeParameter / x (at most
// kDenseFactor times) where the size parameter x at the shortest wavelength is below
// kDenseSizeParameter: there a node is cheap (its cost grows like x) and the intensity at a fixed
// angle swings with x (the Mie ripple, and the fringes between ray orders, about 1 apart in x), so
// denser nodes average it rather than sampling it at random phases; times `sampling`. Measured
// (docs/lee.md): this halves the scatter between two seeds for 40-300 um drops for 1.7x the time. Node j sits where the
// cumulative density reaches j + shift, with a shift that changes with the wavelength.
class RadiusGrid {
 public:
  RadiusGrid() = default;
  // k_max: the largest wavenumber (2 pi n_air / lambda_min, m^-1).
  // dense_ripple: raise the density for small size parameters (the wave theories, whose intensity
  // has the Mie ripple; Airy theory and geometric optics have none and cost the same at any x).
  RadiusGrid(double ln_lo, double ln_hi, double width, double sampling, double k_max, bool dense_ripple)
      : lo_(ln_lo), hi_(ln_hi) {
    const double base = kNodesPerWidth / width * sampling;
    const double dense = dense_ripple ? kDenseFactor : 1.0;
    const auto density = [base, k_max, dense](double l) {
      const double x = k_max * std::exp(l);
      return base * std::clamp(kDenseSizeParameter / x, 1.0, dense);
    };
    constexpr int n = 4096;
    step_ = (hi_ - lo_) / n;
    cumulative_.resize(n + 1);
    cumulative_[0] = 0;
    for (int i = 0; i < n; ++i)  // Simpson's rule on each step
      cumulative_[std::size_t(i) + 1] =
          cumulative_[std::size_t(i)] +
          step_ / 6 * (density(lo_ + i * step_) + 4 * density(lo_ + (i + 0.5) * step_) + density(lo_ + (i + 1) * step_));
    nodes_ = int(std::ceil(cumulative_.back())) + 1;
    density_ = density;
  }
  int nodes() const { return nodes_; }
  // ln a of node j, and the width in ln a a node at ln a stands for.
  double ln_radius(std::size_t j, double shift) const { return inverse(double(j) + shift); }
  double width_at(double ln_a) const { return 1 / density_(ln_a); }
  // The nodes whose ln a lies in [l0, l1], as [first, last] (clamped to the grid).
  std::array<std::size_t, 2> nodes_between(double l0, double l1, double shift) const {
    const double u0 = std::floor(forward(l0) - shift), u1 = std::ceil(forward(l1) - shift);
    const double top = double(nodes_ - 1);
    return {std::size_t(std::clamp(u0, 0.0, top)), std::size_t(std::clamp(u1, 0.0, top))};
  }

 private:
  double forward(double l) const {
    const double pos = std::clamp((l - lo_) / step_, 0.0, double(cumulative_.size() - 1));
    const std::size_t i = std::min(std::size_t(pos), cumulative_.size() - 2);
    return cumulative_[i] + (pos - double(i)) * (cumulative_[i + 1] - cumulative_[i]);
  }
  double inverse(double u) const {
    const auto it = std::upper_bound(cumulative_.begin(), cumulative_.end(), u);
    if (it == cumulative_.end()) return hi_ + (u - cumulative_.back()) / density_(hi_);
    const std::size_t i = std::size_t(std::max<std::ptrdiff_t>(it - cumulative_.begin(), 1) - 1);
    const double f = (u - cumulative_[i]) / (cumulative_[i + 1] - cumulative_[i]);
    return lo_ + (double(i) + f) * step_;
  }
  double lo_ = 0, hi_ = 0, step_ = 0;
  std::vector<double> cumulative_;
  std::function<double(double)> density_;
  int nodes_ = 0;
};

// The largest and smallest radius (m) the grid reaches.
double largest_radius_m(const LeeSpec& s) {
  return std::max(s.radius_min_um, s.radius_max_um) * 1e-6 * std::exp(kTailSigmas * s.size_spread * 1.01);
}
double smallest_radius_m(const LeeSpec& s) {
  return std::min(s.radius_min_um, s.radius_max_um) * 1e-6 * std::exp(-kTailSigmas * s.size_spread * 1.01);
}

// The shared radius grid of a spec with a spread (k_max: the largest wavenumber, m^-1).
RadiusGrid shared_grid(const LeeSpec& s, double k_max) {
  const double w = s.size_spread;
  return RadiusGrid(std::log(std::min(s.radius_min_um, s.radius_max_um) * 1e-6) - kTailSigmas * w,
                    std::log(std::max(s.radius_min_um, s.radius_max_um) * 1e-6) + kTailSigmas * w, w, s.sampling, k_max,
                    is_wave_theory(s.theory));
}

// The most cells (angles per evaluation) and values per array a table may need: 2^16 cells, and
// 2^27 doubles (1 GiB) for the nodes' values and the columns' weights.
constexpr double kMaxCells = 65536, kMaxArrayValues = 134217728;

// The rows' cells and the sun's disk. With two rows or more, every evaluation samples each cell of
// the angle axis (angle or cosine, the rows' own spacing) at a jittered point inside it, so that the
// cells average the fringes finer than the table instead of aliasing them; the sun's disk is then a
// fixed matrix from cells to rows: for each row, the share of the disk's radiance (2048 points,
// exact spherical angles, so the axis at 0 and 180 degrees is right) falling into each cell. Cells
// reach beyond the table by the disk's radius. With one row, each evaluation takes one point of the
// disk instead (R2 sequence).
struct AngleCells {
  bool per_evaluation_disk = false;  // one row: the disk is sampled per evaluation
  int first = 0;                     // index of the first cell relative to row 0 (<= 0)
  int count = 0;
  double v0 = 0, dv = 0;  // axis value of row 0 and the spacing (degrees or cosine)
  bool cosine = false;
  // Row i's kernel: (cell, weight) pairs.
  std::vector<std::vector<std::pair<int, double>>> kernel;
};

// Inverse CDF of the distance rho / R from the sun's centre of a point drawn by radiance over the
// disk: uniform, rho = R sqrt(u); limb-darkened, by a table of the CDF.
class SunDiskSampler {
 public:
  explicit SunDiskSampler(bool limb) : limb_(limb) {
    if (!limb) return;
    constexpr int n = 2048;
    cdf_.resize(n + 1);
    double sum = 0;
    cdf_[0] = 0;
    for (int i = 1; i <= n; ++i) {
      const double r = (i - 0.5) / n;  // midpoint of the ring
      sum += r * (1 - kLimbDarkeningU * (1 - std::sqrt(1 - r * r))) / n;
      cdf_[i] = sum;
    }
    for (double& c : cdf_) c /= sum;
  }
  double radius_fraction(double u) const {
    if (!limb_) return std::sqrt(u);
    const auto it = std::upper_bound(cdf_.begin(), cdf_.end(), u);
    const std::size_t i = std::min<std::size_t>(std::max<std::ptrdiff_t>(it - cdf_.begin(), 1), cdf_.size() - 1);
    const double a = cdf_[i - 1], b = cdf_[i];
    const double t = b > a ? (u - a) / (b - a) : 0;
    return (double(i - 1) + t) / double(cdf_.size() - 1);
  }

 private:
  bool limb_;
  std::vector<double> cdf_;
};

// y += a x over n values: the inner loop of the columns' sums over their radii, which bounds the
// time of the cheap theories. Compiled for AVX-512 and AVX2 as well on x86-64 (the library's
// baseline is SSE2), chosen when the program loads.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
__attribute__((target_clones("avx512f", "avx2", "default")))
#endif
void axpy(double* __restrict y, const double* __restrict x, double a, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i) y[i] += a * x[i];
}

// Per-thread scratch for one evaluation.
struct Scratch {
  std::vector<double> mu, theta;
  std::vector<scatter::Complex> s1, s2;
  scatter::MieCoefficients coef;  // reused: no allocation per radius
  void resize(std::size_t n) {
    mu.resize(n);
    theta.resize(n);
    s1.resize(n);
    s2.resize(n);
  }
};

}  // namespace

namespace {

constexpr std::pair<LeeTableKind, std::string_view> kTableKinds[] = {
    {LeeTableKind::rainbow, "rainbow"}, {LeeTableKind::corona, "corona"}, {LeeTableKind::glory, "glory"}};

}  // namespace

double sampling_for_tolerance(double error, double sampling, double most, double order) {
  double need = sampling;
  while (need < most && error * std::pow(sampling / need, order) > kLeeErrorTolerance) need *= 2;
  return std::min(need, most);
}

std::array<Vec3, kCantingAxes> canting_axes(double canting_deg, double su, double sv) {
  constexpr int side = 3;
  static_assert(side * side == kCantingAxes);
  const double sigma = deg_to_rad(canting_deg), most = deg_to_rad(89.0);
  std::array<Vec3, kCantingAxes> axes;
  for (int a = 0; a < side; ++a)
    for (int b = 0; b < side; ++b) {
      const double u = frac((a + 0.5) / side + su), v = frac((b + 0.5) / side + sv);
      const double r = sigma * std::sqrt(-2 * std::log1p(-u)), phi = 2 * kPi<> * v;
      const double tx = std::clamp(r * std::cos(phi), -most, most), tz = std::clamp(r * std::sin(phi), -most, most);
      axes[std::size_t(a * side + b)] = glm::normalize(Vec3(std::tan(tx), 1, std::tan(tz)));
    }
  return axes;
}

std::string_view table_kind_name(LeeTableKind k) {
  for (const auto& [kind, name] : kTableKinds)
    if (kind == k) return name;
  return "?";
}
std::string_view angle_axis_name(AngleAxis a) { return a == AngleAxis::angle ? "angle" : "cos"; }
std::string_view radius_scale_name(RadiusScale s) { return s == RadiusScale::log ? "log" : "linear"; }

LeeTableKind parse_table_kind(std::string_view name) {
  for (const auto& [kind, kind_name] : kTableKinds)
    if (kind_name == name) return kind;
  throw UnknownNameError(fmt::format("table '{}': expected rainbow, corona or glory", name));
}

LeeSpec default_lee_spec(LeeTableKind kind) {
  LeeSpec s;
  s.table = kind;
  if (kind != LeeTableKind::rainbow) {
    s.radius_min_um = 1;
    s.radius_max_um = 50;
  }
  if (kind == LeeTableKind::corona) {
    s.angle_min_deg = 0;
    s.angle_max_deg = 20;
  } else if (kind == LeeTableKind::glory) {
    s.angle_min_deg = 160;
    s.angle_max_deg = 180;
  }
  return s;
}

LeeSpec profile_spec(LeeTableKind kind, double radius_um, double a0, double a1, int rows) {
  LeeSpec s = default_lee_spec(kind);
  s.radius_min_um = s.radius_max_um = radius_um;
  s.columns = 1;
  s.angle_min_deg = a0;
  s.angle_max_deg = a1;
  s.rows = rows;
  s.size_spread = 0;
  return s;
}

LeeShapeError::LeeShapeError(Rule rule, int columns, int rows)
    : Error(rule == Rule::one_radius_columns
                ? fmt::format("size ({}, {}): a single radius makes one column; give size=(1, {})", columns, rows, rows)
                : fmt::format("angle_deg: a table of {} rows needs A < B (or one row)", rows)),
      rule_(rule),
      columns_(columns),
      rows_(rows) {}

DropShapeSpec parse_drop_shape(std::string_view text) {
  DropShapeSpec s;
  if (text == "sphere") return s;
  if (text == "beard-chuang") {
    s.kind = DropShapeSpec::Kind::beard_chuang;
    return s;
  }
  if (text.starts_with("spheroid:")) {
    const auto q = parse::number(text.substr(9));
    if (!q)
      throw UnknownNameError(fmt::format("shape '{}': the axis ratio after 'spheroid:' is not a number (give Q in [{:g}, 1])",
                                         text, kMinBowAxisRatio));
    if (!(*q >= kMinBowAxisRatio && *q <= 1))
      throw DomainError::with_message(
          fmt::format("shape '{}': axis_ratio = {:g} is outside [{:g}, 1], the axis ratios (polar over equatorial) "
                      "whose bows the plane-section method describes (docs/non-spherical.md)",
                      text, *q, kMinBowAxisRatio),
          "axis_ratio", *q, kMinBowAxisRatio, 1);
    s.kind = DropShapeSpec::Kind::spheroid;
    s.axis_ratio = *q;
    return s;
  }
  throw UnknownNameError(fmt::format("shape '{}': expected sphere, spheroid:Q (axis ratio Q in [{:g}, 1]) or beard-chuang",
                                     text, kMinBowAxisRatio));
}

std::string drop_shape_name(const DropShapeSpec& s) {
  switch (s.kind) {
    case DropShapeSpec::Kind::sphere: return "sphere";
    case DropShapeSpec::Kind::spheroid: return fmt::format("spheroid:{:g}", s.axis_ratio);
    case DropShapeSpec::Kind::beard_chuang: return "beard-chuang";
  }
  return "?";
}

double drop_axis_ratio(const DropShapeSpec& s, double radius_um) {
  switch (s.kind) {
    case DropShapeSpec::Kind::sphere: return 1;
    case DropShapeSpec::Kind::spheroid: return s.axis_ratio;
    case DropShapeSpec::Kind::beard_chuang: {
      const auto range = scatter::drop_shape_radius_range_m();
      const double a = radius_um * 1e-6;
      if (a >= range[1]) return scatter::axis_ratio(scatter::drop_shape(range[1]));
      if (a >= range[0]) return scatter::axis_ratio(scatter::drop_shape(a));
      // Below the table: the departure from the sphere scaled as a^2 (scatter/drop_shape.hpp).
      static const double q0 = scatter::axis_ratio(scatter::drop_shape(range[0]));
      return 1 - (1 - q0) * (a / range[0]) * (a / range[0]);
    }
  }
  return 1;
}

LeeSpec make_lee_spec(const LeeRequest& r) {
  LeeSpec s = default_lee_spec(r.table);
  s.theory = r.theory;
  if (r.radius_um) {
    s.radius_min_um = (*r.radius_um)[0];
    s.radius_max_um = (*r.radius_um)[1];
  }
  if (r.angle_deg) {
    s.angle_min_deg = (*r.angle_deg)[0];
    s.angle_max_deg = (*r.angle_deg)[1];
  }
  if (r.one_radius()) s.columns = 1;
  if (r.size) {
    s.columns = (*r.size)[0];
    s.rows = (*r.size)[1];
    if (r.one_radius() && s.columns != 1) throw LeeShapeError(LeeShapeError::Rule::one_radius_columns, s.columns, s.rows);
  }
  if (s.rows > 1 && s.angle_min_deg == s.angle_max_deg)
    throw LeeShapeError(LeeShapeError::Rule::one_angle_rows, s.columns, s.rows);
  s.radius_scale = r.radius_scale;
  s.axis = r.axis;
  s.sun_disk_deg = r.sun_disk_deg;
  s.limb_darkening = r.limb_darkening;
  s.size_spread = r.size_spread;
  s.sampling = r.sampling.value_or(1);
  s.sampling_most = r.sampling ? 0.0 : kAutoSamplingMost;
  s.seed = r.seed;
  s.threads = r.threads;
  s.temperature_c = r.temperature_c;
  s.shape = parse_drop_shape(r.shape);
  if (s.shape.spherical()) {
    // The non-spherical drops' parameters, set for spheres, would be ignored.
    const LeeRequest defaults;
    for (const auto& f : lee_params())
      for (const std::string_view name : kShapeOnlyParams)
        if (f.param.name == name && f.get(r) != f.get(defaults)) {
          f.param.check(f.get(r));  // out of its range: that first
          throw Error(shape_only_message(name, f.get(r), name, "shape"));
        }
  }
  s.sun_elevation_deg = r.sun_elevation_deg;
  s.position_deg = r.position_deg;
  s.canting_deg = r.canting_deg;
  s.stokes = r.stokes;
  return s;
}

namespace {

// The work arrays' shape: cells per evaluation (the rows, and the sun's disk beyond the ends: span
// and reach on the rows' axis) and the radius grid's nodes.
struct WorkShape {
  double cells = 1, nodes = 1, span = 0, reach = 0;
};
WorkShape work_shape(const LeeSpec& s) {
  WorkShape w;
  if (s.rows > 1) {
    const bool cosine = s.axis == AngleAxis::cosine;
    w.span = cosine ? std::cos(deg_to_rad(s.angle_min_deg)) - std::cos(deg_to_rad(s.angle_max_deg))
                    : s.angle_max_deg - s.angle_min_deg;
    w.reach = cosine ? deg_to_rad(s.sun_disk_deg) / 2 : s.sun_disk_deg / 2;  // |d cos| <= |d theta|
    w.cells = s.rows + 2 * (w.reach / (w.span / (s.rows - 1)) + 2);
  }
  const auto air = optics::find_medium(s.surrounding_medium);
  const double k_max = 2 * kPi<> * air->n(s.wavelength_min_nm) / (s.wavelength_min_nm * 1e-9);
  w.nodes = s.size_spread == 0 ? double(s.columns) : double(shared_grid(s, k_max).nodes());
  return w;
}

}  // namespace

double estimated_bytes(const LeeSpec& s) {
  const WorkShape w = work_shape(s);
  const double pixels = double(s.rows) * s.columns;
  // compute_lee_table: per column and cell 3 doubles (cell_xyz) and 1 (cell_y_half), per node and cell 1 (node_values),
  // per column and node 1 (column_weight); the table's XYZ (3 doubles a pixel). lee_images: 6 + 3
  // floats and 2 doubles a pixel. Then the encoders' buffers (EXR, PNG): kLeeEncoderBytesPerPixel.
  // The error estimate: 1 double per column and cell (the even wavelengths' Y), Q's too with stokes.
  const double base = kLeeFixedBytes + 32 * double(s.columns) * w.cells + 8 * w.nodes * w.cells +
                      8 * double(s.columns) * w.nodes + (24 + 36 + 16 + kLeeEncoderBytesPerPixel) * pixels;
  // Stokes: Q's cell_xyz, node values (none where Q is a fraction of I) and table (as I's), and 3
  // more EXR channels (floats).
  const double q_nodes = q_is_fraction_of_i(s) ? 0.0 : 8 * w.nodes * w.cells;
  return s.stokes ? base + 32 * double(s.columns) * w.cells + q_nodes + (24 + 12) * pixels : base;
}

void check_table_memory(const std::vector<const LeeSpec*>& specs, const std::string& size_text, SizeSyntax syntax,
                        std::optional<std::uint64_t> available) {
  const LeeSpec* worst = nullptr;
  double need = 0;
  for (const auto* sp : specs)
    if (const double b = estimated_bytes(*sp); b > need) need = b, worst = sp;
  const double avail = double(available ? *available : available_memory_bytes());
  if (!worst || need <= avail) return;
  // The arrays grow with columns x rows: scale both sides alike.
  const double k = std::sqrt(std::max(0.0, avail - kLeeFixedBytes) / (need - kLeeFixedBytes));
  const double columns = std::max(1.0, std::floor(specs.front()->columns * k));
  const double rows = std::max(1.0, std::floor(specs.front()->rows * k));
  const bool cli = syntax == SizeSyntax::cli;
  throw Error(fmt::format("{} {}: the {} table needs about {} of memory and {} is available; about {} would fit",
                          cli ? "--size" : "size", size_text, table_kind_name(worst->table), format_bytes(need),
                          format_bytes(avail),
                          cli ? fmt::format("--size {:.0f}x{:.0f}", columns, rows)
                              : fmt::format("size=({:.0f}, {:.0f})", columns, rows)));
}

void validate(const LeeSpec& s) {
  require_in_range("columns", s.columns, 1, kMaxSide);
  require_in_range("rows", s.rows, 1, kMaxSide);
  require_in_range("radius_um", s.radius_min_um, kMinRadiusUm, kMaxRadiusUm, "a Lee table");
  require_in_range("radius_um", s.radius_max_um, kMinRadiusUm, kMaxRadiusUm, "a Lee table");
  if (s.columns > 1 && !(s.radius_max_um > s.radius_min_um))
    throw DomainError("radius_um", s.radius_max_um, s.radius_min_um, kMaxRadiusUm,
                      fmt::format("a table of {} columns (the largest radius must exceed the smallest, {:g} um)",
                                  s.columns, s.radius_min_um));
  require_in_range("angle_deg", s.angle_min_deg, 0.0, 180.0, "the scattering angle");
  require_in_range("angle_deg", s.angle_max_deg, 0.0, 180.0, "the scattering angle");
  if (s.rows > 1 && !(s.angle_max_deg > s.angle_min_deg))
    throw DomainError("angle_deg", s.angle_max_deg, s.angle_min_deg, 180.0,
                      fmt::format("a table of {} rows (the largest angle must exceed the smallest, {:g} degrees)",
                                  s.rows, s.angle_min_deg));
  // The declared parameters' ranges (lee_params.cpp); a spread other than 0 at least 0.01.
  const Param &sun_disk = lee_param("sun_disk_deg"), &sampling = lee_param("sampling");
  require_in_range("sun_disk_deg", s.sun_disk_deg, sun_disk.lo, sun_disk.hi, "the sun's angular diameter");
  if (s.size_spread != 0)
    require_in_range("size_spread", s.size_spread, 0.01, lee_param("size_spread").hi,
                     "the relative width (0 for one radius)");
  require_in_range("wavelength_nm", s.wavelength_min_nm, color::kCmfMinNm, color::kCmfMaxNm, "the CIE 1931 observer");
  require_in_range("wavelength_nm", s.wavelength_max_nm, s.wavelength_min_nm, color::kCmfMaxNm,
                   "the CIE 1931 observer (at least the shortest wavelength)");
  require_in_range("wavelengths", s.wavelengths, 0, 2000, "wavelength samples (0: one per 10 nm)");
  require_in_range("sampling", s.sampling, sampling.lo, sampling.hi, "the sampling multiplier");
  const auto sun_range = s.sun.range_nm();
  require_in_range("wavelength_nm", s.wavelength_min_nm, sun_range[0], sun_range[1], s.sun.name());
  require_in_range("wavelength_nm", s.wavelength_max_nm, sun_range[0], sun_range[1], s.sun.name());
  const auto drop = optics::find_medium(s.drop_medium);
  const auto air = optics::find_medium(s.surrounding_medium);
  // The media's own ranges (wavelength, temperature) at both ends.
  for (double nm : {s.wavelength_min_nm, s.wavelength_max_nm}) {
    (void)drop->index(nm, s.temperature_c);
    (void)air->n(nm);
  }
  const bool wave_theory = is_wave_theory(s.theory);
  const double x_max = 2 * kPi<> * largest_radius_m(s) * air->n(s.wavelength_min_nm) / (s.wavelength_min_nm * 1e-9);
  const double x_min = 2 * kPi<> * smallest_radius_m(s) * air->n(s.wavelength_max_nm) / (s.wavelength_max_nm * 1e-9);
  const double x_limit = wave_theory ? scatter::kMaxSizeParameter : scatter::kMaxGeometricSizeParameter;
  require_in_range("size_parameter", x_max, scatter::kMinSizeParameter, x_limit,
                   fmt::format("{} (the largest drop at the shortest wavelength)", scatter::theory_name(s.theory)));
  require_in_range("size_parameter", x_min, scatter::kMinSizeParameter, x_limit,
                   fmt::format("{} (the smallest drop at the longest wavelength)", scatter::theory_name(s.theory)));
  if (s.theory.kind == scatter::TheoryKind::Airy && s.table != LeeTableKind::rainbow)
    throw Error(fmt::format("Airy theory describes a rainbow only; a {} table needs mie, debye:P or geometric",
                            table_kind_name(s.table)));
  lee_param("sun_elevation_deg").check(s.sun_elevation_deg);
  lee_param("position_deg").check(s.position_deg);
  lee_param("canting_deg").check(s.canting_deg);
  if (!s.shape.spherical()) {
    if (s.table != LeeTableKind::rainbow || s.theory.kind != scatter::TheoryKind::Airy || s.theory.p > 3)
      throw Error(fmt::format("shape {}: non-spherical drops are computed by Airy theory of their plane section "
                              "(docs/non-spherical.md): a rainbow table with theory airy (primary) or airy:3 "
                              "(secondary), not a {} table with {}",
                              drop_shape_name(s.shape), table_kind_name(s.table), scatter::theory_name(s.theory)));
    if (s.shape.kind == DropShapeSpec::Kind::beard_chuang) {
      // The flattest drop of the population must keep a bow (docs/non-spherical.md).
      const double q = drop_axis_ratio(s.shape, largest_radius_m(s) * 1e6);
      if (q < kMinBowAxisRatio)
        throw DomainError("radius_um", s.radius_max_um, kMinRadiusUm, max_shape_radius_um(s),
                          fmt::format("beard-chuang drops (axis ratio {:.3f} at the population's largest drop; the "
                                      "plane-section method needs at least {:g})",
                                      q, kMinBowAxisRatio));
    }
  }
  // The work arrays: the cells per evaluation (the rows, and the sun's disk beyond the ends) and
  // the nodes' values and columns' weights.
  const WorkShape w = work_shape(s);
  const double cells = w.cells, nodes = w.nodes;
  if (s.rows > 1) {
    const bool cosine = s.axis == AngleAxis::cosine;
    const double reach = w.reach;
    if (cells > kMaxCells) {
      const double min_span = 2 * reach * (s.rows - 1) / (kMaxCells - s.rows - 4);
      const double lo = cosine ? rad_to_deg(safe_acos(std::cos(deg_to_rad(s.angle_min_deg)) - min_span)) : s.angle_min_deg + min_span;
      throw DomainError("angle_deg", s.angle_max_deg, lo, 180.0,
                        fmt::format("{} rows under the sun's {:g} degree disk: the angles must span at least {:.3g} "
                                    "{} (at most {:g} row spacings may fit in the disk)",
                                    s.rows, s.sun_disk_deg, min_span, cosine ? "in cosine" : "degrees",
                                    kMaxCells - s.rows - 4));
    }
  }
  if (nodes * cells > kMaxArrayValues)
    throw DomainError("rows", s.rows, 1, std::floor(kMaxArrayValues / nodes),
                      fmt::format("a table whose radius grid has {:g} nodes (the work arrays are limited to 1 GiB)", nodes));
  if (nodes * s.columns > kMaxArrayValues)
    throw DomainError("columns", s.columns, 1, std::floor(kMaxArrayValues / nodes),
                      fmt::format("a table whose radius grid has {:g} nodes (the work arrays are limited to 1 GiB)", nodes));
}

double max_shape_radius_um(const LeeSpec& s) {
  const auto flat = [&](double r_um) {
    LeeSpec t = s;
    t.radius_max_um = r_um;
    t.radius_min_um = std::min(t.radius_min_um, r_um);
    return drop_axis_ratio(s.shape, largest_radius_m(t) * 1e6) < kMinBowAxisRatio;
  };
  if (!flat(kMaxRadiusUm)) return kMaxRadiusUm;
  double lo = std::ceil(kMinRadiusUm), hi = kMaxRadiusUm;  // whole micrometres: lo keeps a bow, hi does not
  if (flat(lo)) return kMinRadiusUm;
  while (hi - lo > 1) {
    const double mid = std::floor(0.5 * (lo + hi));
    (flat(mid) ? hi : lo) = mid;
  }
  return lo;
}

double max_radius_um(const LeeSpec& s) {
  const auto air = optics::find_medium(s.surrounding_medium);
  const double x_limit = is_wave_theory(s.theory) ? scatter::kMaxSizeParameter : scatter::kMaxGeometricSizeParameter;
  const double k_max = 2 * kPi<> * air->n(s.wavelength_min_nm) / (s.wavelength_min_nm * 1e-9);
  // largest_radius_m's tail factor, inverted; floored to a whole micrometre so validate() accepts it.
  const double r_um = x_limit / k_max / std::exp(kTailSigmas * s.size_spread * 1.01) * 1e6;
  return std::min(kMaxRadiusUm, std::floor(r_um));
}

std::vector<double> column_radii_um(const LeeSpec& s) {
  std::vector<double> r(std::size_t(s.columns));
  for (int c = 0; c < s.columns; ++c) {
    const double t = s.columns > 1 ? double(c) / (s.columns - 1) : 0.0;
    r[std::size_t(c)] = s.radius_scale == RadiusScale::log
                            ? s.radius_min_um * std::pow(s.radius_max_um / s.radius_min_um, t)
                            : s.radius_min_um + t * (s.radius_max_um - s.radius_min_um);
  }
  if (s.columns > 1) r.back() = s.radius_max_um;
  return r;
}

std::vector<double> row_angles_deg(const LeeSpec& s) {
  std::vector<double> a(std::size_t(s.rows));
  for (int i = 0; i < s.rows; ++i) {
    const double t = s.rows > 1 ? double(i) / (s.rows - 1) : 0.0;
    if (s.axis == AngleAxis::angle) {
      a[std::size_t(i)] = s.angle_min_deg + t * (s.angle_max_deg - s.angle_min_deg);
    } else {
      // cos theta increases downward: row 0 holds the largest angle.
      const double c0 = std::cos(deg_to_rad(s.angle_max_deg)), c1 = std::cos(deg_to_rad(s.angle_min_deg));
      a[std::size_t(i)] = rad_to_deg(safe_acos(c0 + t * (c1 - c0)));
    }
  }
  if (s.rows > 1) {
    a.front() = s.axis == AngleAxis::angle ? s.angle_min_deg : s.angle_max_deg;
    a.back() = s.axis == AngleAxis::angle ? s.angle_max_deg : s.angle_min_deg;
  }
  return a;
}

color::Xyz LeeTable::at(int row, int column) const {
  const std::size_t i = (std::size_t(row) * radius_um.size() + std::size_t(column)) * 3;
  return {xyz[i], xyz[i + 1], xyz[i + 2]};
}

color::Xyz LeeTable::q_at(int row, int column) const {
  if (q_xyz.empty()) throw Error("the table has no Stokes Q (compute it with stokes on)");
  const std::size_t i = (std::size_t(row) * radius_um.size() + std::size_t(column)) * 3;
  return {q_xyz[i], q_xyz[i + 1], q_xyz[i + 2]};
}

double LeeTable::dolp(int row, int column) const {
  const double q = q_at(row, column).Y, i = at(row, column).Y;
  return i > 0 ? q / i : 0.0;
}

color::Rgb LeeTable::rgb(int row, int column, bool into_gamut) const {
  const color::Rgb v = color::matmul(xyz_to_rgb, at(row, column));
  return into_gamut ? color::desaturate_into_gamut(v, spec.rgb_space) : v;
}

// ---- compute_lee_table's steps ---------------------------------------------------------------

namespace {

// The rows' axes: theta and cos theta per row (on the cosine axis, its exact sample positions: acos
// and cos do not round-trip), and sin theta (returned) for the sun's disk; the columns' radii.
std::vector<double> set_axes(const LeeSpec& spec, LeeTable& t) {
  t.radius_um = column_radii_um(spec);
  t.angle_deg = row_angles_deg(spec);
  const std::size_t rows = t.angle_deg.size();
  t.cos_angle.resize(rows);
  std::vector<double> sin_angle(rows);
  for (std::size_t i = 0; i < rows; ++i) {
    t.cos_angle[i] = std::cos(deg_to_rad(t.angle_deg[i]));
    sin_angle[i] = std::sin(deg_to_rad(t.angle_deg[i]));
  }
  if (spec.axis == AngleAxis::cosine && rows > 1) {
    const double c0 = std::cos(deg_to_rad(spec.angle_max_deg)), c1 = std::cos(deg_to_rad(spec.angle_min_deg));
    for (std::size_t i = 0; i < rows; ++i) t.cos_angle[i] = c0 + double(i) / double(rows - 1) * (c1 - c0);
  }
  return sin_angle;
}

// The wavelengths (spectral sampling): midpoints of K equal steps, weights S(l) dl times the
// observer, relative to the sun's luminance (returned, one X, Y, Z per wavelength). Sets the table's
// wavelengths, the sun's white and the XYZ -> RGB matrix (Bradford from the sun's white to D65).
std::vector<color::Xyz> sample_wavelengths(const LeeSpec& spec, LeeTable& t) {
  const int K = wavelength_count(spec);
  const double dl = K > 1 ? (spec.wavelength_max_nm - spec.wavelength_min_nm) / K : 1.0;
  t.wavelengths_nm.resize(std::size_t(K));
  std::vector<color::Xyz> weight(static_cast<std::size_t>(K));
  color::Xyz white;
  for (int k = 0; k < K; ++k) {
    const double nm = K > 1 ? spec.wavelength_min_nm + (k + 0.5) * dl
                            : 0.5 * (spec.wavelength_min_nm + spec.wavelength_max_nm);
    t.wavelengths_nm[std::size_t(k)] = nm;
    const color::Xyz c = color::cie1931(nm);
    const double s = spec.sun(nm) * dl;
    weight[std::size_t(k)] = {s * c.X, s * c.Y, s * c.Z};
    white.X += s * c.X;
    white.Y += s * c.Y;
    white.Z += s * c.Z;
  }
  if (!(white.Y > 0)) throw Error("the sampled wavelengths carry no luminance (the observer's y_bar is 0 there)");
  for (auto& w : weight) w = {w.X / white.Y, w.Y / white.Y, w.Z / white.Y};
  t.sun_white = {white.X / white.Y, 1.0, white.Z / white.Y};
  t.xyz_to_rgb = color::multiply(color::xyz_to_rgb_matrix(spec.rgb_space),
                                 color::bradford_adaptation(t.sun_white, color::d65_white()));
  return weight;
}

// The radius grid: the population's nodes, a grid shared by the columns (each column a gamma
// distribution over it), or the columns' own radii (spread 0).
struct Population {
  bool per_column = true;
  RadiusGrid grid;                               // with a spread
  std::size_t nodes = 0;                         // J: radii per wavelength
  std::vector<scatter::SizeDistribution> dists;  // per column, with a spread
};
Population make_population(const LeeSpec& spec, const std::vector<double>& radius_um, const optics::Medium& air) {
  Population p;
  const double w = spec.size_spread;
  p.per_column = w == 0;
  const double k_max = 2 * kPi<> * air.n(spec.wavelength_min_nm) / (spec.wavelength_min_nm * 1e-9);
  if (!p.per_column) p.grid = shared_grid(spec, k_max);
  p.nodes = p.per_column ? radius_um.size() : std::size_t(p.grid.nodes());
  if (!p.per_column)
    for (double r : radius_um) p.dists.push_back(scatter::SizeDistribution::gamma(r * 1e-6, w));
  return p;
}

// Low-discrepancy sequences: the plastic constant's R2 (M. Roberts 2018) for points on the disk,
// the golden ratio's for the grid's shift per wavelength and the jitter inside the cells; each
// starts at a fraction mixed from the seed.
constexpr double kPlastic = 1.32471795724474602596, kGolden = 0.6180339887498949;
struct Sequences {
  explicit Sequences(const LeeSpec& spec)
      : disk_u0(seed_fraction(spec.seed, 1)),
        disk_v0(seed_fraction(spec.seed, 2)),
        shift0(seed_fraction(spec.seed, 3)),
        jitter0(seed_fraction(spec.seed, 4)),
        orient_u0(seed_fraction(spec.seed, 5)),
        orient_v0(seed_fraction(spec.seed, 6)),
        disk(spec.limb_darkening),
        sun_radius(deg_to_rad(spec.sun_disk_deg) / 2) {}
  double a1 = 1 / kPlastic, a2 = 1 / (kPlastic * kPlastic);
  double disk_u0, disk_v0, shift0, jitter0, orient_u0, orient_v0;
  SunDiskSampler disk;
  double sun_radius;  // radians
  // (cos rho, sin rho cos phi) of the n-th point of the disk.
  std::array<double, 2> disk_point(double n) const {
    const double rho = sun_radius * disk.radius_fraction(frac(disk_u0 + n * a1));
    const double phi = 2 * kPi<> * frac(disk_v0 + n * a2);
    return std::array<double, 2>{std::cos(rho), std::sin(rho) * std::cos(phi)};
  }
  // The radius grid's shift at wavelength k.
  double shift(int k) const { return frac(shift0 + k * kGolden); }
  // The jitter of the n-th evaluation's first cell.
  double jitter(double n) const { return frac(jitter0 + n * kGolden); }
  // The shift of the n-th evaluation's canting orientations (drop_orientations).
  std::array<double, 2> orientation_shift(double n) const {
    return {frac(orient_u0 + n * a1), frac(orient_v0 + n * a2)};
  }
};

}  // namespace

std::array<Vec3, kCantingAxes> evaluation_canting_axes(const LeeSpec& spec, double n) {
  const auto shift = Sequences(spec).orientation_shift(n);
  return canting_axes(spec.canting_deg, shift[0], shift[1]);
}

namespace {

// The cells of the angle axis and the disk's kernel from cells to rows (AngleCells).
AngleCells make_angle_cells(const LeeSpec& spec, const LeeTable& t, const std::vector<double>& sin_angle,
                            const Sequences& seq, tbb::task_arena& arena) {
  const std::size_t rows = t.angle_deg.size();
  AngleCells cells;
  cells.cosine = spec.axis == AngleAxis::cosine;
  if (rows < 2) {
    cells.per_evaluation_disk = true;
    cells.count = 1;
    return cells;
  }
  cells.v0 = cells.cosine ? t.cos_angle[0] : t.angle_deg[0];
  cells.dv = ((cells.cosine ? t.cos_angle[rows - 1] : t.angle_deg[rows - 1]) - cells.v0) / double(rows - 1);
  cells.kernel.resize(rows);
  // The disk's points are the same for every row; the rows' shares are computed in parallel, each in
  // order (the same kernel on any thread count).
  const int points = seq.sun_radius > 0 ? kDiskPointsNearAxis : 1;
  std::vector<std::array<double, 2>> disk(std::size_t(points), std::array<double, 2>{1.0, 0.0});
  if (seq.sun_radius > 0)
    for (int q = 0; q < points; ++q) disk[std::size_t(q)] = seq.disk_point(double(q));
  const double near_axis_deg = kDiskAxisRadii * rad_to_deg(seq.sun_radius);
  std::vector<int> row_lo(rows, 0), row_hi(rows, 0);
  arena.execute([&] {
    tbb::parallel_for(std::size_t(0), rows, [&](std::size_t i) {
      std::vector<std::pair<int, double>> share;  // a few cells: a linear search is quickest
      int lo = 0, hi = 0;
      const double to_axis = std::min(t.angle_deg[i], 180 - t.angle_deg[i]);
      const int row_points = to_axis < near_axis_deg ? kDiskPointsNearAxis : kDiskPoints;
      const std::size_t n = seq.sun_radius > 0 ? std::size_t(row_points) : 1;
      for (std::size_t q = 0; q < n; ++q) {
        const auto& d = disk[q];
        const double mu = std::clamp(t.cos_angle[i] * d[0] + sin_angle[i] * d[1], -1.0, 1.0);
        const double v = cells.cosine ? mu : rad_to_deg(std::acos(mu));
        const int cell = int(std::floor((v - cells.v0) / cells.dv + 0.5));
        auto it = std::find_if(share.begin(), share.end(), [cell](const auto& e) { return e.first == cell; });
        if (it == share.end()) {
          it = share.insert(share.end(), {cell, 0.0});
          lo = share.size() == 1 ? cell : std::min(lo, cell);
          hi = share.size() == 1 ? cell : std::max(hi, cell);
        }
        it->second += 1.0 / double(n);
      }
      std::sort(share.begin(), share.end());
      cells.kernel[i] = std::move(share);
      row_lo[i] = lo;
      row_hi[i] = hi;
    });
  });
  const int lo = std::min(0, *std::min_element(row_lo.begin(), row_lo.end()));
  const int hi = std::max(int(rows) - 1, *std::max_element(row_hi.begin(), row_hi.end()));
  cells.first = lo;
  cells.count = hi - lo + 1;
  return cells;
}

// The point at fraction f of cell c (c counted from cells.first) as theta (radians) and mu = cos
// theta; only what the theory needs is computed (Mie sums take mu, the ray theories theta).
void cell_point(const AngleCells& cells, bool wants_mu, std::size_t c, double f, double& theta, double& mu) {
  const double v = cells.v0 + (double(int(c) + cells.first) + f - 0.5) * cells.dv;
  if (cells.cosine) {
    mu = v < -1 ? -2 - v : (v > 1 ? 2 - v : v);  // beyond an axis, the mirror direction
    if (!wants_mu) theta = std::acos(mu);
    return;
  }
  const double d = v < 0 ? -v : (v > 180 ? 360 - v : v);  // beyond an axis, the mirror angle
  theta = deg_to_rad(d);
  if (wants_mu) mu = std::cos(theta);
}

// Estimated work per wavelength (for progress): terms ~ x for the wave theories, from every
// (J / 64)-th node; `total` their sum.
std::vector<double> work_per_wavelength(const LeeTable& t, const Population& pop, const Sequences& seq,
                                        bool wants_mu, double& total) {
  const int K = int(t.wavelengths_nm.size());
  const std::size_t J = pop.nodes;
  const auto node_radius_m = [&](std::size_t j, int k) {
    return pop.per_column ? t.radius_um[j] * 1e-6 : std::exp(pop.grid.ln_radius(j, seq.shift(k)));
  };
  std::vector<double> k_work(static_cast<std::size_t>(K));
  total = 0;
  for (int k = 0; k < K; ++k) {
    double sum = 0;
    for (std::size_t j = 0; j < J; j += std::max<std::size_t>(1, J / 64))
      sum += wants_mu ? 10 + 2 * kPi<> * node_radius_m(j, k) / (t.wavelengths_nm[std::size_t(k)] * 1e-9) : 1.0;
    k_work[std::size_t(k)] = sum;
    total += sum;
  }
  return k_work;
}

// The drop's index relative to air at every wavelength, within the domain all four theories
// share (the Debye series, Airy theory and geometric optics stop at Re m = 10, Im m = 1; the
// Mie solver goes further), checked before any work.
void check_drop_index(const LeeSpec& spec, const std::vector<double>& wavelengths_nm, const optics::Medium& drop,
                      const optics::Medium& air) {
  for (const double nm : wavelengths_nm) {
    const scatter::Complex m = drop.index(nm, spec.temperature_c) / air.n(nm);
    require_in_range("m_real", m.real(), scatter::kMinIndexReal, scatter::kMaxIndexReal, "a Lee table's drop index");
    require_in_range("m_imag", m.imag(), 0.0, scatter::kMaxIndexImag, "a Lee table's drop index");
  }
}

// The work arrays, reused from one wavelength to the next.
struct WorkArrays {
  // node_q: Q's own node values (stokes, unless Q is a fraction of I).
  WorkArrays(std::size_t J, std::size_t R, std::size_t cols, bool stokes, bool node_q_values)
      : node_ln(J), node_a(J), node_width(J), cell_xyz(cols * R * 3, 0.0), node_values(J * R),
        cell_q_xyz(stokes ? cols * R * 3 : 0, 0.0), node_q(stokes && node_q_values ? J * R : 0), node_used(J, 1),
        column_first(cols), column_count(cols), cell_y_half(cols * R, 0.0), cell_qy_half(stokes ? cols * R : 0, 0.0) {}
  std::vector<double> node_ln, node_a, node_width;  // this wavelength's nodes
  std::vector<double> cell_xyz;                     // per column and cell, before the disk kernel
  std::vector<double> node_values;                  // T at each node and cell, this wavelength
  std::vector<double> cell_q_xyz, node_q;           // the same for Q (stokes only; else empty)
  std::vector<char> node_used;
  std::vector<double> column_weight;  // (column, node) area weights, this wavelength
  std::vector<std::size_t> column_first, column_count;
  // The error estimate (LeeTable::error): Y (and Q's Y) per column and cell over the even-numbered
  // wavelengths alone, and their weights' sum; the odd ones are the rest of cell_xyz.
  std::vector<double> cell_y_half, cell_qy_half;
  double half_weight_y = 0;
  // Non-spherical drops: each (node, orientation)'s 3-D bow edge at the last wavelength, the seed of
  // the next one's search (bow_seeded: found), and per node the smallest axis ratio whose search
  // failed (2 if none did): there the section's angle stands.
  std::vector<scatter::SpheroidBow> bow_seed;
  std::vector<char> bow_seeded;
  std::vector<double> bow_fallback_q;
};

// This wavelength's nodes: radius and width in ln a (each an inverse of the grid's cumulative
// density: found once here, not once per column that uses the node).
void place_nodes(const Population& pop, const LeeTable& t, double shift, WorkArrays& w) {
  for (std::size_t j = 0; j < pop.nodes; ++j) {
    const double ln_a = pop.per_column ? std::log(t.radius_um[j] * 1e-6) : pop.grid.ln_radius(j, shift);
    w.node_ln[j] = ln_a;
    w.node_a[j] = std::exp(ln_a);
    w.node_width[j] = pop.per_column ? 1.0 : pop.grid.width_at(ln_a);
  }
}

// Each column's weights over the shared grid's nodes: number density per unit ln a (n(a) a) x the
// node's width in ln a x a^2 (projected area), summed to 1; and the nodes any column uses.
void weigh_columns(const Population& pop, const LeeTable& t, double spread, double shift, tbb::task_arena& arena,
                   WorkArrays& wa) {
  const std::size_t cols = t.radius_um.size(), J = pop.nodes;
  std::fill(wa.node_used.begin(), wa.node_used.end(), 0);
  wa.column_weight.assign(cols * J, 0.0);
  arena.execute([&] {
    tbb::parallel_for(std::size_t(0), cols, [&](std::size_t c) {
      // Gamma: n(a) a^3 ~ exp((alpha + 2) ln a - a / beta), taken relative to its peak at
      // a* = (alpha + 2) beta; only nodes within kTailSigmas widths of the column are kept.
      const double alpha = pop.dists[c].alpha(), beta = pop.dists[c].beta();
      const double peak_a = (alpha + 2) * beta, ln_peak = std::log(peak_a);
      const double centre = std::log(t.radius_um[c] * 1e-6);
      const auto [first, last] =
          pop.grid.nodes_between(centre - kTailSigmas * spread, centre + kTailSigmas * spread, shift);
      double* cw = &wa.column_weight[c * J];
      double sum = 0;
      for (std::size_t j = first; j <= last; ++j) {
        const double v = std::exp((alpha + 2) * (wa.node_ln[j] - ln_peak) - (wa.node_a[j] - peak_a) / beta);
        cw[j] = v > kNegligibleWeight ? v * wa.node_width[j] : 0.0;
        sum += cw[j];
      }
      if (!(sum > 0))
        throw Error(fmt::format("the radius grid does not resolve the column of {:g} um", t.radius_um[c]));
      std::size_t used_first = last, used_last = first;
      for (std::size_t j = first; j <= last; ++j) {
        cw[j] /= sum;
        if (cw[j] != 0) {
          used_first = std::min(used_first, j);
          used_last = std::max(used_last, j);
        }
      }
      wa.column_first[c] = used_first;
      wa.column_count[c] = used_last - used_first + 1;
    });
  });
  for (std::size_t c = 0; c < cols; ++c)
    for (std::size_t j = wa.column_first[c]; j < wa.column_first[c] + wa.column_count[c]; ++j)
      if (wa.column_weight[c * J + j] != 0) wa.node_used[j] = 1;
}

// One wavelength's single drops, as the kernel sees them.
struct Wavelength {
  int k = 0, K = 0;         // its index, of K
  scatter::Complex m;       // the drop's index relative to air
  double wavenumber = 0;    // 2 pi n_air / lambda, m^-1
};

// Non-spherical drops: the directions of their symmetry axes and the weights. Without canting, one
// vertical axis. With canting, the kCantingAxes axes of canting_axes for each evaluation n (one node
// at one wavelength), equal weights, shifted by the n-th point of a 2-D low-discrepancy sequence
// (Cranley-Patterson rotation), so that each evaluation's nine are balanced and every evaluation has
// its own. A table's columns average their nodes over all wavelengths, so each pixel sees nodes x
// wavelengths x 9 orientations, and the table's error estimate (its even- and odd-numbered
// wavelengths as two tables) includes the orientations' sampling, whose share falls about as
// 1 / sqrt(sampling). A fixed product rule cannot do this: the bow moves at first order in the tilt
// (Moebius's shift; 0.35 degrees per degree at the top for Q = 0.9), by more than its width, and the
// 3 x 3 Gauss-Hermite rule hydrolux had was 5-87% RMS off (tests/atmos/test_claims_canting_rule.cpp).
struct Orientation {
  Vec3 axis;
  double weight;
};
std::size_t orientation_count(const LeeSpec& spec) {
  return spec.shape.spherical() || spec.canting_deg == 0 ? 1 : std::size_t(kCantingAxes);
}
// The axes for the evaluation whose sequence shift is (su, sv) (Sequences::orientation_shift).
void drop_orientations(const LeeSpec& spec, double su, double sv, std::vector<Orientation>& o) {
  o.clear();
  if (orientation_count(spec) == 1) {
    o.push_back({Vec3(0, 1, 0), 1.0});
    return;
  }
  for (const Vec3& axis : canting_axes(spec.canting_deg, su, sv)) o.push_back({axis, 1.0 / kCantingAxes});
}

// Below this axis ratio a note warns of the rays beyond the fold near the feet (compute_lee_table).
constexpr double kUmbilicNoteAxisRatio = 0.78;

// One non-spherical drop (equal-volume radius radius_um, size parameter x): the plane-section Airy
// bow of each orientation, moved to the bow's angle by exact 3-D ray optics (scatter::spheroid_bow:
// the section's rays stay in the plane, the real ones do not), weighted; T = i / (pi x^2) per the
// equal-volume sphere's cross-section. The profile's width, Fresnel weights and normalisation stay
// the section's. A section without a bow of this order adds nothing. seeds / seeded: this node's
// edges at the last wavelength (one per orientation), updated; where the 3-D search fails the
// section's angle is kept and *fallback_q lowered to the drop's axis ratio.
// With `out_q`, Q as well: each orientation's intensity times its degree of polarisation
// (w_perpendicular - w_parallel) / (w_perpendicular + w_parallel), the section's two weights.
void section_bow(const LeeSpec& spec, const std::vector<Orientation>& orientations, scatter::Complex m, double x,
                 double radius_um, const std::vector<double>& theta, double norm, double* out, double* out_q,
                 scatter::SpheroidBow* seeds, char* seeded, double* fallback_q) {
  const double q = drop_axis_ratio(spec.shape, radius_um);
  const double e = deg_to_rad(spec.sun_elevation_deg), psi = deg_to_rad(spec.position_deg);
  std::fill(out, out + theta.size(), 0.0);
  if (out_q) std::fill(out_q, out_q + theta.size(), 0.0);
  for (std::size_t k = 0; k < orientations.size(); ++k) {
    const Orientation& o = orientations[k];
    const auto bow = scatter::section_rainbow(m.real(), spec.theory.p, scatter::spheroid_section(q, o.axis, e, psi));
    if (!bow) continue;
    scatter::SectionAiry a = scatter::section_airy(*bow, x, m.imag());
    const auto edge =
        scatter::spheroid_bow(m.real(), spec.theory.p, q, o.axis, e, psi, *bow, seeded[k] ? &seeds[k] : nullptr);
    if (edge) {
      a.theta_r = edge->scattering_angle;
      seeds[k] = *edge;
      seeded[k] = 1;
    } else {
      *fallback_q = std::min(*fallback_q, q);
    }
    if (!out_q) {
      for (std::size_t i = 0; i < theta.size(); ++i)
        out[i] += o.weight * norm * scatter::section_airy_intensity(a, theta[i]);
      continue;
    }
    const double wsum = a.weight_perpendicular + a.weight_parallel;
    const double pol = wsum > 0 ? (a.weight_perpendicular - a.weight_parallel) / wsum : 0.0;
    for (std::size_t i = 0; i < theta.size(); ++i) {
      const double v = o.weight * norm * scatter::section_airy_intensity(a, theta[i]);
      out[i] += v;
      out_q[i] += v * pol;
    }
  }
}

// The kernel (per-radius scattering): every used node at every cell, T = i / (pi x^2),
// i = (|S1|^2 + |S2|^2) / 2, at a jittered point of the cell (or, for one row, at the row's angle
// to one point of the disk).
void scatter_nodes(const LeeSpec& spec, const LeeTable& t, const std::vector<double>& sin_angle,
                   const AngleCells& cells, const Sequences& seq, const Wavelength& wl, tbb::task_arena& arena,
                   WorkArrays& wa, std::atomic<std::int64_t>& terms, std::atomic<std::int64_t>& evaluations) {
  const std::size_t J = wa.node_a.size(), R = std::size_t(cells.count);
  const bool wants_mu = is_wave_theory(spec.theory);
  const int k = wl.k, K = wl.K;
  const scatter::Complex m = wl.m;
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, J, 1), [&](const tbb::blocked_range<std::size_t>& range) {
      thread_local Scratch sc;
      thread_local std::vector<Orientation> orientations;
      sc.resize(R);
      for (std::size_t j = range.begin(); j != range.end(); ++j) {
        double* out = &wa.node_values[j * R];
        double* out_q = wa.node_q.empty() ? nullptr : &wa.node_q[j * R];
        if (!wa.node_used[j]) continue;
        const double x = wl.wavenumber * wa.node_a[j];
        // Each node's evaluations are consecutive in the sequences (wavelength fastest), so the
        // K points one column gets are spread over the cell and the disk for any J.
        const double n = double(j * std::size_t(K) + std::size_t(k));
        if (cells.per_evaluation_disk) {
          const auto d = seq.disk_point(n);
          sc.mu[0] = std::clamp(t.cos_angle[0] * d[0] + sin_angle[0] * d[1], -1.0, 1.0);
          sc.theta[0] = std::acos(sc.mu[0]);
        } else {
          const double j0 = seq.jitter(n);
          for (std::size_t c = 0; c < R; ++c)
            cell_point(cells, wants_mu, c, frac(j0 + double(c) * seq.a1), sc.theta[c], sc.mu[c]);
        }
        const double norm = 1 / (kPi<> * x * x);
        switch (spec.theory.kind) {
          case scatter::TheoryKind::Mie:
          case scatter::TheoryKind::Debye: {
            if (spec.theory.kind == scatter::TheoryKind::Mie)
              scatter::mie_coefficients(m, x, sc.coef);
            else
              sc.coef = scatter::debye_coefficients(m, x, spec.theory.p);
            scatter::mie_amplitudes(sc.coef, sc.mu, sc.s1, sc.s2, 1);
            terms += sc.coef.terms();
            for (std::size_t i = 0; i < R; ++i) out[i] = 0.5 * (std::norm(sc.s1[i]) + std::norm(sc.s2[i])) * norm;
            if (out_q)
              for (std::size_t i = 0; i < R; ++i) out_q[i] = 0.5 * (std::norm(sc.s1[i]) - std::norm(sc.s2[i])) * norm;
            break;
          }
          case scatter::TheoryKind::Airy: {
            if (!spec.shape.spherical()) {
              const std::size_t O = orientation_count(spec);
              const auto shift = seq.orientation_shift(n);
              drop_orientations(spec, shift[0], shift[1], orientations);
              // Each evaluation has its own orientations: an edge found for another axis is no seed.
              if (O > 1) std::fill_n(&wa.bow_seeded[j * O], O, char(0));
              section_bow(spec, orientations, m, x, wa.node_a[j] * 1e6, sc.theta, norm, out, out_q,
                          &wa.bow_seed[j * O], &wa.bow_seeded[j * O], &wa.bow_fallback_q[j]);
              break;
            }
            // Q = (|eps_1|^2 - |eps_2|^2) / 2 * amplitude^2 Ai^2: I times airy_polarisation, applied
            // to the columns' sums (accumulate_columns).
            const scatter::AiryRainbow rb = scatter::airy_rainbow(m.real(), x, spec.theory.p, m.imag());
            for (std::size_t i = 0; i < R; ++i) out[i] = scatter::airy_intensity(rb, sc.theta[i]) * norm;
            break;
          }
          case scatter::TheoryKind::Geometric: {
            scatter::geometric_amplitudes(m, x, spec.theory.p, sc.theta, sc.s1, sc.s2, /*diffraction=*/true);
            for (std::size_t i = 0; i < R; ++i) out[i] = 0.5 * (std::norm(sc.s1[i]) + std::norm(sc.s2[i])) * norm;
            if (out_q)
              for (std::size_t i = 0; i < R; ++i) out_q[i] = 0.5 * (std::norm(sc.s1[i]) - std::norm(sc.s2[i])) * norm;
            break;
          }
        }
        ++evaluations;
      }
    });
  });
}

// The accumulation (spectral -> colour): each column's weighted mean over the nodes, into X, Y, Z
// with this wavelength's weight `wk`: I (node_values into cell_xyz) and, with Stokes, Q into
// cell_q_xyz, in one pass over the blocks of columns: as `q_fraction` times each column's I where Q
// is a fraction of I (q_is_fraction_of_i; no sum of its own), else from Q's node values (node_q),
// summed after I's with the block's node range and weights. Neighbouring columns share most of their
// nodes, so a block of them is summed together: each node's values are read once per block (memory
// traffic, not arithmetic, bounds this; summing I and Q node by node, both rows of sums at once,
// measured no faster than one after the other).
void accumulate_columns(const Population& pop, std::size_t cols, std::size_t R, const color::Xyz& wk,
                        double q_fraction, bool even, tbb::task_arena& arena, WorkArrays& wa) {
  const std::size_t J = pop.nodes;
  constexpr std::size_t kBlock = 8;
  const bool q_from_i = !wa.cell_q_xyz.empty() && wa.node_q.empty();
  // The node values summed, and where their colour goes: I, then Q's own (stokes, node_q).
  struct Part {
    const std::vector<double>* values;
    std::vector<double>*xyz, *half;
  };
  std::vector<Part> parts{{&wa.node_values, &wa.cell_xyz, &wa.cell_y_half}};
  if (!wa.node_q.empty()) parts.push_back({&wa.node_q, &wa.cell_q_xyz, &wa.cell_qy_half});
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, (cols + kBlock - 1) / kBlock, 1),
                      [&](const tbb::blocked_range<std::size_t>& range) {
      std::vector<double> acc(kBlock * R);
      for (std::size_t b = range.begin(); b != range.end(); ++b) {
        const std::size_t c0 = b * kBlock, c1 = std::min(cols, c0 + kBlock);
        std::size_t first = J, last = 0;
        if (!pop.per_column)
          for (std::size_t c = c0; c < c1; ++c) {
            first = std::min(first, wa.column_first[c]);
            last = std::max(last, wa.column_first[c] + wa.column_count[c] - 1);
          }
        for (const auto& [node_values, cell_xyz, cell_half] : parts) {
          const std::vector<double>& values = *node_values;
          std::fill(acc.begin(), acc.end(), 0.0);
          if (pop.per_column) {
            for (std::size_t c = c0; c < c1; ++c) std::copy_n(&values[c * R], R, &acc[(c - c0) * R]);
          } else {
            for (std::size_t j = first; j <= last; ++j) {
              const double* v = &values[j * R];
              for (std::size_t c = c0; c < c1; ++c) {
                const double wj = wa.column_weight[c * J + j];
                if (wj == 0) continue;
                axpy(&acc[(c - c0) * R], v, wj, R);
              }
            }
          }
          for (std::size_t c = c0; c < c1; ++c) {
            const double* col = &acc[(c - c0) * R];
            double* px = &(*cell_xyz)[c * R * 3];
            for (std::size_t i = 0; i < R; ++i, px += 3) {
              px[0] += wk.X * col[i];
              px[1] += wk.Y * col[i];
              px[2] += wk.Z * col[i];
            }
            if (even) axpy(&(*cell_half)[c * R], col, wk.Y, R);
            if (!q_from_i) continue;  // (parts is then I alone)
            double* qx = &wa.cell_q_xyz[c * R * 3];
            for (std::size_t i = 0; i < R; ++i, qx += 3) {
              const double q = q_fraction * col[i];
              qx[0] += wk.X * q;
              qx[1] += wk.Y * q;
              qx[2] += wk.Z * q;
            }
            if (even) axpy(&wa.cell_qy_half[c * R], col, q_fraction * wk.Y, R);
          }
        }
      }
    });
  });
}

// The sun's disk: each row is its kernel's weighted sum of the cells (one row: its cell).
void apply_disk(const AngleCells& cells, const std::vector<double>& cell_xyz, const LeeTable& t,
                std::vector<double>& xyz) {
  const std::size_t rows = t.angle_deg.size(), cols = t.radius_um.size(), R = std::size_t(cells.count);
  xyz.assign(rows * cols * 3, 0.0);
  for (std::size_t c = 0; c < cols; ++c) {
    const double* col = &cell_xyz[c * R * 3];
    for (std::size_t i = 0; i < rows; ++i) {
      double* dst = &xyz[(i * cols + c) * 3];
      if (cells.per_evaluation_disk) {
        std::copy_n(col, 3, dst);
        continue;
      }
      for (const auto& [cell, weight_i] : cells.kernel[i])
        for (int q = 0; q < 3; ++q) dst[q] += weight_i * col[std::size_t(cell - cells.first) * 3 + std::size_t(q)];
    }
  }
}

// LeeTable::error: the table of the even-numbered wavelengths alone against the odd-numbered (each
// scaled to the whole's luminance weight), through the same disk kernel: half their difference at
// each pixel, its root mean square over the table relative to that of Y. Nothing with one wavelength.
LeeError half_sum_error(const AngleCells& cells, const WorkArrays& wa, const LeeTable& t, double all_weight_y) {
  LeeError e;
  const double wa_y = wa.half_weight_y, wb_y = all_weight_y - wa.half_weight_y;
  if (t.wavelengths_nm.size() < 2 || !(wa_y > 0) || !(wb_y > 0)) return e;
  const std::size_t rows = t.angle_deg.size(), cols = t.radius_um.size(), R = std::size_t(cells.count);
  const auto rms = [&](const std::vector<double>& half, const std::vector<double>& whole) {
    double num = 0, den = 0;
    for (std::size_t c = 0; c < cols; ++c) {
      const double* col = &half[c * R];
      for (std::size_t i = 0; i < rows; ++i) {
        double a = 0;
        if (cells.per_evaluation_disk) {
          a = col[0];
        } else {
          for (const auto& [cell, w] : cells.kernel[i]) a += w * col[std::size_t(cell - cells.first)];
        }
        const double all = whole[(i * cols + c) * 3 + 1], y = t.xyz[(i * cols + c) * 3 + 1];
        const double d = (a * all_weight_y / wa_y - (all - a) * all_weight_y / wb_y) / 2;
        num += d * d;
        den += y * y;
      }
    }
    return den > 0 ? std::sqrt(num / den) : 0.0;
  };
  e.luminance_rms = rms(wa.cell_y_half, t.xyz);
  if (!t.q_xyz.empty()) e.q_rms = rms(wa.cell_qy_half, t.q_xyz);
  return e;
}

}  // namespace

double supernumerary_spacing_deg(double n, double x, int p) {
  constexpr double kZ2 = 3.248198, kZ3 = 4.820099;  // -a'_2, -a'_3
  return rad_to_deg((kZ3 - kZ2) / scatter::airy_angular_scale(n, x, p));
}

std::vector<std::string> lee_resolution_notes(const LeeSpec& spec) {
  std::vector<std::string> notes;
  if (spec.table != LeeTableKind::rainbow) return notes;
  const auto drop = optics::find_medium(spec.drop_medium);
  const auto air = optics::find_medium(spec.surrounding_medium);
  const std::vector<double> radii = column_radii_um(spec);
  const int rows = std::max(spec.rows, 1);
  // Airy's maxima of Ai(-z)^2 at z = -a'_k (A&S Table 10.13): the second supernumerary's, and the spacing.
  constexpr double kZ3 = 4.820099, kSpacingZ = kZ3 - 3.248198;
  const scatter::SphereProblem short_wave = scatter::sphere_problem(1, spec.wavelength_min_nm, *drop, *air,
                                                                    spec.temperature_c);
  const double n = short_wave.m.real();
  for (const int p : {2, 3}) {
    const double bow_deg = rad_to_deg(scatter::rainbow_angle(n, p));
    if (!(bow_deg >= spec.angle_min_deg && bow_deg <= spec.angle_max_deg) || rows < 2) continue;
    // The fringes' spacing (deg) of a column's drops at the shortest wavelength, where it is narrowest.
    const auto spacing_deg = [&](double radius_um) { return supernumerary_spacing_deg(n, short_wave.x * radius_um, p); };
    double largest = 0;  // the largest drops whose fringes the sun's disk leaves
    for (const double r : radii)
      if (spacing_deg(r) >= spec.sun_disk_deg) largest = std::max(largest, r);
    if (!(largest > 0)) continue;
    const double spacing = spacing_deg(largest);
    const double span = spec.angle_max_deg - spec.angle_min_deg;
    const double step = spec.axis == AngleAxis::angle
                            ? span / (rows - 1)
                            : rad_to_deg((std::cos(deg_to_rad(spec.angle_min_deg)) -
                                          std::cos(deg_to_rad(spec.angle_max_deg))) /
                                         (rows - 1) / std::sin(deg_to_rad(bow_deg)));
    if (step > spacing / 4)
      notes.push_back(fmt::format(
          "the rows are {:.3g} deg apart at the {} bow ({:.1f} deg), more than a quarter of the {:.3g} deg spacing of "
          "the supernumeraries of its {:.4g} um drops{}: they are aliased; give {{size}} with at least {} rows, or a "
          "narrower {{angle_deg}}",
          step, p == 2 ? "primary" : "secondary", bow_deg, spacing, largest,
          spec.sun_disk_deg > 0 ? ", the largest whose fringes the sun's disk leaves" : "",
          int(std::ceil(double(rows - 1) * step / (spacing / 4))) + 1));
  }
  if (spec.theory.kind == scatter::TheoryKind::Airy) {
    const scatter::SphereProblem long_wave = scatter::sphere_problem(1, spec.wavelength_max_nm, *drop, *air,
                                                                      spec.temperature_c);
    const double smallest = *std::min_element(radii.begin(), radii.end());
    const double from_um = kAiryMinX / long_wave.x;
    if (smallest < from_um)
      notes.push_back(fmt::format(
          "Airy theory for drops of {:.3g} um (x = {:.0f} at {:g} nm): below x = {:g} ({:.0f} um) its first "
          "supernumerary is ~20% off Mie's (docs/rainbow-theories.md, \"Validity\"); give {{radius_um}} from "
          "{:.0f}{}",
          smallest, long_wave.x * smallest, spec.wavelength_max_nm, kAiryMinX, from_um, std::ceil(from_um),
          spec.shape.spherical() ? ", or {theory} mie" : ""));
  }
  if (spec.size_spread == 0 && radii.size() > 1) {
    double jump = 0;  // the largest relative step between neighbouring columns
    for (std::size_t i = 1; i < radii.size(); ++i) jump = std::max(jump, radii[i] / radii[i - 1] - 1);
    // The fringe at z moves as a^(-2/3): (2/3) jump z between columns, against half the spacing.
    if (2.0 / 3 * jump * kZ3 > kSpacingZ / 2)
      notes.push_back(fmt::format(
          "neighbouring columns are up to {:.0f}% apart in radius with no size spread: the supernumeraries jump by "
          "more than half their spacing from one column to the next; give more columns ({{size}}) or a "
          "{{size_spread}}",
          100 * jump));
  }
  return notes;
}

namespace {

LeeTable compute_lee_table_at(const LeeSpec& spec, const ProgressFn& progress) {
  LeeTable t;
  t.spec = spec;
  t.notes = lee_resolution_notes(spec);
  const std::vector<double> sin_angle = set_axes(spec, t);
  const std::size_t cols = t.radius_um.size();
  const auto drop = optics::find_medium(spec.drop_medium);
  const auto air = optics::find_medium(spec.surrounding_medium);
  const std::vector<color::Xyz> weight = sample_wavelengths(spec, t);
  const int K = int(t.wavelengths_nm.size());
  const Population pop = make_population(spec, t.radius_um, *air);
  const std::size_t J = pop.nodes;
  t.work.wavelengths = K;
  t.work.radius_nodes = int(J);
  const Sequences seq(spec);
  tbb::task_arena arena(spec.threads > 0 ? spec.threads : tbb::task_arena::automatic);
  const AngleCells cells = make_angle_cells(spec, t, sin_angle, seq, arena);
  const std::size_t R = std::size_t(cells.count);
  double total_work = 0;
  const std::vector<double> k_work = work_per_wavelength(t, pop, seq, is_wave_theory(spec.theory), total_work);
  WorkArrays wa(J, R, cols, spec.stokes, !q_is_fraction_of_i(spec));
  if (!spec.shape.spherical()) {
    const std::size_t O = orientation_count(spec);
    wa.bow_seed.resize(J * O);
    wa.bow_seeded.assign(J * O, 0);
    wa.bow_fallback_q.assign(J, 2.0);
  }
  std::atomic<std::int64_t> terms{0}, evaluations{0};
  check_drop_index(spec, t.wavelengths_nm, *drop, *air);

  double done_work = 0;
  for (int k = 0; k < K; ++k) {
    const double nm = t.wavelengths_nm[std::size_t(k)];
    const std::complex<double> n_drop = drop->index(nm, spec.temperature_c);
    const double n_air = air->n(nm);
    const Wavelength wl{k, K, n_drop / n_air, 2 * kPi<> * n_air / (nm * 1e-9)};
    const double shift = seq.shift(k);
    place_nodes(pop, t, shift, wa);
    if (!pop.per_column) weigh_columns(pop, t, spec.size_spread, shift, arena, wa);
    scatter_nodes(spec, t, sin_angle, cells, seq, wl, arena, wa, terms, evaluations);
    const double q_fraction = spec.stokes && q_is_fraction_of_i(spec) ? airy_polarisation(wl.m, spec.theory.p) : 0.0;
    accumulate_columns(pop, cols, R, weight[std::size_t(k)], q_fraction, k % 2 == 0, arena, wa);
    if (k % 2 == 0) wa.half_weight_y += weight[std::size_t(k)].Y;
    done_work += k_work[std::size_t(k)];
    if (progress) progress(done_work / total_work, fmt::format("{:.0f} nm", nm));
  }

  apply_disk(cells, wa.cell_xyz, t, t.xyz);
  if (spec.stokes) apply_disk(cells, wa.cell_q_xyz, t, t.q_xyz);
  double all_weight_y = 0;
  for (const auto& w : weight) all_weight_y += w.Y;
  t.error = half_sum_error(cells, wa, t, all_weight_y);
  if (t.error.luminance_rms && *t.error.luminance_rms > kLeeErrorTolerance) {
    // Canted tables' orientations are drawn at random per evaluation: their share of the error falls
    // about as 1 / sqrt(sampling) (tests/atmos/test_claims_canting_rule.cpp).
    const bool canted = orientation_count(spec) > 1;
    const double most = lee_param("sampling").hi;
    const double need = sampling_for_tolerance(*t.error.luminance_rms, spec.sampling, most, canted ? 0.5 : 1.0);
    // With the wavelengths given, sampling sets the radius grid alone.
    t.notes.push_back(
        spec.wavelengths > 0
            ? fmt::format("the table's estimated error is {:.2g}% RMS in luminance, more than {:g}%: give more "
                          "{{wavelengths}} than {} or a larger {{sampling}}",
                          100 * *t.error.luminance_rms, 100 * kLeeErrorTolerance, spec.wavelengths)
            : fmt::format("the table's estimated error is {:.2g}% RMS in luminance, more than {:g}%: give "
                          "{{sampling}} {:g}{} (the error falls about as {})",
                          100 * *t.error.luminance_rms, 100 * kLeeErrorTolerance, need,
                          need >= most && spec.sampling < most ? ", the most" : "",
                          canted ? "1 / sqrt({sampling}) with {canting_deg}" : "1 / {sampling}"));
  }
  // Near the method's limit the fold is close to the hyperbolic umbilic: measured by brute-force ray
  // tracing (tests/scatter/test_claims_section_3d.cpp), for axis ratios below 0.78 near the feet with
  // a low sun rays entering at 70-75 degrees of incidence reach up to ~2 degrees beyond the fold.
  if (!wa.bow_fallback_q.empty() && spec.theory.p == 2 && std::abs(spec.position_deg - 90) <= 15 &&
      spec.sun_elevation_deg <= 10) {
    const double flattest = drop_axis_ratio(spec.shape, largest_radius_m(spec) * 1e6);
    if (flattest < kUmbilicNoteAxisRatio)
      t.notes.push_back(fmt::format(
          "drops flatter than {:g} (here down to {:.3f}) near the feet of the bow ({{position_deg}} {:g}, "
          "{{sun_elevation_deg}} {:g}): beside the bow's fold, rays entering near the drop's rim reach up to ~2 "
          "degrees further out (the hyperbolic umbilic is near, docs/non-spherical.md); the table has the fold's bow "
          "only; a rounder {{shape}} avoids it",
          kUmbilicNoteAxisRatio, flattest, spec.position_deg, spec.sun_elevation_deg));
  }
  if (orientation_count(spec) > 1 && !t.error.luminance_rms)
    t.notes.push_back(fmt::format(
        "{{canting_deg}} {:g} with one wavelength: each evaluation averages the tilts over {} orientations of its own, "
        "and no error estimate covers them (it needs two or more wavelengths; docs/non-spherical.md, \"Canting\")",
        spec.canting_deg, kCantingAxes));
  if (!wa.bow_fallback_q.empty()) {
    const auto flattest = std::min_element(wa.bow_fallback_q.begin(), wa.bow_fallback_q.end());
    if (*flattest <= 1)
      t.notes.push_back(fmt::format(
          "the exact 3-D edge of the bow was not found for {} of the {} drop sizes (axis ratio down to {:.3f}, near "
          "the limit of the plane-section method) at {{position_deg}} {:g}: their bow is the plane section's, "
          "whose angle is off between the top and the side (docs/non-spherical.md); a rounder {{shape}} avoids it",
          std::count_if(wa.bow_fallback_q.begin(), wa.bow_fallback_q.end(), [](double v) { return v <= 1; }), J,
          *flattest, spec.position_deg));
  }
  t.work.evaluations = evaluations.load();
  t.work.terms = terms.load();
  t.work.term_angles = t.work.terms * std::int64_t(R);
  t.work.cells = int(R);
  return t;
}

}  // namespace

LeeTable compute_lee_table(const LeeSpec& spec, const ProgressFn& progress, std::optional<std::uint64_t> available_bytes) {
  validate(spec);
  LeeTable t = compute_lee_table_at(spec, progress);
  // Automatic sampling: once more at the sampling that would meet the tolerance (the spectrum's error
  // falls about as 1 / sampling, canting's about as 1 / sqrt(sampling)), where it fits. With the
  // wavelengths given, sampling sets the radius grid alone: that table keeps its note.
  if (!(spec.sampling_most > spec.sampling) || spec.wavelengths > 0 || !t.error.luminance_rms ||
      *t.error.luminance_rms <= kLeeErrorTolerance)
    return t;
  LeeSpec more = spec;
  more.sampling = sampling_for_tolerance(*t.error.luminance_rms, spec.sampling, spec.sampling_most,
                                         orientation_count(spec) > 1 ? 0.5 : 1.0);
  if (!(more.sampling > spec.sampling)) return t;
  // Where the second pass would not fit, the table stays as it is and says why (its note above names
  // the sampling that would meet the tolerance).
  const double need = estimated_bytes(more), available = double(available_bytes.value_or(available_memory_bytes()));
  if (need > available) {
    t.notes.push_back(fmt::format("automatic sampling did not compute it again at {{sampling}} {:g}: that needs about "
                                  "{} of memory and {} is available",
                                  more.sampling, format_bytes(need), format_bytes(available)));
    return t;
  }
  // The second pass's progress runs on from the share of the work already done (the work grows as the
  // square of the sampling: more wavelengths and a denser radius grid alike), so that an ETA stays right.
  const double done = 1 / (1 + (more.sampling / spec.sampling) * (more.sampling / spec.sampling));
  const ProgressFn second = progress ? ProgressFn([&](double f, std::string_view label) {
    progress(done + (1 - done) * f, fmt::format("sampling {:g} (the table at {:g}: {:.2g}% error): {}", more.sampling,
                                                spec.sampling, 100 * *t.error.luminance_rms, label));
  })
                                     : ProgressFn();
  LeeTable better = compute_lee_table_at(more, second);
  better.first_sampling = spec.sampling;
  better.first_error = t.error.luminance_rms;
  return better;
}

LeeImages lee_images(const LeeTable& t, double exposure, double white) {
  const std::size_t rows = t.angle_deg.size(), cols = t.radius_um.size(), n = rows * cols;
  LeeImages im;
  im.linear.resize(n * 6);
  im.display.resize(n * 3);
  std::vector<double> lum(n);
  const color::Rgb lw = color::luminance_weights(t.spec.rgb_space);
  for (std::size_t p = 0; p < n; ++p) {
    const color::Xyz v{t.xyz[p * 3], t.xyz[p * 3 + 1], t.xyz[p * 3 + 2]};
    const color::Rgb rgb = color::desaturate_into_gamut(color::matmul(t.xyz_to_rgb, v), t.spec.rgb_space);
    for (int c = 0; c < 3; ++c) im.linear[p * 6 + std::size_t(c)] = float(rgb[std::size_t(c)]);
    im.linear[p * 6 + 3] = float(v.X);
    im.linear[p * 6 + 4] = float(v.Y);
    im.linear[p * 6 + 5] = float(v.Z);
    lum[p] = lw[0] * rgb[0] + lw[1] * rgb[1] + lw[2] * rgb[2];
  }
  // Reinhard et al. 2002 ("Photographic tone reproduction"): the key 0.18 over the log-average
  // luminance sets the exposure, and the white point is the 99.9th percentile, so a table of any
  // dynamic range (a corona's forward peak is 1e4 times its rings) keeps its structure visible.
  const double floor_l = *std::max_element(lum.begin(), lum.end()) * 1e-6;  // black pixels left out
  double log_sum = 0;
  std::size_t lit = 0;
  for (double l : lum)
    if (l > floor_l) {
      log_sum += std::log(l);
      ++lit;
    }
  im.exposure = exposure > 0 ? exposure : lit > 0 ? kKey / std::exp(log_sum / double(lit)) : 1.0;
  std::vector<double> sorted(lum);
  const std::size_t q = std::min(n - 1, std::size_t(0.999 * double(n)));
  std::nth_element(sorted.begin(), sorted.begin() + std::ptrdiff_t(q), sorted.end());
  im.white = white > 0 ? white : std::max(1.0, sorted[q] * im.exposure);
  const double inv_w2 = 1 / (im.white * im.white);
  for (std::size_t p = 0; p < n; ++p) {
    const double l = lum[p] * im.exposure;
    const double mapped = l > 0 ? l * (1 + l * inv_w2) / (1 + l) : 0.0;
    const double gain = l > 0 ? mapped / l * im.exposure : 0.0;
    for (int c = 0; c < 3; ++c)
      im.display[p * 3 + std::size_t(c)] = float(std::clamp(double(im.linear[p * 6 + std::size_t(c)]) * gain, 0.0, 1.0));
  }
  return im;
}

}  // namespace hydrolux::atmos
