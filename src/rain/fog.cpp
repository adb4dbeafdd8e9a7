// Fog, haze and mist (rain/fog.hpp; docs/fog.md).
#include "hydrolux/rain/fog.hpp"

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

#include "hydrolux/core/error.hpp"
#include "hydrolux/rain/params.hpp"
#include "hydrolux/scatter/amplitudes.hpp"
#include "hydrolux/scatter/mie.hpp"

namespace hydrolux::rain {

namespace {

constexpr double kWaterDensityGM3 = 1e6;  // g/m^3
constexpr double kWaterIndex = 1.333;
constexpr double kPi = std::numbers::pi;

double luminance(double r, double g, double b) { return 0.2126 * r + 0.7152 * g + 0.0722 * b; }

// The radius range the quadratures cover: the modified gamma r^alpha exp(-alpha r / r_mode) holds
// all but ~1e-12 of its third moment between r_mode / 30 and r_mode (10 + 40 / alpha).
std::pair<double, double> radius_range_m(const FogSettings& s) {
  const double rm = s.mode_radius_um * 1e-6;
  return {rm / 30, rm * (10 + 40 / s.size_alpha)};
}

double wavenumber(const FogSettings& s) { return 2 * kPi / (s.wavelength_nm * 1e-9); }

}  // namespace

double koschmieder_beta_per_m(double visibility_m) { return kKoschmieder / visibility_m; }
double koschmieder_visibility_m(double beta_per_m) { return kKoschmieder / beta_per_m; }

void validate(const FogSettings& s) {
  FogOptions o;
  o.settings = s;
  for (const auto& f : fog_params()) {
    if (f.param.group != "fog") continue;
    const double v = f.get(o);
    if (!std::isnan(v)) f.param.check(v);
  }
  if (s.visibility_m.has_value() == s.lwc_g_m3.has_value())
    throw ParamError(s.visibility_m ? "{lwc_g_m3}: give {visibility_m} or {lwc_g_m3}, not both"
                                    : "{visibility_m}: give the fog's visibility in metres (Koschmieder), or "
                                      "{lwc_g_m3} for Mie over the droplets");
}

scatter::SizeDistribution fog_distribution(const FogSettings& s) {
  // n ~ r^alpha exp(-b r), mode alpha / b: the library's gamma with shape a = alpha + 1, scale
  // r_mode / alpha, mean a r_mode / alpha, relative width 1 / sqrt(a).
  const double a = s.size_alpha + 1, rm = s.mode_radius_um * 1e-6;
  const double mean = a * rm / s.size_alpha, w = 1 / std::sqrt(a);
  auto unit = scatter::SizeDistribution::gamma(mean, w, 1.0);
  if (!s.lwc_g_m3) return unit;
  const double per_drop_g = kWaterDensityGM3 * 4.0 / 3.0 * kPi * unit.moment(3);
  return scatter::SizeDistribution::gamma(mean, w, *s.lwc_g_m3 / per_drop_g);
}

double mie_fog_beta_per_m(const FogSettings& s, int nodes) {
  if (!s.lwc_g_m3) throw std::logic_error("mie_fog_beta_per_m: lwc_g_m3 not given");
  const auto [lo, hi] = radius_range_m(s);
  const auto q = fog_distribution(s).quadrature(nodes, lo, hi, true);
  return scatter::mie_bulk_optics({kWaterIndex, 0.0}, wavenumber(s), q, 1).extinction_per_m;
}

PhaseTable PhaseTable::from_values(std::vector<double> p_u) {
  PhaseTable t;
  const std::size_t n = p_u.size();
  if (n < 2) throw std::logic_error("PhaseTable: needs two values at least");
  const double du = 1.0 / double(n - 1);
  // F(u) = integral_0^u 2 p u' du' (dOmega / 4 pi = 2 u du), trapezoid; then normalised.
  std::vector<double> cum(n, 0.0);
  for (std::size_t i = 1; i < n; ++i)
    cum[i] = cum[i - 1] + du * (p_u[i - 1] * double(i - 1) * du + p_u[i] * double(i) * du);
  const double total = cum.back();
  if (!(total > 0)) throw std::logic_error("PhaseTable: no scattering");
  for (auto& v : p_u) v /= total;
  for (auto& v : cum) v /= total;
  t.p = std::move(p_u);
  t.cum = std::move(cum);
  return t;
}

namespace {
double lerp_table(const std::vector<double>& v, double u) {
  const double pos = std::clamp(u, 0.0, 1.0) * double(v.size() - 1);
  const std::size_t i = std::min(std::size_t(pos), v.size() - 2);
  const double f = pos - double(i);
  return v[i] * (1 - f) + v[i + 1] * f;
}
}  // namespace

double PhaseTable::at(double u) const {
  const double v = lerp_table(p, u);
  if (!divided_by_u) return v;
  return u > 0 ? v / u : std::numeric_limits<double>::infinity();
}
double PhaseTable::cumulative(double u) const { return lerp_table(cum, u); }

PhaseTable PhaseTable::apparent() const {
  // P(u) = integral_u^1 p dv (trapezoid), p_app = P / u; F_app(u) = integral_0^u 2 P du'.
  const std::size_t n = p.size();
  const double du = 1.0 / double(n - 1);
  PhaseTable t;
  t.divided_by_u = true;
  t.p.assign(n, 0.0);
  for (std::size_t i = n - 1; i-- > 0;) t.p[i] = t.p[i + 1] + 0.5 * du * (p[i] + p[i + 1]);
  t.cum.assign(n, 0.0);
  for (std::size_t i = 1; i < n; ++i) t.cum[i] = t.cum[i - 1] + du * (t.p[i - 1] + t.p[i]);
  return t;
}

FogOptics fog_optics(const FogSettings& s, int angles, int phase_nodes) {
  validate(s);
  FogOptics o;
  const auto dist = fog_distribution(s);
  if (s.lwc_g_m3) {
    o.beta_per_m = mie_fog_beta_per_m(s);
    o.lwc_g_m3 = *s.lwc_g_m3;
    o.number_per_cm3 = dist.number_concentration() * 1e-6;
  } else {
    o.beta_per_m = koschmieder_beta_per_m(*s.visibility_m);
    o.lwc_g_m3 = o.number_per_cm3 = std::numeric_limits<double>::quiet_NaN();
  }
  o.visibility_m = koschmieder_visibility_m(o.beta_per_m);
  o.effective_radius_um = dist.effective_radius() * 1e6;
  // The phase function: sum over radii of w (|S1|^2 + |S2|^2), normalised on the table.
  const auto [lo, hi] = radius_range_m(s);
  const auto q = dist.quadrature(phase_nodes, lo, hi, true);
  const double k = wavenumber(s);
  std::vector<double> mu(static_cast<std::size_t>(angles)), p(static_cast<std::size_t>(angles), 0.0);
  for (int i = 0; i < angles; ++i) {
    const double u = double(i) / (angles - 1);
    mu[std::size_t(i)] = 1 - 2 * u * u;
  }
  std::vector<scatter::Complex> s1(mu.size()), s2(mu.size());
  double gsum = 0, csum = 0;
  for (std::size_t j = 0; j < q.size(); ++j) {
    const auto c = scatter::mie_coefficients({kWaterIndex, 0.0}, k * q.radius_m[j]);
    const auto e = scatter::mie_efficiencies(c);
    const double csca = e.qsca * kPi * q.radius_m[j] * q.radius_m[j] * q.weight[j];
    gsum += csca * e.g;
    csum += csca;
    scatter::mie_amplitudes(c, mu, s1, s2, 1);  // the SIMD path, one thread: the same bits every run
    for (std::size_t i = 0; i < mu.size(); ++i) p[i] += q.weight[j] * (std::norm(s1[i]) + std::norm(s2[i]));
  }
  o.g = csum > 0 ? gsum / csum : 0;
  o.phase = PhaseTable::from_values(std::move(p));
  o.apparent = o.phase.apparent();
  return o;
}

Vec3 estimate_sky(const Image& frame) {
  const int rows = std::max(1, frame.height / 10);
  std::vector<std::pair<double, std::size_t>> lum;
  lum.reserve(std::size_t(rows) * std::size_t(frame.width));
  for (int y = 0; y < rows; ++y)
    for (int x = 0; x < frame.width; ++x) {
      const double r = std::max(0.f, frame.at(x, y, 0)), g = std::max(0.f, frame.at(x, y, 1)),
                   b = std::max(0.f, frame.at(x, y, 2));
      lum.emplace_back(luminance(r, g, b), std::size_t(y) * std::size_t(frame.width) + std::size_t(x));
    }
  const std::size_t keep = std::max<std::size_t>(1, lum.size() / 10);
  // The brightest tenth, ties broken by position: the same pixels whatever the sort.
  std::nth_element(lum.begin(), lum.begin() + std::ptrdiff_t(keep - 1), lum.end(),
                   [](const auto& a, const auto& b) { return a.first != b.first ? a.first > b.first : a.second < b.second; });
  std::sort(lum.begin(), lum.begin() + std::ptrdiff_t(keep), [](const auto& a, const auto& b) { return a.second < b.second; });
  Vec3 sum(0.0);
  for (std::size_t i = 0; i < keep; ++i) {
    const std::size_t px = lum[i].second;
    const int x = int(px % std::size_t(frame.width)), y = int(px / std::size_t(frame.width));
    for (int c = 0; c < 3; ++c) sum[c] += std::max(0.f, frame.at(x, y, c));
  }
  return sum / double(keep);
}

Image fog_glow(const Image& source_in, const RainCamera& cam, const PhaseTable& apparent, int cells, double pair_budget,
               const ProgressFn& progress) {
  const auto step = [&](double fraction) {  // where the caller may stop the work (its callback throws)
    if (progress) progress(fraction, "glow");
  };
  const int W = source_in.width, H = source_in.height;
  // Sources below 1e-6 of the brightest are left out (a lamp behind an optical depth of 20 still has
  // a positive tau e^-tau): they would only make the cells coarser.
  Image source = source_in;
  float peak = 0;
  for (float v : source.pixels) peak = std::max(peak, v);
  for (float& v : source.pixels)
    if (v <= 1e-6f * peak) v = 0;
  // The finest blocks whose source cells times cells stay within the budget, at most as coarse as
  // `cells` along the longer side: a few lamps are summed on fine cells, a frame full of sources on
  // coarse ones.
  const int f_max = std::max(1, (std::max(W, H) + cells - 1) / cells);
  int f = f_max;
  for (int k = 1; k < f_max; ++k) {
    step(0);
    const int kw = (W + k - 1) / k, kh = (H + k - 1) / k;
    std::vector<char> lit(std::size_t(kw) * std::size_t(kh), 0);
    for (int y = 0; y < H; ++y)
      for (int x = 0; x < W; ++x)
        if (source.at(x, y, 0) > 0 || source.at(x, y, 1) > 0 || source.at(x, y, 2) > 0)
          lit[std::size_t(y / k) * std::size_t(kw) + std::size_t(x / k)] = 1;
    const double n = double(std::count(lit.begin(), lit.end(), char(1)));
    if (n * double(kw) * double(kh) <= pair_budget) {
      f = k;
      break;
    }
  }
  const int cw = (W + f - 1) / f, ch = (H + f - 1) / f;
  const double pitch = 1.0 / cam.focal_px();  // tan per pixel
  // Per cell: mean source radiance, solid angle, and the direction of its centre.
  std::vector<Vec3> e(std::size_t(cw) * std::size_t(ch), Vec3(0.0)), dir(e.size());
  std::vector<double> omega(e.size(), 0.0);
  for (int cy = 0; cy < ch; ++cy)
    for (int cx = 0; cx < cw; ++cx) {
      const std::size_t ci = std::size_t(cy) * std::size_t(cw) + std::size_t(cx);
      int n = 0;
      for (int y = cy * f; y < std::min(H, (cy + 1) * f); ++y)
        for (int x = cx * f; x < std::min(W, (cx + 1) * f); ++x) {
          const Vec3 r = cam.ray(x + 0.5, y + 0.5);
          omega[ci] += pitch * pitch * r.z * r.z * r.z;  // a pixel's solid angle, cos^3 off axis
          for (int c = 0; c < 3; ++c) e[ci][c] += source.at(x, y, c);
          ++n;
        }
      e[ci] /= double(n);
      dir[ci] = cam.ray(0.5 * (cx * f + std::min(W, (cx + 1) * f)), 0.5 * (cy * f + std::min(H, (cy + 1) * f)));
    }
  std::vector<Vec3> g(e.size(), Vec3(0.0));
  for (std::size_t s = 0; s < e.size(); ++s) {
    if (e[s][0] <= 0 && e[s][1] <= 0 && e[s][2] <= 0) continue;
    step(double(s) / double(e.size()));
    // The cell's own light within the cap of its solid angle: 2 pi (1 - cos) = 4 pi u^2.
    g[s] += e[s] * apparent.cumulative(std::sqrt(omega[s] / (4 * kPi)));
    const Vec3 w = e[s] * (omega[s] / (4 * kPi));
    for (std::size_t t = 0; t < e.size(); ++t) {
      if (t == s) continue;
      const double u = 0.5 * glm::length(dir[t] - dir[s]);
      g[t] += w * apparent.at(u);
    }
  }
  Image out(W, H, 3);
  for (int y = 0; y < H; ++y) {
    const double fy = std::clamp((y + 0.5) / f - 0.5, 0.0, double(ch - 1));
    const int y0 = std::min(int(fy), ch - 1), y1 = std::min(y0 + 1, ch - 1);
    const double ty = fy - y0;
    for (int x = 0; x < W; ++x) {
      const double fx = std::clamp((x + 0.5) / f - 0.5, 0.0, double(cw - 1));
      const int x0 = std::min(int(fx), cw - 1), x1 = std::min(x0 + 1, cw - 1);
      const double tx = fx - x0;
      const auto at = [&](int xx, int yy) { return g[std::size_t(yy) * std::size_t(cw) + std::size_t(xx)]; };
      const Vec3 v = (at(x0, y0) * (1 - tx) + at(x1, y0) * tx) * (1 - ty) + (at(x0, y1) * (1 - tx) + at(x1, y1) * tx) * ty;
      for (int c = 0; c < 3; ++c) out.at(x, y, c) = float(v[c]);
    }
  }
  return out;
}

FogVeil fog_veil(const Image& frame, const Image* depth, const RainCamera& cam, const FogSettings& s,
                 const FogOptics& optics, std::optional<Vec3> sky_given, const ProgressFn& progress) {
  const auto row = [&](double fraction) {  // once a row: where the caller may stop the work
    if (progress) progress(fraction, "fog");
  };
  validate(cam);
  if (frame.width != cam.width || frame.height != cam.height || frame.channels < 3)
    throw Error(fmt::format("fog: the frame is {}x{}x{}; the camera is {}x{} and needs 3 channels at least", frame.width,
                            frame.height, frame.channels, cam.width, cam.height));
  if (depth && (depth->width != frame.width || depth->height != frame.height || depth->channels != 1))
    throw Error("fog: the depth map must be one channel of the frame's size");
  const int W = frame.width, H = frame.height, C = frame.channels;
  FogVeil out;
  FogStats& st = out.stats;
  // Finite input, negatives read as 0.
  for (int y = 0; y < H; ++y) {
    row(0.1 * y / H);
    for (int x = 0; x < W; ++x)
      for (int c = 0; c < C; ++c) {
        const float v = frame.at(x, y, c);
        if (!std::isfinite(v))
          throw Error(fmt::format("pixel ({}, {}) channel {} is {}: fog needs finite linear values (negative ones read as 0)",
                                  x, y, c, std::isnan(v) ? "NaN" : v > 0 ? "+inf" : "-inf"));
        if (c < 3 && v < 0) ++st.negative_values_clamped;
      }
  }
  const auto clear = [&](int x, int y, int c) { return std::max(0.f, frame.at(x, y, c)); };
  Vec3 A;
  if (sky_given) {
    A = *sky_given;
  } else if (st.negative_values_clamped == 0) {
    A = estimate_sky(frame);
  } else {
    Image clamped = frame;
    for (std::size_t i = 0; i < clamped.pixels.size(); ++i)
      if (int(i % std::size_t(C)) < 3) clamped.pixels[i] = std::max(0.f, clamped.pixels[i]);
    A = estimate_sky(clamped);
  }
  out.sky = A;
  std::vector<float> z;
  if (!depth) z = ground_plane_depth(cam, s.backdrop_m);
  const std::size_t npx = std::size_t(W) * std::size_t(H);
  out.t.assign(npx, 0.0);
  out.tau.assign(npx, std::numeric_limits<float>::infinity());
  Image source(W, H, 3);
  std::vector<float> ranges;
  ranges.reserve(npx);
  double tsum = 0, tmin = 1, tmax = 0;
  std::size_t sky_px = 0, glow_src = 0;
  for (int y = 0; y < H; ++y) {
    row(0.1 + 0.2 * y / H);
    for (int x = 0; x < W; ++x) {
      const std::size_t i = std::size_t(y) * std::size_t(W) + std::size_t(x);
      const double zc = depth ? double(depth->pixels[i]) : double(z[i]);
      double t = 0, tau = 0;
      if (std::isfinite(zc) && zc > 0) {
        const double d = zc / cam.ray(x + 0.5, y + 0.5).z;
        tau = optics.beta_per_m * d;
        t = std::exp(-tau);
        out.tau[i] = float(tau);
        ranges.push_back(float(d));
      } else {
        ++sky_px;
      }
      out.t[i] = t;
      tsum += t;
      tmin = std::min(tmin, t);
      tmax = std::max(tmax, t);
      bool src = false;
      for (int c = 0; c < 3; ++c) {
        const double excess = std::max(0.0, double(clear(x, y, c)) - A[c]);
        if (excess > 0) src = true;
        source.at(x, y, c) = float(excess * tau * t);  // scattered once, and not again
      }
      glow_src += src ? 1 : 0;
    }
  }
  if (s.glow) {
    out.glow = fog_glow(source, cam, optics.apparent, kGlowCells, kGlowPairBudget, progress);
    double gl = 0;
    for (int y = 0; y < H; ++y)
      for (int x = 0; x < W; ++x) gl += luminance(out.glow.at(x, y, 0), out.glow.at(x, y, 1), out.glow.at(x, y, 2));
    st.glow_mean = gl / double(npx);
  }
  st.beta_per_m = optics.beta_per_m;
  st.visibility_m = optics.visibility_m;
  st.transmittance_mean = tsum / double(npx);
  st.transmittance_min = tmin;
  st.transmittance_max = tmax;
  if (!ranges.empty()) {
    const auto mid = ranges.begin() + std::ptrdiff_t(ranges.size() / 2);
    std::nth_element(ranges.begin(), mid, ranges.end());
    st.range_m_median = *mid;
  }
  st.sky_fraction = double(sky_px) / double(npx);
  st.sky = A;
  st.glow_source_fraction = double(glow_src) / double(npx);
  return out;
}

Image apply_fog_veil(const Image& frame, const FogVeil& veil) {
  const int W = frame.width, H = frame.height;
  Image out = frame;
  const Vec3& A = veil.sky;
  tbb::parallel_for(0, H, [&](int y) {
    for (int x = 0; x < W; ++x) {
      const std::size_t i = std::size_t(y) * std::size_t(W) + std::size_t(x);
      const double t = veil.t[i];
      for (int c = 0; c < 3; ++c) {
        const double I = std::max(0.f, frame.at(x, y, c));
        out.at(x, y, c) = float(I * t + A[c] * (1 - t));
        if (!veil.glow.pixels.empty()) out.at(x, y, c) += veil.glow.at(x, y, c);
      }
    }
  });
  return out;
}

FogFrame render_fog(const Image& frame, const Image* depth, const RainCamera& cam, const FogSettings& s,
                    const FogOptics& optics, std::optional<Vec3> sky_given, const ProgressFn& progress) {
  FogVeil veil = fog_veil(frame, depth, cam, s, optics, sky_given, progress);
  if (progress) progress(0.95, "fog");
  FogFrame out;
  out.stats = veil.stats;
  out.image = apply_fog_veil(frame, veil);
  out.alpha = Image(frame.width, frame.height, 1);
  for (std::size_t i = 0; i < out.alpha.pixels.size(); ++i) out.alpha.pixels[i] = float(1 - veil.t[i]);
  return out;
}

// ---- declared parameters ----

namespace {
using K = ParamKind;
}  // namespace

// The fog itself, declared here once: hydrolux fog's rows and hydrolux rain's fog rows (rain with fog,
// one veil) are these. A table of its own, made on first use, so that rain's table can take them
// while it is made.
const Param& fog_medium_param(std::string_view name) {
  static const Param table[] = {
      {"visibility_m", "--visibility-m", "fog", K::real, "m", 1, 1e5,
       "Meteorological visibility, m: beta = 3.912 / V (Koschmieder, 2% contrast); instead of --lwc-g-m3", "lwc_g_m3"},
      {"lwc_g_m3", "--lwc-g-m3", "fog", K::real, "g/m^3", 1e-4, 5,
       "Liquid water content, g/m^3: beta from Lorenz-Mie over the droplets (instead of --visibility-m)"},
      {"mode_radius_um", "--mode-radius-um", "fog", K::real, "um", 0.5, 50,
       "Droplets' mode radius, um (Shettle & Fenn 1979: 10 advection fog, 2 radiation fog)"},
      {"size_alpha", "--size-alpha", "fog", K::real, "", 1, 20,
       "Shape alpha of the droplets' modified gamma r^alpha exp(-alpha r / r_mode) (3 advection, 6 radiation fog)"},
      {"wavelength_nm", "--wavelength-nm", "fog", K::real, "nm", 380, 780, "Wavelength of the Mie optics, nm (fog is grey)"},
      {"glow", "--no-glow", "fog", K::flag, "", 0, 1, "Leave out the forward-scattered glow around lights brighter than the sky"},
  };
  for (const Param& p : table)
    if (p.name == name) return p;
  throw std::logic_error("fog_medium_param: no parameter " + std::string(name));
}

// The camera and the files are hydrolux rain's (rain/params.cpp): the same quantities, declared
// there once; fog's rows copy them (made on first use, after rain's tables exist).
std::span<const Field<FogOptions>> fog_params() {
  static const Field<FogOptions> table[] = {
      {fog_medium_param("visibility_m"), HYDROLUX_PARAM_OPTIONAL(settings.visibility_m)},
      {fog_medium_param("lwc_g_m3"), HYDROLUX_PARAM_OPTIONAL(settings.lwc_g_m3)},
      {fog_medium_param("mode_radius_um"), HYDROLUX_PARAM_MEMBER(settings.mode_radius_um)},
      {fog_medium_param("size_alpha"), HYDROLUX_PARAM_MEMBER(settings.size_alpha)},
      {fog_medium_param("wavelength_nm"), HYDROLUX_PARAM_MEMBER(settings.wavelength_nm)},
      {{"backdrop_m", "--backdrop-m", "fog", K::real, "m", 1, 1e6,
        "Without --depth: the scene is the ground plane up to a backdrop this far, m"},
       HYDROLUX_PARAM_MEMBER(settings.backdrop_m)},
      {fog_medium_param("glow"), HYDROLUX_PARAM_MEMBER(settings.glow)},
      {rain_param("focal_mm"), HYDROLUX_PARAM_MEMBER(camera.focal_mm)},
      {rain_param("fov_deg"), HYDROLUX_PARAM_OPTIONAL(fov_deg)},
      {rain_param("sensor_width_mm"), HYDROLUX_PARAM_MEMBER(camera.sensor_width_mm)},
      {rain_param("camera_height_m"), HYDROLUX_PARAM_MEMBER(camera.height_m)},
      {rain_param("pitch_deg"), HYDROLUX_PARAM_MEMBER(camera.pitch_deg)},
  };
  return table;
}

std::span<const Field<FogFileOptions>> fog_file_params() {
  static const Field<FogFileOptions> table[] = {
      {rain_param("png_compression"), HYDROLUX_PARAM_MEMBER(png_compression)},
      {rain_param("depth_scale_m"), HYDROLUX_PARAM_MEMBER(depth_scale_m)},
  };
  return table;
}

RainCamera fog_camera_for(const FogOptions& o, int width, int height) {
  RainCamera c = o.camera;
  c.width = width;
  c.height = height;
  if (o.fov_deg) c.focal_mm = focal_mm_from_fov(*o.fov_deg, c.sensor_width_mm);
  return c;
}

}  // namespace hydrolux::rain
