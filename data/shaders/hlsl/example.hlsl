// hydrolux shaders (HLSL, shader model 5): example.hlsl, a complete full-screen pass (docs/sky.md):
// the sky, the sun and the ground (or your scene), the rain curtain with the rainbow and the corona
// from the Lee tables, the blend and the tone map. The same as ../glsl/example.frag.
//   vertex shader  hx_fullscreen_vs: Draw(3, 0) with no vertex buffer (one covering triangle)
//   pixel shader   hx_example_ps
// The constant buffer's fields are example.frag's uniforms (README.md next to this folder).
#include "hydrolux_common.hlsl"
#include "hydrolux_sky.hlsl"
#include "hydrolux_rainbow.hlsl"
#include "hydrolux_composite.hlsl"

cbuffer HydroluxConstants : register(b0) {
  HxSky u_sky;
  float2 u_resolution;        // viewport width, height (pixels)
  float u_tan_half_fov;       // tan(horizontal fov / 2)
  float u_cam_height;         // 1.7 m
  float3 u_cam_f;             // camera forward, right, up (world, unit)
  float u_l_ref;              // sky.json's l_ref (cd/m^2)
  float3 u_cam_r;
  float u_radius_um;          // the drops' radius (um)
  float3 u_cam_u;
  float u_beta_geo;           // pi M2 (m^-1)
  float3 u_light_color;       // (1, 1, 1)
  float u_moisture;           // [0, 1]
  float4 u_rainbow_rows, u_rainbow_cols, u_corona_rows, u_corona_cols;
  float2 u_curtain;           // d0, d1 (m)
  float u_moisture_noise;     // 0..1
  int u_secondary;            // 1 keep the secondary bow
  int u_corona_on;            // 1 add the corona
  int u_blend;                // 0 physical, 1 whitepaper
  int u_bow_source;           // 0 per pixel, 1 cube map, 2 screen texture (half dome)
  int u_has_scene;            // 1: u_scene holds opaque objects (rgb radiance, a distance m; 0 none)
  int u_output;               // 0 tone-mapped sRGB, 1 linear radiance
  // Non-spherical drops (hydrolux export --shape): appended, the fields above keep their offsets.
  float4 u_rainbow_shaped_rows, u_rainbow_shaped_cols;
  int u_shaped;               // 1: the rainbow from u_rainbow_shaped by the position angle
  // A linear polariser (docs/sky.md, "Polarisation"): appended, the fields above keep their offsets.
  float2 u_polarizer;         // (on 0/1, the axis A in radians from the image's horizontal towards up)
  float u_sky_max_dolp;       // P90, sky.json's polarization.sky_max_dolp (0.8)
};

Texture2D<float4> u_rainbow : register(t0);
Texture2D<float4> u_corona : register(t1);
TextureCube<float4> u_bow_cube : register(t2);
Texture2D<float4> u_bow_screen : register(t3);
Texture2D<float4> u_scene : register(t4);
Texture3D<float4> u_rainbow_shaped : register(t5);
// The Stokes Q (read with the polariser only): the tables *_q.f32 laid out as u_rainbow, u_corona,
// u_rainbow_shaped, and the cube map and the half dome's texture baked again from them.
Texture2D<float4> u_rainbow_q : register(t6);
Texture2D<float4> u_corona_q : register(t7);
TextureCube<float4> u_bow_cube_q : register(t8);
Texture2D<float4> u_bow_screen_q : register(t9);
Texture3D<float4> u_rainbow_shaped_q : register(t10);
SamplerState u_linear_clamp : register(s0);

float hx_hash3(float3 p) {
  return frac(sin(dot(p, float3(127.1, 311.7, 74.7))) * 43758.5453);
}
float hx_value_noise(float3 p) {
  float3 i = floor(p), f = frac(p);
  f = f * f * (3.0 - 2.0 * f);
  float n000 = hx_hash3(i), n100 = hx_hash3(i + float3(1, 0, 0));
  float n010 = hx_hash3(i + float3(0, 1, 0)), n110 = hx_hash3(i + float3(1, 1, 0));
  float n001 = hx_hash3(i + float3(0, 0, 1)), n101 = hx_hash3(i + float3(1, 0, 1));
  float n011 = hx_hash3(i + float3(0, 1, 1)), n111 = hx_hash3(i + float3(1, 1, 1));
  return lerp(lerp(lerp(n000, n100, f.x), lerp(n010, n110, f.x), f.y),
              lerp(lerp(n001, n101, f.x), lerp(n011, n111, f.x), f.y), f.z);
}
float hx_moisture_pattern(float3 v) {
  float3 p = float3(v.x * 7.0, v.y * 1.5, v.z * 7.0);
  float n = 0.6 * hx_value_noise(p) + 0.4 * hx_value_noise(p * 2.7 + 3.1);
  return smoothstep(0.3, 0.7, n);
}

float4 hx_fullscreen_vs(uint id : SV_VertexID) : SV_Position {
  float2 uv = float2((id << 1) & 2, id & 2);
  return float4(uv * 2.0 - 1.0, 0.0, 1.0);
}

// T_rgb w (sr^-1) along v at theta from the given tables (the intensity's, or the same lookups in the
// Stokes Q tables), from where u_bow_source says.
float3 hx_example_bow(Texture2D<float4> rainbow, Texture2D<float4> corona_table,
                      Texture3D<float4> shaped, TextureCube<float4> cube, Texture2D<float4> screen,
                      int2 texel, float3 v, float theta) {
  bool secondary = u_secondary != 0;
  float3 corona = hx_corona_term(corona_table, u_corona_rows, u_corona_cols, u_radius_um, theta,
                                 u_corona_on != 0);
  if (u_bow_source == 1) return cube.SampleLevel(u_linear_clamp, v, 0).rgb;
  if (u_bow_source == 2) return screen.Load(int3(texel, 0)).rgb + corona;
  if (u_shaped != 0) {
    float column = hx_lee_column(u_rainbow_shaped_cols, u_radius_um);
    float psi = hx_position_angle_deg(v, u_sky.sun_dir);
    return hx_shaped_rainbow_term(shaped, u_rainbow_shaped_rows, column, theta, psi, secondary) +
           corona;
  }
  float column = hx_lee_column(u_rainbow_cols, u_radius_um);
  return hx_rainbow_term(rainbow, u_rainbow_rows, column, theta, secondary) + corona;
}

float4 hx_example_ps(float4 position : SV_Position) : SV_Target {
  float2 pixel = position.xy;  // pixel centres, from the top row
  int2 texel = int2(position.xy);
  float3 v = hx_camera_ray(pixel, u_resolution, u_cam_f, u_cam_r, u_cam_u, u_tan_half_fov);
  float theta = hx_angle_deg(v, u_sky.sun_dir);

  float3 bg;
  float d_hit = 1e30;
  float4 scene = u_has_scene != 0 ? u_scene.Load(int3(texel, 0)) : float4(0, 0, 0, 0);
  bool polarizer = u_polarizer.x != 0.0;
  float c2 = polarizer ? hx_polarizer_cos2(v, u_sky.sun_dir, u_cam_r, u_polarizer.y) : 0.0;
  if (scene.a > 0.0) {
    bg = scene.rgb;
    d_hit = scene.a;
    if (polarizer) bg *= 0.5;  // your objects: unpolarised
  } else {
    bg = hx_background(u_sky, v);
    if (polarizer) bg = hx_polarize(bg, bg * hx_background_dolp(u_sky, v, u_sky_max_dolp), c2);
  }

  float3 T = hx_example_bow(u_rainbow, u_corona, u_rainbow_shaped, u_bow_cube, u_bow_screen, texel,
                            v, theta);
  if (polarizer) {
    float3 TQ = hx_example_bow(u_rainbow_q, u_corona_q, u_rainbow_shaped_q, u_bow_cube_q,
                               u_bow_screen_q, texel, v, theta);
    T = hx_polarize(T, TQ, c2);
  }

  float moisture = u_moisture;
  if (u_moisture_noise > 0.0) moisture *= lerp(1.0, hx_moisture_pattern(v), u_moisture_noise);
  float tau = hx_tau_geo(u_beta_geo, hx_rain_path(v, u_cam_height, u_curtain, d_hit), moisture);
  float3 bow = hx_bow_radiance(u_sky.sun_rgb * u_light_color, T, tau);
  float3 L = u_blend == 1 ? hx_blend_whitepaper(bg, bow, u_l_ref) : hx_blend_physical(bg, tau, bow);
  // With a polariser the exposure opens up one stop (l_ref / 2), as hydrolux sky's PNG.
  return float4(u_output == 1 ? L : hx_tonemap(L, polarizer ? 0.5 * u_l_ref : u_l_ref), 1.0);
}
