// hydrolux shaders (HLSL): the Preetham sky, the sun's disk and the ground (docs/sky.md, "Sun and
// sky"); the same as ../glsl/hydrolux_sky.glsl. Every field comes from sky.json at the sun's
// elevation (interpolate linearly between its 1-degree rows):
//   perez_a .. perez_e  Preetham's Perez coefficients A..E, each float3(for Y, for x, for y)
//   zenith              float3(Y_z in cd/m^2 = 1000 x zenith_Y_kcd, x_z, y_z)
//   xyz_to_rgb          the XYZ -> linear Rec.709 matrix, rows as in sky.json (mul(M, xyz)); in a
//                       constant buffer declare it row_major or upload its transpose
//   sun_dir             s = hx_dir(sun_az, sun_el)
//   sun_rgb             the sun's illuminance per channel on a surface facing it (lux)
//   sky_irradiance      E_sky, the sky's illuminance on a horizontal surface per channel (lux)
//   ground_albedo       sky.json's ground_albedo
#ifndef HYDROLUX_SKY_HLSL
#define HYDROLUX_SKY_HLSL
#include "hydrolux_common.hlsl"

struct HxSky {
  float3 perez_a, perez_b, perez_c, perez_d, perez_e;
  float3 zenith;
  row_major float3x3 xyz_to_rgb;
  float3 sun_dir;
  float3 sun_rgb;
  float3 sky_irradiance;
  float3 ground_albedo;
};

// The Perez function F(t, g) for Y, x and y at once; cos t clamped to >= 0.01, g in radians.
float3 hx_perez(HxSky sky, float cos_t, float gamma_rad) {
  float c = max(cos_t, 0.01);
  float cg = cos(gamma_rad);
  return (1.0 + sky.perez_a * exp(sky.perez_b / c)) *
         (1.0 + sky.perez_c * exp(sky.perez_d * gamma_rad) + sky.perez_e * cg * cg);
}

// Preetham's sky radiance (cd/m^2, linear Rec.709) seen along the unit direction v (v.y >= 0).
float3 hx_sky_radiance(HxSky sky, float3 v) {
  float gamma_rad = hx_angle_deg(v, sky.sun_dir) / HX_DEG;
  float theta_s = acos(clamp(sky.sun_dir.y, -1.0, 1.0));
  float3 yxy = sky.zenith * hx_perez(sky, v.y, gamma_rad) / hx_perez(sky, 1.0, theta_s);
  float Y = yxy.x, x = yxy.y, y = yxy.z;
  float3 xyz = float3(x / y * Y, Y, (1.0 - x - y) / y * Y);
  return mul(sky.xyz_to_rgb, xyz);
}

// The ground, a Lambertian plane: rho / pi * (sun_rgb sin h + E_sky).
float3 hx_ground_radiance(HxSky sky) {
  return sky.ground_albedo / HX_PI * (sky.sun_rgb * max(sky.sun_dir.y, 0.0) + sky.sky_irradiance);
}

// The sun's radiance on its disk: sun_rgb / Omega_sun, Omega_sun = 2 pi (1 - cos 0.265 deg).
float3 hx_sun_disk_radiance(HxSky sky) {
  float h = sin(0.5 * HX_SUN_RADIUS_DEG / HX_DEG);
  float omega = 4.0 * HX_PI * h * h;  // 2 pi (1 - cos a) = 4 pi sin^2(a / 2), exact in floats
  return sky.sun_rgb / omega;
}

// The ground (v.y < 0), else the sun's disk (within 0.265 degrees of the sun), else the sky.
float3 hx_background(HxSky sky, float3 v) {
  if (v.y < 0.0) return hx_ground_radiance(sky);
  if (hx_angle_deg(v, sky.sun_dir) < HX_SUN_RADIUS_DEG) return hx_sun_disk_radiance(sky);
  return hx_sky_radiance(sky, v);
}

// The sky's polarisation (docs/sky.md, "Polarisation"; sky.json's "polarization"): polarised
// normal to the scattering plane with degree P(gamma) = P90 (1 - cos^2) / (P90 (1 + cos^2) + 1 - P90),
// cos gamma = dot(v, s), P90 = max_dolp (sky.json's polarization.sky_max_dolp, 0.8).
float hx_sky_dolp(float cos_gamma, float max_dolp) {
  float c2 = cos_gamma * cos_gamma;
  float den = max_dolp * (1.0 + c2) + 1.0 - max_dolp;
  return den > 0.0 ? max_dolp * (1.0 - c2) / den : 0.0;
}

// The degree of polarisation of hx_background(sky, v): the sky's; 0 on the sun's disk and the ground.
float hx_background_dolp(HxSky sky, float3 v, float max_dolp) {
  if (v.y < 0.0) return 0.0;
  if (hx_angle_deg(v, sky.sun_dir) < HX_SUN_RADIUS_DEG) return 0.0;
  return hx_sky_dolp(dot(v, sky.sun_dir), max_dolp);
}

#endif
