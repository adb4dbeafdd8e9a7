#include "hydrolux/scene/compositor.hpp"

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>

#include "hydrolux/core/error.hpp"
#include "hydrolux/core/math.hpp"
#include "hydrolux/scatter/size_distribution.hpp"
#include "hydrolux/scene/sky_params.hpp"

namespace hydrolux::scene {

namespace {

using V3f = Vec3T<float>;

constexpr float kDegPerRad = float(180.0 / kPi<double>);
constexpr double kExtinctionEfficiency = 2.0;  // Q_ext of drops much larger than the wavelength
constexpr int kSkyTable = 4096;                // intervals of the sky's tabulated Perez factors

// Linear interpolation in a table of kSkyTable + 1 RGB-like triples over [0, 1].
inline void table3(const float* t, float x, float out[3]) {
  float p = x * float(kSkyTable);
  p = p < 0 ? 0 : (p > float(kSkyTable) ? float(kSkyTable) : p);
  int i = int(p);
  i = i > kSkyTable - 1 ? kSkyTable - 1 : i;
  const float f = p - float(i);
  const float* a = t + std::size_t(i) * 3;
  out[0] = a[0] + f * (a[3] - a[0]);
  out[1] = a[1] + f * (a[4] - a[1]);
  out[2] = a[2] + f * (a[5] - a[2]);
}

V3f to_f(const Vec3& v) { return {float(v.x), float(v.y), float(v.z)}; }

float smoothstep(float e0, float e1, float x) {
  const float t = std::clamp((x - e0) / (e1 - e0), 0.0f, 1.0f);
  return t * t * (3 - 2 * t);
}

// OpenGL cube faces: the direction through face coordinates (sc, tc) in [-1, 1].
V3f face_direction(int face, float sc, float tc) {
  switch (face) {
    case 0: return {1, -tc, -sc};
    case 1: return {-1, -tc, sc};
    case 2: return {sc, 1, tc};
    case 3: return {sc, -1, -tc};
    case 4: return {sc, -tc, 1};
    default: return {-sc, -tc, -1};
  }
}

// One row of view rays, structure of arrays: the unit direction, its cosine to the sun and the
// angle (radians). Branch-free, so the compiler vectorises it; compiled for AVX-512 and AVX2 too
// on x86-64 (the baseline is SSE2), chosen when the program loads.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
__attribute__((target_clones("avx512f", "avx2", "default")))
#endif
void row_rays(int n, float px0, float dpx, float py, const float* __restrict f, const float* __restrict r,
              const float* __restrict u, const float* __restrict sun, float* __restrict dx, float* __restrict dy,
              float* __restrict dz, float* __restrict c, float* __restrict gamma) {
  const float bx = f[0] + py * u[0], by = f[1] + py * u[1], bz = f[2] + py * u[2];
  for (int i = 0; i < n; ++i) {
    const float px = px0 + float(i) * dpx;
    const float x = bx + px * r[0], y = by + px * r[1], z = bz + px * r[2];
    const float inv = 1.0f / std::sqrt(x * x + y * y + z * z);
    const float ux = x * inv, uy = y * inv, uz = z * inv;
    float cc = ux * sun[0] + uy * sun[1] + uz * sun[2];
    cc = cc < -1.0f ? -1.0f : (cc > 1.0f ? 1.0f : cc);
    dx[i] = ux, dy[i] = uy, dz[i] = uz, c[i] = cc;
    gamma[i] = fast_acos(cc);
  }
}

}  // namespace

// ---- tables --------------------------------------------------------------------------------

std::array<double, 2> BowTable::angle_range_deg() const {
  double a = row_first, b = row_last;
  if (axis == atmos::AngleAxis::cosine) {
    a = rad_to_deg(safe_acos(row_first));
    b = rad_to_deg(safe_acos(row_last));
  }
  return {std::min(a, b), std::max(a, b)};
}

namespace {
// |Q| <= I per channel: Q goes to RGB unmapped while I is gamut-mapped, and where the mapping
// lifted a channel of I (the bow's out-of-gamut edges) Q's would exceed it (docs/sky.md).
void limit_q(std::vector<float>& q, const std::vector<float>& rgb) {
  for (std::size_t i = 0; i < q.size(); ++i) q[i] = std::clamp(q[i], -rgb[i], rgb[i]);
}
}  // namespace

BowTable bow_table(const atmos::LeeTable& t) {
  BowTable b;
  b.kind = t.spec.table;
  b.axis = t.spec.axis;
  b.radius_um = t.radius_um;
  b.rows = t.rows();
  const auto& rows = t.spec.axis == atmos::AngleAxis::angle ? t.angle_deg : t.cos_angle;
  b.row_first = rows.front();
  b.row_last = rows.back();
  b.rgb.resize(std::size_t(t.rows()) * t.columns() * 3);
  for (int r = 0; r < t.rows(); ++r)
    for (int c = 0; c < t.columns(); ++c) {
      const auto v = t.rgb(r, c);
      for (int k = 0; k < 3; ++k) b.rgb[(std::size_t(r) * t.columns() + c) * 3 + k] = float(v[k]);
    }
  if (!t.q_xyz.empty()) {
    b.q.resize(b.rgb.size());
    for (int r = 0; r < t.rows(); ++r)
      for (int c = 0; c < t.columns(); ++c) {
        const auto v = color::matmul(t.xyz_to_rgb, t.q_at(r, c));
        for (int k = 0; k < 3; ++k) b.q[(std::size_t(r) * t.columns() + c) * 3 + k] = float(v[k]);
      }
    limit_q(b.q, b.rgb);
  }
  return b;
}

BowTable bow_table(atmos::LeeTableKind kind, atmos::AngleAxis axis, std::vector<double> radius_um,
                   const std::vector<double>& row_values, std::vector<float> rgb,
                   std::optional<atmos::RadiusScale> radius_scale, std::vector<float> q) {
  if (radius_um.empty() || row_values.empty()) throw Error("a Lee table needs at least one radius and one row");
  for (std::size_t i = 0; i < radius_um.size(); ++i)
    if (!(radius_um[i] >= atmos::kMinRadiusUm && radius_um[i] <= atmos::kMaxRadiusUm))
      throw Error(fmt::format("radius {} of the table is {:g} um, outside [{:g}, {:g}] um", i, radius_um[i],
                              atmos::kMinRadiusUm, atmos::kMaxRadiusUm));
  for (std::size_t i = 1; i < radius_um.size(); ++i)
    if (!(radius_um[i] > radius_um[i - 1]))
      throw Error(fmt::format("the table's radii must increase strictly (radius {}: {:g} um after {:g})", i,
                              radius_um[i], radius_um[i - 1]));
  if (radius_scale && radius_um.size() > 2) {
    const bool log = *radius_scale == atmos::RadiusScale::log;
    const auto at = [&](std::size_t i) { return log ? std::log(radius_um[i]) : radius_um[i]; };
    const std::size_t n = radius_um.size();
    const double a = at(0), b = at(n - 1);
    for (std::size_t i = 1; i + 1 < n; ++i) {
      const double expect = a + (b - a) * double(i) / double(n - 1);
      if (std::abs(at(i) - expect) > 1e-6 * (b - a))
        throw Error(fmt::format("the table's radii are not uniform on its {} radius scale (radius {}: {:g} um where "
                                "{:g} was expected)",
                                atmos::radius_scale_name(*radius_scale), i, radius_um[i],
                                log ? std::exp(expect) : expect));
    }
  }
  if (rgb.size() != radius_um.size() * row_values.size() * 3)
    throw Error(fmt::format("the table holds {} values; {} radii x {} rows x 3 channels need {}", rgb.size(),
                            radius_um.size(), row_values.size(), radius_um.size() * row_values.size() * 3));
  const double first = row_values.front(), last = row_values.back();
  const int n = int(row_values.size());
  const double lo = axis == atmos::AngleAxis::angle ? 0 : -1, hi = axis == atmos::AngleAxis::angle ? 180 : 1;
  const char* axis_name = axis == atmos::AngleAxis::angle ? "angle_deg" : "cos_angle";
  if (n > 1 && !(last > first))
    throw Error(fmt::format("the table's rows must increase strictly downward ({} runs from {:g} to {:g})", axis_name,
                            first, last));
  for (int i = 0; i < n; ++i) {
    const double v = row_values[std::size_t(i)];
    if (!(v >= lo && v <= hi))
      throw Error(fmt::format("row {} lies at {} {:g}, outside [{}, {}]", i, axis_name, v, lo, hi));
    if (n > 1) {
      const double expect = first + (last - first) * i / (n - 1);
      if (std::abs(v - expect) > 1e-6 * std::max(std::abs(last - first), 1e-12))
        throw Error(fmt::format("the table's rows are not uniform on their axis (row {}: {} where {} was expected)", i,
                                v, expect));
    }
  }
  for (std::size_t i = 0; i < rgb.size(); ++i)
    if (!(std::isfinite(rgb[i]) && rgb[i] >= 0))
      throw Error(fmt::format("the table holds {:g} at row {}, column {} (values are radiance per unit irradiance, "
                              "sr^-1: finite and non-negative)",
                              rgb[i], i / 3 / radius_um.size(), i / 3 % radius_um.size()));
  BowTable b;
  b.kind = kind;
  b.axis = axis;
  b.radius_um = std::move(radius_um);
  b.row_first = first;
  b.row_last = last;
  b.rows = n;
  if (!q.empty()) {
    if (q.size() != rgb.size())
      throw Error(fmt::format("the table's Stokes Q holds {} values where its intensity holds {}", q.size(), rgb.size()));
    for (std::size_t i = 0; i < q.size(); ++i)
      if (!std::isfinite(q[i]))
        throw Error(fmt::format("the table's Stokes Q holds {:g} at row {}, column {} (finite values only)", q[i],
                                i / 3 / b.radius_um.size(), i / 3 % b.radius_um.size()));
  }
  if (!q.empty()) limit_q(q, rgb);
  b.rgb = std::move(rgb);
  b.q = std::move(q);
  return b;
}

BowSlice slice_at_radius(const BowTable& t, double radius_um, bool outside_is_empty) {
  BowSlice s;
  const auto& r = t.radius_um;
  if (outside_is_empty && (radius_um < r.front() * (1 - 1e-9) || radius_um > r.back() * (1 + 1e-9))) return s;
  s.kind = t.kind;
  s.cosine_axis = t.axis == atmos::AngleAxis::cosine;
  s.first = float(t.row_first);
  s.last = float(t.row_last);
  s.rows = t.rows;
  const int cols = t.columns();
  int c0 = 0;
  double f = 0;
  if (cols > 1) {
    const double x = std::log(std::clamp(radius_um, r.front(), r.back()));
    c0 = int(std::upper_bound(r.begin(), r.end(), std::exp(x)) - r.begin()) - 1;
    c0 = std::clamp(c0, 0, cols - 2);
    f = std::clamp((x - std::log(r[c0])) / (std::log(r[c0 + 1]) - std::log(r[c0])), 0.0, 1.0);
  }
  const auto column = [&](const std::vector<float>& table, std::vector<float>& out) {
    out.resize(std::size_t(t.rows) * 3);
    for (int row = 0; row < t.rows; ++row)
      for (int k = 0; k < 3; ++k) {
        const float a = table[(std::size_t(row) * cols + c0) * 3 + k];
        const float b = cols > 1 ? table[(std::size_t(row) * cols + c0 + 1) * 3 + k] : a;
        out[std::size_t(row) * 3 + k] = float(a + f * (b - a));
      }
  };
  column(t.rgb, s.rgb);
  if (t.has_q()) column(t.q, s.q);
  return s;
}

// ---- settings ------------------------------------------------------------------------------

std::string_view blend_name(Blend b) { return b == Blend::physical ? "physical" : "whitepaper"; }
std::string_view bow_mode_name(BowMode m) {
  return m == BowMode::per_pixel ? "per-pixel" : m == BowMode::cube_map ? "cube-map" : "half-dome";
}

void validate(const SkySettings& s) {
  // The declared parameters' ranges (sky_params.cpp): the numbers, the size, the curtain's span (its far
  // edge not nearer than its near one), the light's colour, the blend and the mode.
  SkyOptions declared;
  declared.settings = s;
  check_fields(sky_params(), declared);
  // An optional set to NaN reads as unset there (HYDROLUX_PARAM_OPTIONAL): refused here.
  if (s.polarizer_deg) sky_param("polarizer_deg").check(*s.polarizer_deg);
}

void check_polarization(const SkySettings& s, bool rainbow_q, bool corona_q, Door door) {
  const std::string stokes(spelled(sky_param("stokes"), door));
  const auto polarizer = [&] {
    return fmt::format("{} {:g}", spelled(sky_param("polarizer_deg"), door), s.polarizer_deg.value_or(0));
  };
  if (s.stokes && s.polarizer_deg)
    throw Error(fmt::format("{}: the Stokes images are the light before any filter: ask for them or for a polariser "
                            "({}), not both",
                            stokes, polarizer()));
  if (s.stokes && s.blend != Blend::physical)
    throw Error(fmt::format("{}: the Stokes images need the physical blend (the whitepaper's is not linear in the light)",
                            stokes));
  if (!s.polarizer_deg && !s.stokes) return;
  const auto needs_q = [&](std::string_view table) {
    return Error(fmt::format("{}: {} the {}'s Stokes Q, and its table has none (compute it with stokes on: hydrolux "
                             "lee --stokes, or hydrolux export)",
                             s.stokes ? stokes : polarizer(), s.stokes ? "the Stokes images need" : "a polariser needs",
                             table));
  };
  if (!rainbow_q) throw needs_q("rainbow");
  if (s.corona && !corona_q) throw needs_q("corona");
}

double estimated_bytes(const SkySettings& s) {
  const double pixels = double(s.camera.width) * double(s.camera.height);
  const double cube = s.mode == BowMode::cube_map ? double(s.cube_face_size) * s.cube_face_size : 0;
  // The dome: (rings + 1) x segments float vertices, negligible but counted.
  const double dome = s.mode == BowMode::half_dome ? double(s.dome_rings + 1) * s.dome_segments * 12 : 0;
  // The Stokes images: 9 channels where a frame has 3, the frame and the EXR encoder's buffers tripled;
  // with them or a polariser, the cube map of Q besides the bow's.
  const bool pol = s.stokes || s.polarizer_deg.has_value();
  return kSkyFixedBytes + kSkyBytesPerPixel * pixels * (s.stokes ? 3 : 1) + kSkyBytesPerCubeTexel * cube * (pol ? 2 : 1) +
         dome;
}

float secondary_weight(bool secondary_on, float theta_deg) {
  return secondary_on ? 1.0f : smoothstep(132.0f, 136.0f, theta_deg);
}

double rain_beta_geo_per_m(double rain_rate_mmh) {
  if (rain_rate_mmh <= 0) return 0;
  const auto d = scatter::SizeDistribution::marshall_palmer(rain_rate_mmh, scatter::kMarshallPalmerN0PerRadius);
  return kPi<double> * d.moment(2);
}

// ---- cube map -------------------------------------------------------------------------------

void CubeMap::lookup(const V3f& d, float out[3]) const {
  const float ax = std::abs(d.x), ay = std::abs(d.y), az = std::abs(d.z);
  int face;
  float sc, tc, ma;
  if (ax >= ay && ax >= az) {
    face = d.x > 0 ? 0 : 1;
    ma = ax;
    sc = d.x > 0 ? -d.z : d.z;
    tc = -d.y;
  } else if (ay >= az) {
    face = d.y > 0 ? 2 : 3;
    ma = ay;
    sc = d.x;
    tc = d.y > 0 ? d.z : -d.z;
  } else {
    face = d.z > 0 ? 4 : 5;
    ma = az;
    sc = d.z > 0 ? d.x : -d.x;
    tc = -d.y;
  }
  const float n = float(size);
  const float x = std::clamp((sc / ma + 1) * 0.5f * n - 0.5f, 0.0f, n - 1);
  const float y = std::clamp((tc / ma + 1) * 0.5f * n - 0.5f, 0.0f, n - 1);
  const int x0 = std::min(int(x), size - 2), y0 = std::min(int(y), size - 2);  // size >= 4 (validate)
  const int x1 = x0 + 1, y1 = y0 + 1;
  const float fx = x - float(x0), fy = y - float(y0);
  const auto at = [&](int xx, int yy, int k) {
    return rgb[((std::size_t(face) * size + yy) * size + xx) * 3 + k];
  };
  for (int k = 0; k < 3; ++k) {
    const float a = at(x0, y0, k) + fx * (at(x1, y0, k) - at(x0, y0, k));
    const float b = at(x0, y1, k) + fx * (at(x1, y1, k) - at(x0, y1, k));
    out[k] = a + fy * (b - a);
  }
}

// ---- the compositor -------------------------------------------------------------------------

SkyCompositor::SkyCompositor(const SkySettings& settings, RainbowSlices rainbow, BowSlice corona,
                             std::shared_ptr<const Environment> environment, double environment_scale)
    : s_(settings), corona_(std::move(corona)), env_(std::move(environment)), env_scale_(environment_scale) {
  validate(s_);
  auto& slices = rainbow.by_position;
  if (slices.size() == 1) {
    rainbow_ = std::move(slices.front());
  } else if (slices.size() > 1) {
    const BowSlice& a = slices.front();
    for (std::size_t k = 1; k < slices.size(); ++k) {
      const BowSlice& b = slices[k];
      if (b.kind != a.kind || b.cosine_axis != a.cosine_axis || b.first != a.first || b.last != a.last ||
          b.rows != a.rows || b.rgb.size() != a.rgb.size())
        throw Error(fmt::format("the rainbow's slice at position {} of {} differs from the first in its kind or rows "
                                "(the slices by position angle must share them)",
                                k, slices.size()));
    }
    by_position_ = std::move(slices);
  }
  check_polarization(s_,
                     by_position_.empty() ? (rainbow_.empty() || rainbow_.has_q())
                                          : std::all_of(by_position_.begin(), by_position_.end(),
                                                        [](const BowSlice& b) { return b.has_q(); }),
                     corona_.empty() || corona_.has_q());
  const Param& scale = sky_param("environment_scale");  // the declared range (sky_params.cpp)
  if (!(environment_scale >= scale.lo && std::isfinite(environment_scale)))
    throw DomainError("environment_scale", environment_scale, scale.lo, scale.hi);
  sky_ = make_sun_sky(s_.sun_elevation_deg, s_.turbidity);
  sun_ = direction_from_angles(s_.sun_azimuth_deg, s_.sun_elevation_deg);
  fwd_ = direction_from_angles(s_.camera.azimuth_deg, s_.camera.elevation_deg);
  right_ = glm::normalize(glm::cross(Vec3{0, 1, 0}, fwd_));
  up_ = glm::cross(fwd_, right_);
  {
    // The position angle's frame: the antisolar direction and the zenith projected normal to it
    // (undefined, and left zero, for a sun at the zenith).
    const Vec3 a = -sun_;
    const Vec3 u = Vec3{0, 1, 0} - a.y * a;
    if (glm::length(u) > 1e-9) {
      position_up_ = to_f(glm::normalize(u));
      position_side_ = to_f(glm::normalize(glm::cross(a, u)));
    }
  }
  beta_geo_ = rain_beta_geo_per_m(s_.rain_rate_mmh);
  sky_zenith_factor_.resize(std::size_t(kSkyTable + 1) * 3);
  sky_sun_factor_.resize(std::size_t(kSkyTable + 1) * 3);
  for (int i = 0; i <= kSkyTable; ++i) {
    for (int k = 0; k < 3; ++k) {
      const auto& p = sky_.perez[std::size_t(k)];
      sky_zenith_factor_[std::size_t(i) * 3 + k] = float(p.zenith_factor(double(i) / kSkyTable));
      sky_sun_factor_[std::size_t(i) * 3 + k] = float(p.sun_factor(kPi<double> * i / kSkyTable));
    }
  }

  const auto start = std::chrono::steady_clock::now();
  if (s_.mode == BowMode::cube_map) {
    const int n = s_.cube_face_size;
    cube_.size = n;
    cube_.rgb.assign(std::size_t(6) * n * n * 3, 0.f);
    const bool bake_q = s_.polarizer_deg.has_value() || s_.stokes;
    if (bake_q) {
      cube_q_.size = n;
      cube_q_.rgb.assign(cube_.rgb.size(), 0.f);
    }
    const V3f sun = to_f(sun_);
    tbb::parallel_for(0, 6 * n, [&](int fy) {
      const int face = fy / n, y = fy % n;
      for (int x = 0; x < n; ++x) {
        const float sc = 2 * (float(x) + 0.5f) / float(n) - 1, tc = 2 * (float(y) + 0.5f) / float(n) - 1;
        const V3f d = glm::normalize(face_direction(face, sc, tc));
        const float c = std::clamp(glm::dot(d, sun), -1.0f, 1.0f);
        float v[3], vq[3];
        const float theta = std::acos(c) * kDegPerRad;
        rainbow_term(d, c, theta, v, bake_q ? vq : nullptr);
        add_corona_term(c, theta, v, bake_q ? vq : nullptr);
        float* o = &cube_.rgb[((std::size_t(face) * n + y) * n + x) * 3];
        o[0] = v[0], o[1] = v[1], o[2] = v[2];
        if (bake_q) {
          float* oq = &cube_q_.rgb[((std::size_t(face) * n + y) * n + x) * 3];
          oq[0] = vq[0], oq[1] = vq[1], oq[2] = vq[2];
        }
      }
    });
  } else if (s_.mode == BowMode::half_dome) {
    // The dome's axis is the antisolar direction; ring i lies alpha_i = 90 i / rings degrees from it.
    const Vec3 axis = -sun_;
    const Vec3 helper = std::abs(axis.y) < 0.9 ? Vec3{0, 1, 0} : Vec3{1, 0, 0};
    const Vec3 e1 = glm::normalize(glm::cross(helper, axis));
    const Vec3 e2 = glm::cross(axis, e1);
    dome_axis_ = to_f(axis);
    dome_e1_ = to_f(e1);
    dome_e2_ = to_f(e2);
    const int R = s_.dome_rings, S = s_.dome_segments;
    dome_.resize(std::size_t(R + 1) * S);
    for (int i = 0; i <= R; ++i) {
      const double a = deg_to_rad(90.0 * i / R);
      for (int j = 0; j < S; ++j) {
        const double p = 2 * kPi<double> * j / S;
        dome_[std::size_t(i) * S + j] =
            to_f(axis * std::cos(a) + (e1 * std::cos(p) + e2 * std::sin(p)) * std::sin(a));
      }
    }
  }
  bake_seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

float SkyCompositor::position_angle_deg(const V3f& d) const {
  // From d's two components normal to the antisolar direction, by atan2: no cancellation near the
  // antisolar point, where an arccosine of their ratio to sqrt(1 - cos^2) would lose degrees in
  // float. atan2(0, 0) = 0 there and for a sun at the zenith.
  return std::atan2(std::abs(glm::dot(d, position_side_)), glm::dot(d, position_up_)) * kDegPerRad;
}

// The rainbow table's part at theta (in the direction d, for the position angle of non-spherical
// drops' slices), the secondary window applied.
void SkyCompositor::rainbow_term(const V3f& d, float c, float theta_deg, float out[3], float* q_out) const {
  if (by_position_.empty()) {
    rainbow_.lookup_in(c, theta_deg, out, q_out);
  } else {
    // Linear between the two nearest positions.
    const int n = int(by_position_.size());
    const float p = std::clamp(position_angle_deg(d) * float(n - 1) / 180.0f, 0.0f, float(n - 1));
    const int k = std::min(int(p), n - 2);
    const float f = p - float(k);
    float a[3], b[3], qa[3], qb[3];
    by_position_[std::size_t(k)].lookup_in(c, theta_deg, a, q_out ? qa : nullptr);
    by_position_[std::size_t(k) + 1].lookup_in(c, theta_deg, b, q_out ? qb : nullptr);
    for (int i = 0; i < 3; ++i) out[i] = a[i] + f * (b[i] - a[i]);
    if (q_out)
      for (int i = 0; i < 3; ++i) q_out[i] = qa[i] + f * (qb[i] - qa[i]);
  }
  const float w = secondary_weight(s_.secondary, theta_deg);
  out[0] *= w, out[1] *= w, out[2] *= w;
  if (q_out) q_out[0] *= w, q_out[1] *= w, q_out[2] *= w;
}

// The corona table's part at theta, added to `out` (and its Q to `q_out`) when the corona is on.
void SkyCompositor::add_corona_term(float c, float theta_deg, float out[3], float* q_out) const {
  if (!s_.corona || corona_.empty()) return;
  float v[3], vq[3];
  corona_.lookup_in(c, theta_deg, v, q_out ? vq : nullptr);
  out[0] += v[0], out[1] += v[1], out[2] += v[2];
  if (q_out) q_out[0] += vq[0], q_out[1] += vq[1], q_out[2] += vq[2];
}

// The half dome: the ray meets the flat triangle of the tessellation whose corners carry theta;
// the GPU's perspective-correct interpolation is the barycentric blend at that point.
float SkyCompositor::dome_theta(const V3f& d, bool& covered) const {
  covered = false;
  const float ca = glm::dot(d, dome_axis_);
  if (ca < 0) return 0;
  const int R = s_.dome_rings, S = s_.dome_segments;
  const float alpha = std::acos(std::min(ca, 1.0f)) * kDegPerRad;
  float phi = std::atan2(glm::dot(d, dome_e2_), glm::dot(d, dome_e1_));
  if (phi < 0) phi += float(2 * kPi<double>);
  const int i0 = std::min(int(alpha / 90.0f * float(R)), R - 1);
  const int j0 = std::min(int(phi / float(2 * kPi<double>) * float(S)), S - 1);
  const auto vert = [&](int i, int j) { return dome_[std::size_t(i) * S + ((j % S) + S) % S]; };
  const auto ring_theta = [&](int i) { return 180.0f - 90.0f * float(i) / float(R); };
  // Moller-Trumbore from the origin along d; returns the interpolated theta when the ray hits.
  const auto hit = [&](int ia, int ja, int ib, int jb, int ic, int jc, float& theta) {
    const V3f a = vert(ia, ja), b = vert(ib, jb), c = vert(ic, jc);
    const V3f e1 = b - a, e2 = c - a;
    const V3f p = glm::cross(d, e2);
    const float det = glm::dot(e1, p);
    if (std::abs(det) < 1e-12f) return false;
    const V3f t = -a;
    const float u = glm::dot(t, p) / det;
    const V3f q = glm::cross(t, e1);
    const float v = glm::dot(d, q) / det;
    constexpr float eps = -1e-5f;
    if (u < eps || v < eps || u + v > 1 - eps) return false;
    if (glm::dot(e2, q) / det <= 0) return false;
    theta = (1 - u - v) * ring_theta(ia) + u * ring_theta(ib) + v * ring_theta(ic);
    return true;
  };
  float theta = 0;
  for (int di : {0, -1, 1}) {
    const int i = i0 + di;
    if (i < 0 || i >= R) continue;
    for (int dj : {0, -1, 1}) {
      const int j = j0 + dj;
      if (hit(i, j, i + 1, j, i + 1, j + 1, theta) || (i > 0 && hit(i, j, i + 1, j + 1, i, j + 1, theta))) {
        covered = true;
        return theta;
      }
    }
  }
  return 0;
}

// The bow colour (and, into `q_out` when given, its Stokes Q) at one pixel in the current mode.
void SkyCompositor::bow_pixel(const V3f& d, float c, float theta, float o[3], float* q_out) const {
  if (s_.mode == BowMode::cube_map) {
    cube_.lookup(d, o);
    if (q_out) cube_q_.lookup(d, q_out);
  } else if (s_.mode == BowMode::half_dome) {
    // The dome carries the rainbow side only; the corona stays per pixel.
    bool covered = false;
    const float t = dome_theta(d, covered);
    o[0] = o[1] = o[2] = 0;
    if (q_out) q_out[0] = q_out[1] = q_out[2] = 0;
    // The position angle, for non-spherical drops, from the view ray (a shader's interpolated
    // direction), theta from the dome.
    if (covered) rainbow_term(d, std::cos(t / kDegPerRad), t, o, q_out);
    add_corona_term(c, theta, o, q_out);
  } else {
    rainbow_term(d, c, theta, o, q_out);
    add_corona_term(c, theta, o, q_out);
  }
}

Image SkyCompositor::bow_colour() const {
  const int W = s_.camera.width, H = s_.camera.height;
  Image out(W, H, 3);
  const V3f f = to_f(fwd_), r = to_f(right_), u = to_f(up_), sun = to_f(sun_);
  const float tx = float(std::tan(deg_to_rad(s_.camera.fov_deg) / 2)), ty = tx * float(H) / float(W);
  tbb::parallel_for(0, H, [&](int j) {
    const float py = (1 - 2 * (float(j) + 0.5f) / float(H)) * ty;
    for (int i = 0; i < W; ++i) {
      const float px = (2 * (float(i) + 0.5f) / float(W) - 1) * tx;
      const V3f d = glm::normalize(f + px * r + py * u);
      const float c = std::clamp(glm::dot(d, sun), -1.0f, 1.0f);
      bow_pixel(d, c, fast_acos(c) * kDegPerRad, &out.pixels[(std::size_t(j) * W + i) * 3]);
    }
  });
  return out;
}

Image SkyCompositor::render(const Image* moisture) const {
  Image out;
  render_into(out, moisture);
  return out;
}

void SkyCompositor::render_into(Image& out, const Image* moisture) const {
  const int W = s_.camera.width, H = s_.camera.height;
  const bool stokes = s_.stokes;
  const int C = stokes ? 9 : 3;
  if (out.width != W || out.height != H || out.channels != C || out.pixels.size() != std::size_t(W) * H * C)
    out = Image(W, H, C);
  out.channel_names.clear();
  if (stokes) out.channel_names = {"R", "G", "B", "Q.R", "Q.G", "Q.B", "U.R", "U.G", "U.B"};
  const V3f f = to_f(fwd_), r = to_f(right_), u = to_f(up_), sun = to_f(sun_);
  const float tx = float(std::tan(deg_to_rad(s_.camera.fov_deg) / 2)), ty = tx * float(H) / float(W);

  // The frame's constants, float.
  const float Z[3] = {float(sky_.zenith_Y_kcd * 1000 / sky_.perez_at_sun[0]),
                      float(sky_.zenith_x / sky_.perez_at_sun[1]), float(sky_.zenith_y / sky_.perez_at_sun[2])};
  float M[3][3];
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) M[a][b] = float(sky_.xyz_to_rgb[std::size_t(a)][std::size_t(b)]);
  const V3f ground = to_f(sky_.ground_rgb);
  const double omega_sun = 2 * kPi<double> * (1 - std::cos(deg_to_rad(kSunAngularRadiusDeg)));
  const V3f sun_disk = to_f(sky_.sun_rgb / omega_sun);
  const float cos_sun_radius = float(std::cos(deg_to_rad(kSunAngularRadiusDeg)));
  const V3f light = to_f(sky_.sun_rgb * s_.light_color);
  const float beta = float(beta_geo_), d0 = float(s_.curtain_near_m), d1 = float(s_.curtain_far_m);
  const float h_cam = float(kCameraHeightM), q = float(kExtinctionEfficiency);
  const float inv_lref = float(1.0 / sky_.l_ref);
  const bool physical = s_.blend == Blend::physical;
  const float inv_pi = float(1 / kPi<double>);
  // Above the horizon every ray crosses the whole curtain: one transmittance for the sky.
  const float sky_trans = std::exp(-q * beta * std::max(d1 - d0, 0.0f));
  const float* zt = sky_zenith_factor_.data();
  const float* gt = sky_sun_factor_.data();
  // The polariser (docs/sky.md, "Polarisation"): its axis a = cos A h + sin A v in each pixel's image
  // basis (h the camera's right made normal to the ray, v = d x h, up); the sky's and the bow's
  // polarised light lies normal to the scattering plane, along e = d x sun, so the filter passes
  // (I + Qp cos 2(chi - A)) / 2 of it, chi e's angle in that basis; the rest passes half.
  // With the Stokes images, Q = Qp cos 2chi and U = Qp sin 2chi instead of a filter.
  const bool filter = s_.polarizer_deg.has_value();
  const bool pol = filter || stokes;
  const float cos2a = filter ? float(std::cos(2 * deg_to_rad(*s_.polarizer_deg))) : 0.0f;
  const float sin2a = filter ? float(std::sin(2 * deg_to_rad(*s_.polarizer_deg))) : 0.0f;
  const float p90 = float(s_.sky_max_dolp);
  const float fa[3] = {f.x, f.y, f.z}, ra[3] = {r.x, r.y, r.z}, ua[3] = {u.x, u.y, u.z}, sa[3] = {sun.x, sun.y, sun.z};
  tbb::enumerable_thread_specific<std::vector<float>> scratch;

  tbb::parallel_for(tbb::blocked_range<int>(0, H, 8), [&](const tbb::blocked_range<int>& rows) {
    for (int j = rows.begin(); j != rows.end(); ++j) {
      const float py = (1 - 2 * (float(j) + 0.5f) / float(H)) * ty;
      float* row = &out.pixels[std::size_t(j) * W * C];
      auto& buf = scratch.local();
      buf.resize(std::size_t(W) * 5);
      float *bx = buf.data(), *by = bx + W, *bz = by + W, *bc = bz + W, *bg_ = bc + W;
      row_rays(W, (1.0f / float(W) - 1) * tx, 2 * tx / float(W), py, fa, ra, ua, sa, bx, by, bz, bc, bg_);
      for (int i = 0; i < W; ++i) {
        const V3f d{bx[i], by[i], bz[i]};
        const float c = bc[i];
        const float gamma = bg_[i];
        const float theta = gamma * kDegPerRad;
        // cos 2 (chi - A) with a polariser (0 where the scattering plane is undefined: at the sun and
        // the antisolar point, where nothing is polarised).
        float c2 = 0, cos2chi = 0, sin2chi = 0;
        if (pol) {
          const V3f e = glm::cross(d, sun);
          const V3f h = r - glm::dot(r, d) * d;
          const V3f v = glm::cross(d, h);  // |v| = |h|
          const float ee = glm::dot(e, e), hh = glm::dot(h, h);
          if (ee > 1e-12f && hh > 1e-12f) {
            const float eh = glm::dot(e, h), ev = glm::dot(e, v), norm = 1 / (ee * hh);
            cos2chi = (eh * eh - ev * ev) * norm;
            sin2chi = 2 * eh * ev * norm;
            c2 = std::clamp(cos2chi * cos2a + sin2chi * sin2a, -1.0f, 1.0f);
          }
        }
        // The background.
        V3f bg;
        float bg_dolp = 0;  // the sky's degree of polarisation (the sun, ground and environment: none)
        if (env_) {
          bg = to_f(env_->radiance(Vec3(d)) * env_scale_);
        } else if (d.y >= 0) {
          float zf[3], gf[3];
          table3(zt, d.y, zf);
          table3(gt, gamma * inv_pi, gf);
          const float Y = Z[0] * zf[0] * gf[0], x = Z[1] * zf[1] * gf[1], y = Z[2] * zf[2] * gf[2];
          const float X = x / y * Y, Zc = (1 - x - y) / y * Y;
          bg = {M[0][0] * X + M[0][1] * Y + M[0][2] * Zc, M[1][0] * X + M[1][1] * Y + M[1][2] * Zc,
                M[2][0] * X + M[2][1] * Y + M[2][2] * Zc};
          if (c >= cos_sun_radius)
            bg = sun_disk;
          else if (pol)
            bg_dolp = float(sky_dolp(c, p90));
        } else {
          bg = ground;
        }
        // The rain along the ray: the whole curtain above the horizon, cut by the ground below.
        float m = 1;
        if (moisture) {
          const float mx = (float(i) + 0.5f) / float(W) * float(moisture->width) - 0.5f;
          const float my = (float(j) + 0.5f) / float(H) * float(moisture->height) - 0.5f;
          const int x0 = std::clamp(int(std::floor(mx)), 0, moisture->width - 1);
          const int y0 = std::clamp(int(std::floor(my)), 0, moisture->height - 1);
          const int x1 = std::min(x0 + 1, moisture->width - 1), y1 = std::min(y0 + 1, moisture->height - 1);
          const float fx = std::clamp(mx - float(x0), 0.0f, 1.0f), fy = std::clamp(my - float(y0), 0.0f, 1.0f);
          const auto at = [&](int xx, int yy) { return moisture->at(xx, yy, 0); };
          const float a = at(x0, y0) + fx * (at(x1, y0) - at(x0, y0));
          const float b = at(x0, y1) + fx * (at(x1, y1) - at(x0, y1));
          m = std::clamp(a + fy * (b - a), 0.0f, 1.0f);
        }
        float trans = sky_trans;
        if (d.y < 0 || m != 1) {
          float path = d1 - d0;
          if (d.y < 0) path = std::min(d1, h_cam / -d.y) - d0;
          path = std::max(path, 0.0f);
          trans = path > 0 && m > 0 ? std::exp(-q * beta * path * m) : 1.0f;
        }
        float* o = row + std::size_t(i) * C;
        if (filter) bg *= 0.5f * (1 + bg_dolp * c2);
        const V3f bgq = bg * bg_dolp;  // the background's light polarised along e (Stokes images)
        if (trans == 1.0f) {
          o[0] = bg.x, o[1] = bg.y, o[2] = bg.z;
          if (stokes)
            for (int k = 0; k < 3; ++k) o[3 + k] = bgq[k] * cos2chi, o[6 + k] = bgq[k] * sin2chi;
          continue;
        }
        float t[3], tq[3];
        bow_pixel(d, c, theta, t, pol ? tq : nullptr);
        if (filter) {
          // |Q| <= I per channel (BowTable::q), so this is >= 0 but for rounding.
          for (int k = 0; k < 3; ++k) t[k] = std::max(0.5f * (t[k] + tq[k] * c2), 0.0f);
        }
        const float scatter = (1 - trans) / q;
        for (int k = 0; k < 3; ++k) {
          const float b = light[k] * t[k] * scatter;
          o[k] = physical ? bg[k] * trans + b : bg[k] + b * (1 - std::clamp(bg[k] * inv_lref, 0.0f, 1.0f));
        }
        if (stokes)
          for (int k = 0; k < 3; ++k) {
            const float qp = bgq[k] * trans + light[k] * tq[k] * scatter;
            o[3 + k] = qp * cos2chi, o[6 + k] = qp * sin2chi;
          }
      }
    }
  });
}

// ---- display and comparison -------------------------------------------------------------------

Image tone_map(const Image& radiance, double l_ref) {
  Image out(radiance.width, radiance.height, 3);
  const float k = float(0.6 / l_ref);
  constexpr float w2 = 36.0f;
  for (std::size_t p = 0; p < std::size_t(radiance.width) * radiance.height; ++p)
    for (int c = 0; c < 3; ++c) {
      const float x = std::max(radiance.pixels[p * radiance.channels + c], 0.0f) * k;
      out.pixels[p * 3 + c] = std::clamp(x * (1 + x / w2) / (1 + x), 0.0f, 1.0f);
    }
  return out;
}

BowError bow_error(const Image& approx, const Image& reference) {
  if (approx.width != reference.width || approx.height != reference.height || approx.channels < 3 ||
      reference.channels < 3)
    throw Error("bow_error: the images differ in size");
  const auto w = color::luminance_weights(color::RgbSpace::rec709);
  double peak = 0, max_d = 0, sum = 0;
  const std::size_t n = std::size_t(reference.width) * reference.height;
  for (std::size_t p = 0; p < n; ++p) {
    const float* a = &approx.pixels[p * approx.channels];
    const float* b = &reference.pixels[p * reference.channels];
    peak = std::max(peak, w[0] * b[0] + w[1] * b[1] + w[2] * b[2]);
    for (int c = 0; c < 3; ++c) {
      const double d = double(a[c]) - double(b[c]);
      max_d = std::max(max_d, std::abs(d));
      sum += d * d;
    }
  }
  if (peak <= 0) return {};
  return {max_d / peak, std::sqrt(sum / double(3 * n)) / peak};
}

double psnr(const Image& a, const Image& b) {
  if (a.width != b.width || a.height != b.height || a.channels != b.channels) throw Error("psnr: the images differ in size");
  double sum = 0;
  for (std::size_t i = 0; i < a.pixels.size(); ++i) {
    const double d = double(a.pixels[i]) - double(b.pixels[i]);
    sum += d * d;
  }
  const double mse = sum / double(a.pixels.size());
  return mse > 0 ? 10 * std::log10(1 / mse) : 1e9;
}

}  // namespace hydrolux::scene
