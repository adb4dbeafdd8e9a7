#include "hydrolux/scene/sky_model.hpp"

#include <algorithm>
#include <cmath>

#include "hydrolux/core/error.hpp"
#include "hydrolux/core/math.hpp"
#include "hydrolux/scene/sky_params.hpp"

namespace hydrolux::scene {

namespace {

constexpr double kLumensPerWatt = 683.0;  // the luminous efficacy maximum, lm/W at 555 nm

// Preetham et al. 1999, Appendix A.2: each Perez coefficient is a T + b.
constexpr double kPerezY[5][2] = {{0.1787, -1.4630}, {-0.3554, 0.4275}, {-0.0227, 5.3251},
                                  {0.1206, -2.5771}, {-0.0670, 0.3703}};
constexpr double kPerezX[5][2] = {{-0.0193, -0.2592}, {-0.0665, 0.0008}, {-0.0004, 0.2125},
                                  {-0.0641, -0.8989}, {-0.0033, 0.0452}};
constexpr double kPerezYc[5][2] = {{-0.0167, -0.2608}, {-0.0950, 0.0092}, {-0.0079, 0.2102},
                                   {-0.0441, -1.6537}, {-0.0109, 0.0529}};
// Zenith chromaticity: [T^2 T 1] M [theta_s^3 theta_s^2 theta_s 1]^T.
constexpr double kZenithX[3][4] = {{0.00166, -0.00375, 0.00209, 0},
                                   {-0.02903, 0.06377, -0.03202, 0.00394},
                                   {0.11693, -0.21196, 0.06052, 0.25886}};
constexpr double kZenithY[3][4] = {{0.00275, -0.00610, 0.00317, 0},
                                   {-0.04214, 0.08970, -0.04153, 0.00516},
                                   {0.15346, -0.26756, 0.06670, 0.26688}};

Perez perez_of(const double (&c)[5][2], double T) {
  return {c[0][0] * T + c[0][1], c[1][0] * T + c[1][1], c[2][0] * T + c[2][1], c[3][0] * T + c[3][1],
          c[4][0] * T + c[4][1]};
}

double zenith_chromaticity(const double (&m)[3][4], double T, double theta_s) {
  const double t[3] = {T * T, T, 1};
  const double s[4] = {theta_s * theta_s * theta_s, theta_s * theta_s, theta_s, 1};
  double v = 0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 4; ++j) v += t[i] * m[i][j] * s[j];
  return v;
}

double luminance(const Vec3& rgb) {
  const auto w = color::luminance_weights(color::RgbSpace::rec709);
  return w[0] * rgb.x + w[1] * rgb.y + w[2] * rgb.z;
}

}  // namespace

Vec3 direction_from_angles(double az_deg, double el_deg) {
  const double az = deg_to_rad(az_deg), el = deg_to_rad(el_deg);
  return {std::sin(az) * std::cos(el), std::sin(el), std::cos(az) * std::cos(el)};
}

double kasten_young_air_mass(double elevation_deg) {
  return 1.0 / (std::sin(deg_to_rad(elevation_deg)) + 0.50572 * std::pow(elevation_deg + 6.07995, -1.6364));
}

double Perez::zenith_factor(double cos_t) const { return 1 + A * std::exp(B / std::max(cos_t, 0.01)); }

double Perez::sun_factor(double gamma) const {
  const double cg = std::cos(gamma);
  return 1 + C * std::exp(D * gamma) + E * cg * cg;
}

Vec3 xyY_to_rgb(const SunSky& s, double x, double y, double Y) {
  const color::Xyz c{x / y * Y, Y, (1 - x - y) / y * Y};
  const auto rgb = color::matmul(s.xyz_to_rgb, c);
  return {rgb[0], rgb[1], rgb[2]};
}

Vec3 sky_radiance(const SunSky& s, const Vec3& sun, const Vec3& view) {
  const double gamma = safe_acos(glm::dot(sun, view));
  const double cos_t = view.y;
  const double Y = s.zenith_Y_kcd * 1000 * s.perez[0](cos_t, gamma) / s.perez_at_sun[0];
  const double x = s.zenith_x * s.perez[1](cos_t, gamma) / s.perez_at_sun[1];
  const double y = s.zenith_y * s.perez[2](cos_t, gamma) / s.perez_at_sun[2];
  return xyY_to_rgb(s, x, y, Y);
}

SunSky make_sun_sky(double sun_elevation_deg, double turbidity) {
  const Param& elevation = sky_param("sun_elevation_deg");  // the declared range (sky_params.cpp)
  if (!(sun_elevation_deg >= elevation.lo && sun_elevation_deg <= elevation.hi))
    throw DomainError("sun_elevation_deg", sun_elevation_deg, elevation.lo, elevation.hi,
                      "the sun must be above the horizon");
  if (!(turbidity >= kMinTurbidity && turbidity <= kMaxTurbidity))
    throw DomainError("turbidity", turbidity, kMinTurbidity, kMaxTurbidity, "Preetham's sky model");
  SunSky s;
  s.sun_elevation_deg = sun_elevation_deg;
  s.turbidity = turbidity;
  const double T = turbidity;

  // The colour convention of the Lee tables: the G173 sun's white carried to D65.
  const auto g173 = color::Illuminant::astm_g173_direct();
  const color::Xyz white = color::integrate_xyz(g173, color::kCmfMinNm, color::kCmfMaxNm);
  s.xyz_to_rgb = color::multiply(color::xyz_to_rgb_matrix(color::RgbSpace::rec709),
                                 color::bradford_adaptation(white, color::d65_white()));

  // The sun: G173 (air mass 1.5) carried to the sun's air mass by Beer-Lambert with Preetham's
  // Rayleigh and aerosol optical depths (Appendix A.2; wavelengths in micrometres).
  s.air_mass = kasten_young_air_mass(sun_elevation_deg);
  const double beta = 0.04608 * T - 0.04586;
  color::Xyz sun{};
  for (int nm = int(color::kCmfMinNm); nm <= int(color::kCmfMaxNm); ++nm) {
    const double um = nm * 1e-3;
    const double tau = 0.008735 * std::pow(um, -4.08) + beta * std::pow(um, -1.3);
    const double e = g173(nm) * std::exp(-tau * (s.air_mass - 1.5));
    const double w = (nm == int(color::kCmfMinNm) || nm == int(color::kCmfMaxNm)) ? 0.5 : 1.0;  // trapezoid
    const auto cmf = color::cie1931(nm);
    sun.X += w * e * cmf.X;
    sun.Y += w * e * cmf.Y;
    sun.Z += w * e * cmf.Z;
  }
  sun = {sun.X * kLumensPerWatt, sun.Y * kLumensPerWatt, sun.Z * kLumensPerWatt};
  s.sun_illuminance_lux = sun.Y;
  {
    const auto rgb = color::matmul(s.xyz_to_rgb, sun);
    s.sun_rgb = {rgb[0], rgb[1], rgb[2]};
  }

  // The sky (Preetham Appendix A.2).
  const double theta_s = deg_to_rad(90.0 - sun_elevation_deg);
  const double chi = (4.0 / 9.0 - T / 120.0) * (kPi<double> - 2 * theta_s);
  s.zenith_Y_kcd = (4.0453 * T - 4.9710) * std::tan(chi) - 0.2155 * T + 2.4192;
  s.zenith_x = zenith_chromaticity(kZenithX, T, theta_s);
  s.zenith_y = zenith_chromaticity(kZenithY, T, theta_s);
  s.perez = {perez_of(kPerezY, T), perez_of(kPerezX, T), perez_of(kPerezYc, T)};
  for (int i = 0; i < 3; ++i) s.perez_at_sun[i] = s.perez[i](1.0, theta_s);

  // The sky's horizontal illuminance: a midpoint rule over 16 zenith x 64 azimuth cells.
  const Vec3 sun_dir = direction_from_angles(0, sun_elevation_deg);
  constexpr int kZenith = 16, kAzimuth = 64;
  const double dt = kPi<double> / 2 / kZenith, dp = 2 * kPi<double> / kAzimuth;
  Vec3 e_sky{0};
  for (int i = 0; i < kZenith; ++i) {
    const double t = (i + 0.5) * dt;
    for (int j = 0; j < kAzimuth; ++j) {
      const double p = (j + 0.5) * dp;
      const Vec3 d{std::sin(t) * std::sin(p), std::cos(t), std::sin(t) * std::cos(p)};
      e_sky += sky_radiance(s, sun_dir, d) * (std::cos(t) * std::sin(t) * dt * dp);
    }
  }
  s.sky_illuminance_rgb = e_sky;
  const double sin_h = std::sin(deg_to_rad(sun_elevation_deg));
  const Vec3 e_ground = s.sun_rgb * sin_h + e_sky;
  s.ground_rgb = Vec3{kGroundAlbedo[0], kGroundAlbedo[1], kGroundAlbedo[2]} * e_ground / kPi<double>;
  s.l_ref = luminance(e_ground) / kPi<double>;
  return s;
}

}  // namespace hydrolux::scene
