#pragma once
// The daylight a rainbow scene is lit by: the sun's direct beam at the ground, carried from ASTM
// G173's air mass 1.5 to the sun's elevation, and Preetham, Shirley and Smits' analytic sky (A
// Practical Analytic Model for Daylight, SIGGRAPH 1999), with a Lambertian ground lit by both.
// docs/sky.md states every equation; GLSL and HLSL twins live in data/shaders/.
//
// Units: photometric and absolute. Radiances are linear Rec.709 RGB in cd/m^2 per channel (the
// luminance 0.2126 R + 0.7152 G + 0.0722 B is in candela per square metre), after the Lee tables'
// white balance: XYZ -> RGB through Bradford(G173 sun white -> D65), so the air-mass-1.5 sun is
// neutral. Irradiances are in lux per channel on the same scale.
#include <array>

#include "hydrolux/color/cie.hpp"
#include "hydrolux/core/vec.hpp"

namespace hydrolux::scene {

// A direction of azimuth `az_deg` (from north, +z, towards east, +x) and elevation `el_deg` above
// the horizon (+y up): (sin az cos el, sin el, cos az cos el).
Vec3 direction_from_angles(double az_deg, double el_deg);

// Kasten and Young (1989): the relative optical air mass at the sun's apparent elevation (degrees,
// [0, 90]); 1 at the zenith, ~38 at the horizon.
double kasten_young_air_mass(double elevation_deg);

// Preetham's Perez function F(t, g) = (1 + A exp(B / cos t)) (1 + C exp(D g) + E cos^2 g), with
// cos t clamped to >= 0.01 (the horizon) and g in radians.
struct Perez {
  double A = 0, B = 0, C = 0, D = 0, E = 0;
  double zenith_factor(double cos_t) const;  // 1 + A exp(B / cos t), cos t clamped
  double sun_factor(double gamma) const;     // 1 + C exp(D g) + E cos^2 g
  double operator()(double cos_t, double gamma) const { return zenith_factor(cos_t) * sun_factor(gamma); }
};

inline constexpr double kMinTurbidity = 1.7, kMaxTurbidity = 10;  // Preetham's fitted range (2-10,
                                                                  // the formulas hold to ~1.7)
inline constexpr double kSunAngularRadiusDeg = 0.265;
inline constexpr double kCameraHeightM = 1.7;
inline constexpr std::array<double, 3> kGroundAlbedo{0.10, 0.12, 0.07};  // grass, linear Rec.709

// Everything about the sun and the sky that depends on the sun's elevation and the turbidity.
struct SunSky {
  double sun_elevation_deg = 0, turbidity = 0;
  double air_mass = 0;
  double sun_illuminance_lux = 0;        // direct normal illuminance E_v
  Vec3 sun_rgb{0};                       // the direct beam, lux per channel (luminance = E_v)
  double zenith_Y_kcd = 0, zenith_x = 0, zenith_y = 0;
  std::array<Perez, 3> perez;            // Y, x, y
  std::array<double, 3> perez_at_sun{};  // F(0, theta_s) for Y, x, y: the zenith normalisation
  Vec3 sky_illuminance_rgb{0};           // the sky's illuminance on a horizontal plane, lux
  Vec3 ground_rgb{0};                    // the ground's radiance, cd/m^2
  double l_ref = 0;                      // luminance of a white Lambertian ground: the exposure white
  color::Mat3 xyz_to_rgb{};              // Rec.709 after Bradford(G173 sun -> D65)
};

// Throws DomainError ("sun_elevation_deg" outside [0, 90], "turbidity" outside
// [kMinTurbidity, kMaxTurbidity]).
SunSky make_sun_sky(double sun_elevation_deg, double turbidity);

// The sky's radiance (cd/m^2, RGB) seen along unit direction `view` (view.y >= 0; below the
// horizon the horizon's value) with the sun at unit direction `sun`; no sun disk.
Vec3 sky_radiance(const SunSky& s, const Vec3& sun, const Vec3& view);

// ---- the sky's polarisation (docs/sky.md, "Polarisation") ----
//
// Rayleigh single scattering with depolarisation (Chandrasekhar, Radiative Transfer, 1950, ch. I
// sec. 18; Coulson, Polarization and Intensity of Light in the Atmosphere, 1988): the scattered
// light is an anisotropic-Rayleigh part, polarised normal to the scattering plane (the plane of the
// sun, the observer and the sky point), plus an unpolarised part standing for the depolarisation by
// the molecules' anisotropy, multiple scattering and aerosols. With P90 the degree of linear
// polarisation at 90 degrees from the sun, the degree at scattering angle gamma is
//   P(gamma) = P90 sin^2 gamma / (P90 (1 + cos^2 gamma) + 1 - P90),
// 0 at the sun and at the antisolar point (this model's only neutral points: Arago's, Babinet's and
// Brewster's come from multiple scattering, which it leaves out). P90 = (1 - rho) / (1 + rho) for a
// depolarisation ratio rho: 0.946 for air's molecules alone (rho = 0.0279, Young 1980); clear skies
// measure 0.6-0.85 (Coulson 1988; Pomozi, Horvath & Wehner 2001), hence kSkyMaxDolpDefault.
inline constexpr double kSkyMaxDolpDefault = 0.8;
inline constexpr double kAirDepolarizationRatio = 0.0279;
// P(gamma) for cos gamma = `cos_gamma`, P90 = `max_dolp` in [0, 1].
inline double sky_dolp(double cos_gamma, double max_dolp) {
  const double c2 = cos_gamma * cos_gamma;
  const double den = max_dolp * (1 + c2) + 1 - max_dolp;
  return den > 0 ? max_dolp * (1 - c2) / den : 0;
}

// xyY (Y in cd/m^2) -> the scene's linear RGB.
Vec3 xyY_to_rgb(const SunSky& s, double x, double y, double Y);

}  // namespace hydrolux::scene
