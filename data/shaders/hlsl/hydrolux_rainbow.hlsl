// hydrolux shaders (HLSL): Lee-table lookups (docs/sky.md, "The rain curtain"); the same as
// ../glsl/hydrolux_rainbow.glsl. A table is a Texture2D<float4> (R32G32B32A32_FLOAT or
// R32G32B32_FLOAT) of columns x rows texels, read with Load and interpolated here:
//   linear in the row axis (angle or cosine) between row centres, 0 outside the rows' range;
//   linear in ln(radius) between columns, the radius clamped to the columns' range.
//   rows = float4(first row's value, last row's value, row count, 1 if the axis is "cos" else 0)
//   cols = float4(radius_um[0], radius_um[columns-1], column count, 0)   (radius_scale "log")
#ifndef HYDROLUX_RAINBOW_HLSL
#define HYDROLUX_RAINBOW_HLSL
#include "hydrolux_common.hlsl"

// The fractional column of a radius (um) in a log-spaced table, clamped to [0, columns - 1].
float hx_lee_column(float4 cols, float radius_um) {
  if (cols.z <= 1.0) return 0.0;
  float c = log(radius_um / cols.x) / log(cols.y / cols.x) * (cols.z - 1.0);
  return clamp(c, 0.0, cols.z - 1.0);
}

// True when a radius lies within the table's columns (the corona table is not used outside them).
bool hx_lee_radius_in_range(float4 cols, float radius_um) {
  return radius_um >= min(cols.x, cols.y) && radius_um <= max(cols.x, cols.y);
}

// The fractional row of a scattering angle (degrees), or -1 outside the table's rows.
float hx_lee_row(float4 rows, float theta_deg) {
  float value = rows.w > 0.5 ? cos(theta_deg / HX_DEG) : theta_deg;
  float n = rows.z - 1.0;
  float r = n > 0.0 ? (value - rows.x) / (rows.y - rows.x) * n : 0.0;
  if (r < -1e-3 || r > n + 1e-3) return -1.0;
  return clamp(r, 0.0, n);
}

// Bilinear interpolation between texel centres at a fractional (column, row).
float3 hx_lee_fetch(Texture2D<float4> table, float column, float row) {
  uint width, height;
  table.GetDimensions(width, height);
  int c0 = int(floor(column)), r0 = int(floor(row));
  int c1 = min(c0 + 1, int(width) - 1), r1 = min(r0 + 1, int(height) - 1);
  float fc = column - float(c0), fr = row - float(r0);
  float3 t00 = table.Load(int3(c0, r0, 0)).rgb;
  float3 t10 = table.Load(int3(c1, r0, 0)).rgb;
  float3 t01 = table.Load(int3(c0, r1, 0)).rgb;
  float3 t11 = table.Load(int3(c1, r1, 0)).rgb;
  return lerp(lerp(t00, t10, fc), lerp(t01, t11, fc), fr);
}

// T_rgb (sr^-1) of one table at a scattering angle and a fractional column; 0 outside its rows.
float3 hx_lee_lookup(Texture2D<float4> table, float4 rows, float column, float theta_deg) {
  float row = hx_lee_row(rows, theta_deg);
  if (row < 0.0) return float3(0.0, 0.0, 0.0);
  return hx_lee_fetch(table, column, row);
}

// w(theta): 1 with the secondary bow on; smoothstep(132, 136, theta) without it. Applied to the
// rainbow table only.
float hx_secondary_weight(float theta_deg, bool secondary) {
  return secondary ? 1.0 : smoothstep(132.0, 136.0, theta_deg);
}

// The rainbow table's part: T_rgb(theta) w(theta) for theta in its rows (90-180), else 0.
float3 hx_rainbow_term(Texture2D<float4> rainbow, float4 rows, float column, float theta_deg,
                       bool secondary) {
  return hx_lee_lookup(rainbow, rows, column, theta_deg) * hx_secondary_weight(theta_deg, secondary);
}

// The corona table's part: T_rgb(theta) for theta in its rows (0-90) when the corona is on and the
// radius lies within its columns (1-50 um), else 0.
float3 hx_corona_term(Texture2D<float4> corona, float4 rows, float4 cols, float radius_um,
                      float theta_deg, bool corona_on) {
  if (!corona_on || !hx_lee_radius_in_range(cols, radius_um)) return float3(0.0, 0.0, 0.0);
  return hx_lee_lookup(corona, rows, hx_lee_column(cols, radius_um), theta_deg);
}

// ---- Non-spherical drops (hydrolux export --shape); the same as ../glsl/hydrolux_rainbow.glsl ----
// rainbow_shaped.f32 as a Texture3D<float4> (R32G32B32A32_FLOAT or R32G32B32_FLOAT) of columns x
// rows x positions texels: T_rgb (sr^-1, the primary and the secondary added) over radius,
// scattering angle and 19 position angles 0, 10, ..., 180 degrees (the depth, spread evenly), for
// the one sun elevation of its JSON. Its rows and cols float4 are built as a 2-D table's. Read with
// Load; linear in row and ln(radius), and linear in the position angle between the nearest layers.

// The position angle of the view ray v (degrees, [0, 180]) around the antisolar point a = -s, from
// the zenith side (0, the bow's top) to the nadir side (180, its bottom), the same left and right:
//   u0 = normalize(up - dot(up, a) a),  u90 = normalize(cross(a, u0)),  psi = atan2(|v.u90|, v.u0)
// 0 at the antisolar point itself and for a sun at the zenith (where it is undefined).
float hx_position_angle_deg(float3 v, float3 sun_dir) {
  float3 a = -sun_dir;
  float3 u = float3(0.0, 1.0, 0.0) - a.y * a;
  float l = length(u);
  if (l < 1e-6) return 0.0;
  float3 u0 = u / l;
  float3 u90 = normalize(cross(a, u0));
  float y = abs(dot(v, u90)), x = dot(v, u0);
  if (y == 0.0 && x == 0.0) return 0.0;
  return atan2(y, x) * HX_DEG;
}

// Bilinear interpolation between texel centres at a fractional (column, row) of layer k.
float3 hx_lee_fetch_layer(Texture3D<float4> table, float column, float row, int layer) {
  uint width, height, depth;
  table.GetDimensions(width, height, depth);
  int c0 = int(floor(column)), r0 = int(floor(row));
  int c1 = min(c0 + 1, int(width) - 1), r1 = min(r0 + 1, int(height) - 1);
  float fc = column - float(c0), fr = row - float(r0);
  float3 t00 = table.Load(int4(c0, r0, layer, 0)).rgb;
  float3 t10 = table.Load(int4(c1, r0, layer, 0)).rgb;
  float3 t01 = table.Load(int4(c0, r1, layer, 0)).rgb;
  float3 t11 = table.Load(int4(c1, r1, layer, 0)).rgb;
  return lerp(lerp(t00, t10, fc), lerp(t01, t11, fc), fr);
}

// T_rgb (sr^-1) of the 3-D table at a scattering angle, a fractional column and a position angle
// (degrees); 0 outside its rows.
float3 hx_shaped_lookup(Texture3D<float4> table, float4 rows, float column, float theta_deg,
                        float position_deg) {
  float row = hx_lee_row(rows, theta_deg);
  if (row < 0.0) return float3(0.0, 0.0, 0.0);
  uint width, height, depth;
  table.GetDimensions(width, height, depth);
  int n = int(depth);
  if (n < 2) return hx_lee_fetch_layer(table, column, row, 0);
  float p = clamp(position_deg * float(n - 1) / 180.0, 0.0, float(n - 1));
  int k = min(int(p), n - 2);
  float f = p - float(k);
  float3 a = hx_lee_fetch_layer(table, column, row, k);
  float3 b = hx_lee_fetch_layer(table, column, row, k + 1);
  return a + f * (b - a);
}

// The non-spherical drops' rainbow part: T_rgb(theta, psi) w(theta) for theta in its rows (90-180),
// else 0; psi = hx_position_angle_deg(v, sun_dir).
float3 hx_shaped_rainbow_term(Texture3D<float4> table, float4 rows, float column, float theta_deg,
                              float position_deg, bool secondary) {
  return hx_shaped_lookup(table, rows, column, theta_deg, position_deg) *
         hx_secondary_weight(theta_deg, secondary);
}

#endif
