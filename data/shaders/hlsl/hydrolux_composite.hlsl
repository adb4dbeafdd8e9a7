// hydrolux shaders (HLSL): the rain curtain, the two blends and the tone map (docs/sky.md); the
// same as ../glsl/hydrolux_composite.glsl.
#ifndef HYDROLUX_COMPOSITE_HLSL
#define HYDROLUX_COMPOSITE_HLSL
#include "hydrolux_common.hlsl"

// The length (m) of the view ray inside the rain shell curtain.x..curtain.y, cut by the ground and
// by the nearest opaque surface at d_hit metres (1e30 for none):
//   l = max(0, min(d1, d_ground, d_hit) - d0),  d_ground = cam_height / -v.y if v.y < 0
float hx_rain_path(float3 v, float cam_height, float2 curtain, float d_hit) {
  float d_ground = v.y < 0.0 ? cam_height / -v.y : 1e30;
  return max(0.0, min(min(curtain.y, d_ground), d_hit) - curtain.x);
}

// tau_geo = beta_geo * l * moisture; beta_geo = pi M2 = pi 2 N0 / Lambda^3, N0 = 1.6e7 m^-4,
// Lambda = 8200 R^-0.21 m^-1 (5.0e-4 m^-1 at 5 mm/h).
float hx_tau_geo(float beta_geo, float path_m, float moisture) {
  return beta_geo * path_m * moisture;
}

// bow = sun_light T (1 - exp(-Q tau)) / Q, Q = 2 (cd/m^2).
float3 hx_bow_radiance(float3 sun_light, float3 T, float tau) {
  return sun_light * T * ((1.0 - exp(-HX_Q_EXT * tau)) / HX_Q_EXT);
}

// physical: bg exp(-Q tau) + bow.
float3 hx_blend_physical(float3 bg, float tau, float3 bow) {
  return bg * exp(-HX_Q_EXT * tau) + bow;
}

// whitepaper (srcblend = one, destblend = invsrccolor): bg + bow (1 - saturate(bg / L_ref)).
float3 hx_blend_whitepaper(float3 bg, float3 bow, float l_ref) {
  return bg + bow * (1.0 - saturate(bg / l_ref));
}

// A linear polariser in front of the camera (docs/sky.md, "Polarisation"), its axis angle_rad from the
// image's horizontal towards its up: cos 2 (chi - A), chi the angle of e = v x s (normal to the
// scattering plane) in the pixel's image basis (h = r made normal to v, w = v x h):
//   ea = cos A (e.h) + sin A (e.w),  c2 = clamp(2 ea^2 / ((e.e) (h.h)) - 1, -1, 1)   (0 at the sun and
// the antisolar point).
float hx_polarizer_cos2(float3 v, float3 sun_dir, float3 cam_r, float angle_rad) {
  float3 e = cross(v, sun_dir);
  float3 h = cam_r - dot(cam_r, v) * v;
  float3 w = cross(v, h);
  float ee = dot(e, e), hh = dot(h, h);
  if (!(ee > 1e-12 && hh > 1e-12)) return 0.0;
  float ea = cos(angle_rad) * dot(e, h) + sin(angle_rad) * dot(e, w);
  return clamp(2.0 * ea * ea / (ee * hh) - 1.0, -1.0, 1.0);
}

// What the filter passes of intensity I with Stokes Q: max((I + Q c2) / 2, 0).
float3 hx_polarize(float3 I, float3 Q, float c2) {
  return max(0.5 * (I + Q * c2), 0.0);
}

// The sRGB transfer function of a linear value in [0, 1].
float3 hx_srgb_encode(float3 c) {
  float3 lo = 12.92 * c;
  float3 hi = 1.055 * pow(max(c, 0.0031308), 1.0 / 2.4) - 0.055;
  return lerp(hi, lo, step(c, 0.0031308));
}

// x = 0.6 L / L_ref, extended Reinhard with white 6, clamped, sRGB-encoded (with a polariser
// L_ref / 2: one stop more exposure).
float3 hx_tonemap(float3 L, float l_ref) {
  float3 x = max(0.6 * L / l_ref, 0.0);
  float3 y = saturate(x * (1.0 + x / 36.0) / (1.0 + x));
  return hx_srgb_encode(y);
}

#endif
