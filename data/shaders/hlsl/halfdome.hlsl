// hydrolux shaders (HLSL): halfdome.hlsl, the half-dome optimisation; the same as
// ../glsl/halfdome.vert and halfdome.frag (the mesh is described there): hx_halfdome_vs +
// hx_halfdome_ps, drawn centred on the camera with no depth test into a screen-sized float target
// cleared to 0, read by example.hlsl with u_bow_source = 2. With a polariser, draw it again into a
// second float target (example.hlsl's u_bow_screen_q, t9) with the Stokes Q tables bound at t0, t1
// (rainbow_q.f32, rainbow_shaped_q.f32); Q is signed.
#include "hydrolux_common.hlsl"
#include "hydrolux_rainbow.hlsl"

cbuffer HydroluxHalfDome : register(b0) {
  row_major float4x4 u_view_proj;  // projection x view rotation (camera at the origin), mul(M, p)
  float4 u_rainbow_rows, u_rainbow_cols;
  float u_radius_um;
  int u_secondary;
  // Non-spherical drops (hydrolux export --shape): the position angle from the interpolated
  // direction (the view ray) and the sun.
  float3 u_sun_dir;
  int u_shaped;
  float4 u_rainbow_shaped_rows, u_rainbow_shaped_cols;
};

Texture2D<float4> u_rainbow : register(t0);
Texture3D<float4> u_rainbow_shaped : register(t1);

struct HxDomeVertex {
  float3 direction : POSITION;   // unit direction (world)
  float theta : TEXCOORD0;       // its scattering angle (degrees)
};
struct HxDomeVaryings {
  float4 position : SV_Position;
  float theta : TEXCOORD0;
  float3 direction : TEXCOORD1;  // along the view ray at each pixel (the dome surrounds the camera)
};

HxDomeVaryings hx_halfdome_vs(HxDomeVertex input) {
  HxDomeVaryings output;
  output.position = mul(u_view_proj, float4(input.direction, 1.0));
  output.theta = input.theta;
  output.direction = input.direction;
  return output;
}

float4 hx_halfdome_ps(HxDomeVaryings input) : SV_Target {
  float3 T;
  if (u_shaped != 0) {
    float column = hx_lee_column(u_rainbow_shaped_cols, u_radius_um);
    float psi = hx_position_angle_deg(normalize(input.direction), u_sun_dir);
    T = hx_shaped_rainbow_term(u_rainbow_shaped, u_rainbow_shaped_rows, column, input.theta, psi,
                               u_secondary != 0);
  } else {
    float column = hx_lee_column(u_rainbow_cols, u_radius_um);
    T = hx_rainbow_term(u_rainbow, u_rainbow_rows, column, input.theta, u_secondary != 0);
  }
  return float4(T, 1.0);
}
