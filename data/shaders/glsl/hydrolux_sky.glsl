// hydrolux shaders: the Preetham sky, the sun's disk and the ground (docs/sky.md, "Sun and sky").
// Needs hydrolux_common.glsl.
//
// Every field of HxSky comes from sky.json (written by `hydrolux export`) at the sun's elevation
// (its rows are 1 degree apart: interpolate linearly between the two nearest):
//   perez_a .. perez_e  Preetham's Perez coefficients A..E, each vec3(for Y, for x, for y)
//   zenith              vec3(Y_z in cd/m^2 = 1000 x zenith_Y_kcd, x_z, y_z)
//   xyz_to_rgb          the XYZ -> linear Rec.709 matrix (sky.json's xyz_to_rgb is row-major:
//                       GLSL's mat3 constructor takes columns, so transpose when building it)
//   sun_dir             s = hx_dir(sun_az, sun_el)
//   sun_rgb             the sun's illuminance per channel on a surface facing it (lux)
//   sky_irradiance      E_sky, the sky's illuminance on a horizontal surface per channel (lux)
//   ground_albedo       sky.json's ground_albedo (grass: 0.10, 0.12, 0.07)
struct HxSky {
  vec3 perez_a, perez_b, perez_c, perez_d, perez_e;
  vec3 zenith;
  mat3 xyz_to_rgb;
  vec3 sun_dir;
  vec3 sun_rgb;
  vec3 sky_irradiance;
  vec3 ground_albedo;
};

// The Perez function F(t, g) = (1 + A exp(B / cos t)) (1 + C exp(D g) + E cos^2 g) for Y, x and y
// at once; cos t is clamped to >= 0.01, g in radians.
vec3 hx_perez(HxSky sky, float cos_t, float gamma_rad) {
  float c = max(cos_t, 0.01);
  float cg = cos(gamma_rad);
  return (1.0 + sky.perez_a * exp(sky.perez_b / c)) *
         (1.0 + sky.perez_c * exp(sky.perez_d * gamma_rad) + sky.perez_e * cg * cg);
}

// Preetham's sky radiance (cd/m^2, linear Rec.709) seen along the unit direction v (v.y >= 0).
vec3 hx_sky_radiance(HxSky sky, vec3 v) {
  float gamma_rad = hx_angle_deg(v, sky.sun_dir) / HX_DEG;
  float theta_s = acos(clamp(sky.sun_dir.y, -1.0, 1.0));
  vec3 yxy = sky.zenith * hx_perez(sky, v.y, gamma_rad) / hx_perez(sky, 1.0, theta_s);
  float Y = yxy.x, x = yxy.y, y = yxy.z;
  vec3 xyz = vec3(x / y * Y, Y, (1.0 - x - y) / y * Y);
  return sky.xyz_to_rgb * xyz;
}

// The ground, a Lambertian plane: rho / pi * (sun_rgb sin h + E_sky), the same in every direction.
vec3 hx_ground_radiance(HxSky sky) {
  return sky.ground_albedo / HX_PI * (sky.sun_rgb * max(sky.sun_dir.y, 0.0) + sky.sky_irradiance);
}

// The sun's radiance on its disk: sun_rgb / Omega_sun, Omega_sun = 2 pi (1 - cos 0.265 deg).
vec3 hx_sun_disk_radiance(HxSky sky) {
  float h = sin(0.5 * HX_SUN_RADIUS_DEG / HX_DEG);
  float omega = 4.0 * HX_PI * h * h;  // 2 pi (1 - cos a) = 4 pi sin^2(a / 2), exact in floats
  return sky.sun_rgb / omega;
}

// What lies behind everything along the unit view direction v: the ground (v.y < 0), else the sun's
// disk (within 0.265 degrees of the sun), else the sky.
vec3 hx_background(HxSky sky, vec3 v) {
  if (v.y < 0.0) return hx_ground_radiance(sky);
  if (hx_angle_deg(v, sky.sun_dir) < HX_SUN_RADIUS_DEG) return hx_sun_disk_radiance(sky);
  return hx_sky_radiance(sky, v);
}

// ---- The sky's polarisation (docs/sky.md, "Polarisation"; sky.json's "polarization") -----------
// Rayleigh single scattering with depolarisation: the sky is polarised normal to the scattering
// plane (sun, observer, sky point) with degree
//   P(gamma) = P90 (1 - cos^2 gamma) / (P90 (1 + cos^2 gamma) + 1 - P90),  cos gamma = dot(v, s)
// P90 = max_dolp, sky.json's polarization.sky_max_dolp (0.8); 0 at the sun and the antisolar point.
float hx_sky_dolp(float cos_gamma, float max_dolp) {
  float c2 = cos_gamma * cos_gamma;
  float den = max_dolp * (1.0 + c2) + 1.0 - max_dolp;
  return den > 0.0 ? max_dolp * (1.0 - c2) / den : 0.0;
}

// The degree of polarisation of hx_background(sky, v): the sky's; 0 on the sun's disk and the ground
// (unpolarised).
float hx_background_dolp(HxSky sky, vec3 v, float max_dolp) {
  if (v.y < 0.0) return 0.0;
  if (hx_angle_deg(v, sky.sun_dir) < HX_SUN_RADIUS_DEG) return 0.0;
  return hx_sky_dolp(dot(v, sky.sun_dir), max_dolp);
}
