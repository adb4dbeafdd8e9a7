// hydrolux shaders: the rain curtain, the two blends and the tone map (docs/sky.md, "The rain
// curtain", "Blending", "Tone mapping"). Needs hydrolux_common.glsl.

// The length (m) of the view ray v (unit) inside the rain: the shell from curtain.x = d0 to
// curtain.y = d1 metres, cut by the ground (camera cam_height metres above it) and by the nearest
// opaque surface at d_hit metres (pass 1e30 for none; an object nearer than d0 hides the rain):
//   l = max(0, min(d1, d_ground, d_hit) - d0),  d_ground = cam_height / -v.y if v.y < 0
float hx_rain_path(vec3 v, float cam_height, vec2 curtain, float d_hit) {
  float d_ground = v.y < 0.0 ? cam_height / -v.y : 1e30;
  return max(0.0, min(min(curtain.y, d_ground), d_hit) - curtain.x);
}

// The projected-area optical depth tau_geo = beta_geo * l * moisture. beta_geo = pi M2 (m^-1), M2
// the second radius moment of Marshall and Palmer's distribution: with N0 = 1.6e7 m^-4 per metre of
// radius and Lambda = 8200 R^-0.21 m^-1, M2 = 2 N0 / Lambda^3 (5.0e-4 m^-1 at R = 5 mm/h).
float hx_tau_geo(float beta_geo, float path_m, float moisture) {
  return beta_geo * path_m * moisture;
}

// The light the rain scatters toward the eye (cd/m^2): sun_light = sun_rgb * light_color (lux per
// channel), T = T_rgb(theta) w(theta) (sr^-1), tau = tau_geo:
//   bow = sun_light T (1 - exp(-Q tau)) / Q,  Q = 2
vec3 hx_bow_radiance(vec3 sun_light, vec3 T, float tau) {
  return sun_light * T * ((1.0 - exp(-HX_Q_EXT * tau)) / HX_Q_EXT);
}

// physical (default): what is behind the rain dimmed by its transmittance, plus the bow.
vec3 hx_blend_physical(vec3 bg, float tau, vec3 bow) {
  return bg * exp(-HX_Q_EXT * tau) + bow;
}

// whitepaper (seed 002: srcblend = one, destblend = invsrccolor) in units of the reference white:
// bg + bow (1 - clamp(bg / L_ref, 0, 1)). Never dims the background; saturates where it is bright.
vec3 hx_blend_whitepaper(vec3 bg, vec3 bow, float l_ref) {
  return bg + bow * (1.0 - clamp(bg / l_ref, 0.0, 1.0));
}

// ---- A linear polariser in front of the camera (docs/sky.md, "Polarisation") -------------------
// Its transmission axis lies at angle_rad from the image's horizontal towards its up. The sky's and
// the rain's polarised light lies normal to the scattering plane, along e = v x s; in the pixel's
// image basis (h = the camera's right r made normal to v, w = v x h, up) the filter passes
// (I + Q cos 2 (chi - A)) / 2, chi e's angle. This is cos 2 (chi - A):
//   ea = cos A (e.h) + sin A (e.w),  c2 = clamp(2 ea^2 / ((e.e) (h.h)) - 1, -1, 1)
// 0 where the scattering plane is undefined (at the sun and the antisolar point: nothing polarised).
float hx_polarizer_cos2(vec3 v, vec3 sun_dir, vec3 cam_r, float angle_rad) {
  vec3 e = cross(v, sun_dir);
  vec3 h = cam_r - dot(cam_r, v) * v;
  vec3 w = cross(v, h);
  float ee = dot(e, e), hh = dot(h, h);
  if (!(ee > 1e-12 && hh > 1e-12)) return 0.0;
  float ea = cos(angle_rad) * dot(e, h) + sin(angle_rad) * dot(e, w);
  return clamp(2.0 * ea * ea / (ee * hh) - 1.0, -1.0, 1.0);
}

// What the filter passes of light of intensity I and Stokes Q (in the scattering plane's basis):
// max((I + Q c2) / 2, 0), c2 = hx_polarizer_cos2 (the tables' Q is not gamut-mapped as I is: where
// the two disagree past |Q| <= I, nothing passes). The background: hx_polarize(bg, bg P, c2) with
// P = hx_background_dolp (0.5 bg where unpolarised).
vec3 hx_polarize(vec3 I, vec3 Q, float c2) {
  return max(0.5 * (I + Q * c2), vec3(0.0));
}

// The sRGB transfer function of a linear value in [0, 1].
vec3 hx_srgb_encode(vec3 c) {
  vec3 lo = 12.92 * c;
  vec3 hi = 1.055 * pow(max(c, vec3(0.0031308)), vec3(1.0 / 2.4)) - 0.055;
  return mix(hi, lo, vec3(lessThanEqual(c, vec3(0.0031308))));
}

// The display value (sRGB-encoded, [0, 1]) of a radiance L: x = 0.6 L / L_ref, extended Reinhard
// with white 6 (x (1 + x / 36) / (1 + x)), clamped to [0, 1], then the sRGB curve. L_ref = the
// luminance of a white Lambertian surface lit like the ground, sky.json's l_ref (with a polariser,
// l_ref / 2: a camera opens up one stop for the half of unpolarised light that the filter passes).
vec3 hx_tonemap(vec3 L, float l_ref) {
  vec3 x = max(0.6 * L / l_ref, vec3(0.0));
  vec3 y = clamp(x * (1.0 + x / 36.0) / (1.0 + x), 0.0, 1.0);
  return hx_srgb_encode(y);
}
