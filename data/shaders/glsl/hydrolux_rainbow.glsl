// hydrolux shaders: Lee-table lookups (docs/sky.md, "The rain curtain"; docs/lee.md).
// Needs hydrolux_common.glsl.
//
// A table is a float texture of `columns` x `rows` texels (RGBA32F or RGB32F; the .f32 file's
// rows x columns x 3 floats, row 0 the first angle): texel (c, r) holds T_rgb in sr^-1 of the drop
// population of radius radius_um[c] at the scattering angle angle_deg[r] (or cos_angle[r]). It is
// read with texelFetch and interpolated here, so it needs no filtering support (float32 textures
// are not filterable in WebGL2 without OES_texture_float_linear):
//   linear in the row axis (angle or cosine) between row centres, 0 outside the rows' range;
//   linear in ln(radius) between columns, the radius clamped to the columns' range.
// Two vec4 describe a table (from its JSON sidecar):
//   rows = vec4(first row's value, last row's value, row count, 1.0 if the axis is "cos" else 0.0)
//          (the values are angle_deg[0], angle_deg[rows-1] in degrees, or cos_angle[0], ...)
//   cols = vec4(radius_um[0], radius_um[columns-1], column count, 0.0)   (radius_scale "log")

// The fractional column of a radius (um) in a log-spaced table, clamped to [0, columns - 1].
float hx_lee_column(vec4 cols, float radius_um) {
  if (cols.z <= 1.0) return 0.0;
  float c = log(radius_um / cols.x) / log(cols.y / cols.x) * (cols.z - 1.0);
  return clamp(c, 0.0, cols.z - 1.0);
}

// True when a radius lies within the table's columns (the corona table is not used outside them).
bool hx_lee_radius_in_range(vec4 cols, float radius_um) {
  return radius_um >= min(cols.x, cols.y) && radius_um <= max(cols.x, cols.y);
}

// The fractional row of a scattering angle (degrees), or -1.0 outside the table's rows.
float hx_lee_row(vec4 rows, float theta_deg) {
  float value = rows.w > 0.5 ? cos(theta_deg / HX_DEG) : theta_deg;
  float n = rows.z - 1.0;
  float r = n > 0.0 ? (value - rows.x) / (rows.y - rows.x) * n : 0.0;
  // A hair of tolerance at the ends (180 degrees computed in floats may come out a hair above).
  if (r < -1e-3 || r > n + 1e-3) return -1.0;
  return clamp(r, 0.0, n);
}

// Bilinear interpolation between texel centres at a fractional (column, row).
vec3 hx_lee_fetch(sampler2D table, float column, float row) {
  ivec2 size = textureSize(table, 0);
  int c0 = int(floor(column)), r0 = int(floor(row));
  int c1 = min(c0 + 1, size.x - 1), r1 = min(r0 + 1, size.y - 1);
  float fc = column - float(c0), fr = row - float(r0);
  vec3 t00 = texelFetch(table, ivec2(c0, r0), 0).rgb;
  vec3 t10 = texelFetch(table, ivec2(c1, r0), 0).rgb;
  vec3 t01 = texelFetch(table, ivec2(c0, r1), 0).rgb;
  vec3 t11 = texelFetch(table, ivec2(c1, r1), 0).rgb;
  return mix(mix(t00, t10, fc), mix(t01, t11, fc), fr);
}

// T_rgb (sr^-1) of one table at a scattering angle and a fractional column; 0 outside its rows.
vec3 hx_lee_lookup(sampler2D table, vec4 rows, float column, float theta_deg) {
  float row = hx_lee_row(rows, theta_deg);
  if (row < 0.0) return vec3(0.0);
  return hx_lee_fetch(table, column, row);
}

// w(theta): 1 with the secondary bow on; smoothstep(132, 136, theta) without it (Alexander's dark
// band lies between the secondary at 129 and the primary at 138 degrees). Applied to the rainbow
// table only (the corona, at theta < 20, stays).
float hx_secondary_weight(float theta_deg, bool secondary) {
  return secondary ? 1.0 : smoothstep(132.0, 136.0, theta_deg);
}

// The rainbow table's part: T_rgb(theta) w(theta) for theta in its rows (90-180), else 0.
vec3 hx_rainbow_term(sampler2D rainbow, vec4 rows, float column, float theta_deg, bool secondary) {
  return hx_lee_lookup(rainbow, rows, column, theta_deg) * hx_secondary_weight(theta_deg, secondary);
}

// The corona table's part: T_rgb(theta) for theta in its rows (0-90) when the corona is on and the
// radius lies within its columns (1-50 um), else 0.
vec3 hx_corona_term(sampler2D corona, vec4 rows, vec4 cols, float radius_um, float theta_deg,
                    bool corona_on) {
  if (!corona_on || !hx_lee_radius_in_range(cols, radius_um)) return vec3(0.0);
  return hx_lee_lookup(corona, rows, hx_lee_column(cols, radius_um), theta_deg);
}

// ---- Non-spherical drops (hydrolux export --shape; docs/sky.md, "Drop shapes") ----------------
// Flattened drops' bow changes along its arc: rainbow_shaped.f32 holds it at 19 position
// angles 0, 10, ..., 180 degrees, as a 3-D float texture of columns x rows x positions
// texels (RGBA32F with A = 1, or RGB32F): texel (c, r, k) holds T_rgb in sr^-1 (the primary and the
// secondary added) of radius radius_um[c], scattering angle angle_deg[r] and position_deg[k], for
// the one sun elevation of its JSON (sun_elevation_deg). Its rows and cols vec4 are built from
// rainbow_shaped.json as a 2-D table's; the positions are the texture's depth, spread evenly over
// [0, 180] degrees. Read with texelFetch and interpolated here: linear in row and ln(radius) as
// the 2-D tables, and linear in the position angle between the two nearest layers.
// Sampler parameters carry highp: GLSL ES 3.00 has no default precision for sampler3D.

// The position angle of the view ray v (degrees, [0, 180]) around the antisolar point a = -s, from
// the zenith side (0, the bow's top) over its sides (90) to the nadir side (180, its bottom), the
// same on the left and the right:
//   u0 = normalize(up - dot(up, a) a),  u90 = normalize(cross(a, u0)),  psi = atan(|v.u90|, v.u0)
// 0 at the antisolar point itself and for a sun at the zenith (where it is undefined).
float hx_position_angle_deg(vec3 v, vec3 sun_dir) {
  vec3 a = -sun_dir;
  vec3 u = vec3(0.0, 1.0, 0.0) - a.y * a;
  float l = length(u);
  if (l < 1e-6) return 0.0;
  vec3 u0 = u / l;
  vec3 u90 = normalize(cross(a, u0));
  float y = abs(dot(v, u90)), x = dot(v, u0);
  if (y == 0.0 && x == 0.0) return 0.0;  // atan(0, 0) is undefined in GLSL
  return atan(y, x) * HX_DEG;
}

// Bilinear interpolation between texel centres at a fractional (column, row) of layer k.
vec3 hx_lee_fetch_layer(highp sampler3D table, float column, float row, int layer) {
  ivec3 size = textureSize(table, 0);
  int c0 = int(floor(column)), r0 = int(floor(row));
  int c1 = min(c0 + 1, size.x - 1), r1 = min(r0 + 1, size.y - 1);
  float fc = column - float(c0), fr = row - float(r0);
  vec3 t00 = texelFetch(table, ivec3(c0, r0, layer), 0).rgb;
  vec3 t10 = texelFetch(table, ivec3(c1, r0, layer), 0).rgb;
  vec3 t01 = texelFetch(table, ivec3(c0, r1, layer), 0).rgb;
  vec3 t11 = texelFetch(table, ivec3(c1, r1, layer), 0).rgb;
  return mix(mix(t00, t10, fc), mix(t01, t11, fc), fr);
}

// T_rgb (sr^-1) of the 3-D table at a scattering angle, a fractional column and a position angle
// (degrees); 0 outside its rows.
vec3 hx_shaped_lookup(highp sampler3D table, vec4 rows, float column, float theta_deg,
                      float position_deg) {
  float row = hx_lee_row(rows, theta_deg);
  if (row < 0.0) return vec3(0.0);
  int n = textureSize(table, 0).z;
  if (n < 2) return hx_lee_fetch_layer(table, column, row, 0);
  float p = clamp(position_deg * float(n - 1) / 180.0, 0.0, float(n - 1));
  int k = min(int(p), n - 2);
  float f = p - float(k);
  vec3 a = hx_lee_fetch_layer(table, column, row, k);
  vec3 b = hx_lee_fetch_layer(table, column, row, k + 1);
  return a + f * (b - a);
}

// The non-spherical drops' rainbow part: T_rgb(theta, psi) w(theta) for theta in its rows (90-180),
// else 0; psi = hx_position_angle_deg(v, sun_dir).
vec3 hx_shaped_rainbow_term(highp sampler3D table, vec4 rows, float column, float theta_deg,
                            float position_deg, bool secondary) {
  return hx_shaped_lookup(table, rows, column, theta_deg, position_deg) *
         hx_secondary_weight(theta_deg, secondary);
}
