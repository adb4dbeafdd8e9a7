// hydrolux shaders (HLSL): cubemap_bake.hlsl, the cube-map optimisation's bake; the same as
// ../glsl/cubemap_bake.frag. Render hx_fullscreen_vs (example.hlsl's, repeated here) + hx_cube_bake_ps
// into each face (u_face 0..5 = +X, -X, +Y, -Y, +Z, -Z) of an N x N float cube map (u_face_size =
// N); sample it with the view direction and a linear sampler (example.hlsl, u_bow_source = 1).
// With a polariser, bake a second float cube map (example.hlsl's u_bow_cube_q, t8) by the same pass
// with the Stokes Q tables bound at t0, t1, t2 (rainbow_q.f32, corona_q.f32, rainbow_shaped_q.f32);
// Q is signed.
#include "hydrolux_common.hlsl"
#include "hydrolux_rainbow.hlsl"

cbuffer HydroluxCubeBake : register(b0) {
  float3 u_sun_dir;
  float u_face_size;
  float4 u_rainbow_rows, u_rainbow_cols, u_corona_rows, u_corona_cols;
  float u_radius_um;
  int u_face;
  int u_secondary;
  int u_corona_on;
  // Non-spherical drops (hydrolux export --shape): each texel at its own position angle.
  float4 u_rainbow_shaped_rows, u_rainbow_shaped_cols;
  int u_shaped;
};

Texture2D<float4> u_rainbow : register(t0);
Texture2D<float4> u_corona : register(t1);
Texture3D<float4> u_rainbow_shaped : register(t2);

// The direction through face coordinates (sc, tc) in [-1, 1], tc growing with the texel row.
float3 hx_cube_face_dir(int face, float2 st) {
  float sc = st.x, tc = st.y;
  if (face == 0) return float3(1.0, -tc, -sc);
  if (face == 1) return float3(-1.0, -tc, sc);
  if (face == 2) return float3(sc, 1.0, tc);
  if (face == 3) return float3(sc, -1.0, -tc);
  if (face == 4) return float3(sc, -tc, 1.0);
  return float3(-sc, -tc, -1.0);
}

float4 hx_fullscreen_vs(uint id : SV_VertexID) : SV_Position {
  float2 uv = float2((id << 1) & 2, id & 2);
  return float4(uv * 2.0 - 1.0, 0.0, 1.0);
}

float4 hx_cube_bake_ps(float4 position : SV_Position) : SV_Target {
  float2 st = position.xy / u_face_size * 2.0 - 1.0;
  float3 d = normalize(hx_cube_face_dir(u_face, st));
  float theta = hx_angle_deg(d, u_sun_dir);
  float3 T = hx_corona_term(u_corona, u_corona_rows, u_corona_cols, u_radius_um, theta,
                            u_corona_on != 0);
  if (u_shaped != 0) {
    float column = hx_lee_column(u_rainbow_shaped_cols, u_radius_um);
    T += hx_shaped_rainbow_term(u_rainbow_shaped, u_rainbow_shaped_rows, column, theta,
                                hx_position_angle_deg(d, u_sun_dir), u_secondary != 0);
  } else {
    float column = hx_lee_column(u_rainbow_cols, u_radius_um);
    T += hx_rainbow_term(u_rainbow, u_rainbow_rows, column, theta, u_secondary != 0);
  }
  return float4(T, 1.0);
}
