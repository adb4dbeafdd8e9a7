// hydrolux shaders: example.frag, a complete full-screen fragment shader (docs/sky.md): the sky,
// the sun and the ground (or your scene), the rain curtain with the rainbow and the corona from the
// Lee tables, the blend and the tone map. Prepend the header and the function files (see
// hydrolux_common.glsl); draw one triangle or quad covering a width x height viewport (u_resolution).
// The web demo runs exactly this file.
//
// Uniforms (units; how to fill them: README.md next to this folder):
//   u_resolution        vec2(width, height) of the viewport in pixels
//   u_cam_f, u_cam_r, u_cam_u   the camera's forward, right, up (world, unit): f = hx_dir(view_az,
//                       view_el), r = normalize(cross(vec3(0, 1, 0), f)), u = cross(f, r)
//   u_tan_half_fov      tan(horizontal field of view / 2)
//   u_cam_height        the camera's height above the ground (1.7 m)
//   u_sky               HxSky (hydrolux_sky.glsl) from sky.json at the sun's elevation
//   u_l_ref             sky.json's l_ref at the sun's elevation (cd/m^2): the tone map's white
//   u_light_color       RGB multiplier of the sunlight that makes the bow (1, 1, 1)
//   u_rainbow, u_rainbow_rows, u_rainbow_cols   the rainbow table (rainbow.f32 + rainbow.json)
//   u_corona, u_corona_rows, u_corona_cols      the corona table (corona.f32 + corona.json)
//   u_shaped            0: spherical drops (u_rainbow); 1: non-spherical drops, the rainbow from
//                       u_rainbow_shaped by each pixel's position angle around the antisolar point
//   u_rainbow_shaped, u_rainbow_shaped_rows, u_rainbow_shaped_cols   the 3-D table
//                       (rainbow_shaped.f32 + .json, hydrolux export --shape); unused with u_shaped 0
//   u_radius_um         the drops' radius (um)
//   u_secondary         1: keep the secondary bow; 0: remove it (w(theta))
//   u_corona_on         1: add the corona (for radii within its table)
//   u_blend             0: physical, 1: whitepaper
//   u_beta_geo          the rain's projected-area coefficient pi M2 (m^-1; hydrolux_composite.glsl)
//   u_curtain           vec2(d0, d1): the rain fills d0..d1 metres from the camera
//   u_moisture          global moisture multiplier in [0, 1]
//   u_moisture_noise    0: uniform moisture; up to 1: modulated by a procedural noise of direction
//   u_bow_source        where T_rgb w comes from: 0 per pixel (the reference); 1 the cube map
//                       u_bow_cube (looked up with the view direction, corona included); 2 the
//                       screen-sized texture u_bow_screen (the half dome's pass) plus the corona
//                       per pixel
//   u_has_scene         1: u_scene holds your opaque objects: rgb = radiance (cd/m^2), a = the
//                       distance (m) from the camera, 0 where there is none (sky/ground shows)
//   u_output            0: tone-mapped sRGB display values; 1: linear radiance (cd/m^2) for your
//                       own HDR pipeline (then blend and tone-map yourself)
//   u_polarizer         vec2(on, A): on = 1 puts a linear polariser in front of the camera, its
//                       transmission axis A radians from the image's horizontal towards its up
//                       (0 passes the top of the bow, pi/2 its sides); 0: none (the frame as without)
//   u_sky_max_dolp      P90, the sky's degree of polarisation 90 degrees from the sun (sky.json's
//                       polarization.sky_max_dolp, 0.8)
//   u_rainbow_q, u_corona_q, u_rainbow_shaped_q   the Stokes Q tables (rainbow_q.f32,
//                       corona_q.f32, rainbow_shaped_q.f32) laid out as u_rainbow, u_corona,
//                       u_rainbow_shaped (the same rows and cols vec4); read with the polariser only
//   u_bow_cube_q, u_bow_screen_q   the cube map and the half dome's texture baked again with the Q
//                       tables bound in place of the intensity's (u_bow_source 1, 2 with the polariser)

uniform vec2 u_resolution;
uniform vec3 u_cam_f;
uniform vec3 u_cam_r;
uniform vec3 u_cam_u;
uniform float u_tan_half_fov;
uniform float u_cam_height;
uniform HxSky u_sky;
uniform float u_l_ref;
uniform vec3 u_light_color;
uniform sampler2D u_rainbow;
uniform vec4 u_rainbow_rows;
uniform vec4 u_rainbow_cols;
uniform sampler2D u_corona;
uniform vec4 u_corona_rows;
uniform vec4 u_corona_cols;
uniform int u_shaped;
uniform highp sampler3D u_rainbow_shaped;
uniform vec4 u_rainbow_shaped_rows;
uniform vec4 u_rainbow_shaped_cols;
uniform float u_radius_um;
uniform int u_secondary;
uniform int u_corona_on;
uniform int u_blend;
uniform float u_beta_geo;
uniform vec2 u_curtain;
uniform float u_moisture;
uniform float u_moisture_noise;
uniform int u_bow_source;
uniform samplerCube u_bow_cube;
uniform sampler2D u_bow_screen;
uniform int u_has_scene;
uniform sampler2D u_scene;
uniform int u_output;
uniform vec2 u_polarizer;
uniform float u_sky_max_dolp;
uniform sampler2D u_rainbow_q;
uniform sampler2D u_corona_q;
uniform highp sampler3D u_rainbow_shaped_q;
uniform samplerCube u_bow_cube_q;
uniform sampler2D u_bow_screen_q;

layout(location = 0) out vec4 hx_frag_color;

// Value noise of a 3D point (hash of the lattice corners, smooth interpolation), in [0, 1].
float hx_hash3(vec3 p) {
  return fract(sin(dot(p, vec3(127.1, 311.7, 74.7))) * 43758.5453);
}
float hx_value_noise(vec3 p) {
  vec3 i = floor(p), f = fract(p);
  f = f * f * (3.0 - 2.0 * f);
  float n000 = hx_hash3(i), n100 = hx_hash3(i + vec3(1, 0, 0));
  float n010 = hx_hash3(i + vec3(0, 1, 0)), n110 = hx_hash3(i + vec3(1, 1, 0));
  float n001 = hx_hash3(i + vec3(0, 0, 1)), n101 = hx_hash3(i + vec3(1, 0, 1));
  float n011 = hx_hash3(i + vec3(0, 1, 1)), n111 = hx_hash3(i + vec3(1, 1, 1));
  return mix(mix(mix(n000, n100, f.x), mix(n010, n110, f.x), f.y),
             mix(mix(n001, n101, f.x), mix(n011, n111, f.x), f.y), f.z);
}
// Sheets of rain: noise stretched along the vertical, in [0, 1].
float hx_moisture_pattern(vec3 v) {
  vec3 p = vec3(v.x * 7.0, v.y * 1.5, v.z * 7.0);
  float n = 0.6 * hx_value_noise(p) + 0.4 * hx_value_noise(p * 2.7 + 3.1);
  return smoothstep(0.3, 0.7, n);
}

// T_rgb w (sr^-1) along v at theta from the given tables (the intensity's, or the same lookups in the
// Stokes Q tables), from where u_bow_source says.
vec3 hx_example_bow(sampler2D rainbow, sampler2D corona_table, highp sampler3D shaped, samplerCube cube,
                    sampler2D screen, vec3 v, float theta) {
  bool secondary = u_secondary != 0;
  vec3 corona = hx_corona_term(corona_table, u_corona_rows, u_corona_cols, u_radius_um, theta,
                               u_corona_on != 0);
  if (u_bow_source == 1) return texture(cube, v).rgb;
  if (u_bow_source == 2) return texelFetch(screen, ivec2(gl_FragCoord.xy), 0).rgb + corona;
  if (u_shaped != 0) {
    float column = hx_lee_column(u_rainbow_shaped_cols, u_radius_um);
    float psi = hx_position_angle_deg(v, u_sky.sun_dir);
    return hx_shaped_rainbow_term(shaped, u_rainbow_shaped_rows, column, theta, psi, secondary) +
           corona;
  }
  float column = hx_lee_column(u_rainbow_cols, u_radius_um);
  return hx_rainbow_term(rainbow, u_rainbow_rows, column, theta, secondary) + corona;
}

void main() {
  vec2 pixel = vec2(gl_FragCoord.x, u_resolution.y - gl_FragCoord.y);  // from the top row
  vec3 v = hx_camera_ray(pixel, u_resolution, u_cam_f, u_cam_r, u_cam_u, u_tan_half_fov);
  float theta = hx_angle_deg(v, u_sky.sun_dir);

  vec3 bg;
  float d_hit = 1e30;
  vec4 scene = u_has_scene != 0 ? texelFetch(u_scene, ivec2(gl_FragCoord.xy), 0) : vec4(0.0);
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

  vec3 T = hx_example_bow(u_rainbow, u_corona, u_rainbow_shaped, u_bow_cube, u_bow_screen, v, theta);
  if (polarizer) {
    vec3 TQ = hx_example_bow(u_rainbow_q, u_corona_q, u_rainbow_shaped_q, u_bow_cube_q,
                             u_bow_screen_q, v, theta);
    T = hx_polarize(T, TQ, c2);
  }

  float moisture = u_moisture;
  if (u_moisture_noise > 0.0) moisture *= mix(1.0, hx_moisture_pattern(v), u_moisture_noise);
  float tau = hx_tau_geo(u_beta_geo, hx_rain_path(v, u_cam_height, u_curtain, d_hit), moisture);
  vec3 bow = hx_bow_radiance(u_sky.sun_rgb * u_light_color, T, tau);
  vec3 L = u_blend == 1 ? hx_blend_whitepaper(bg, bow, u_l_ref) : hx_blend_physical(bg, tau, bow);

  // With a polariser the exposure opens up one stop (l_ref / 2), as hydrolux sky's PNG.
  hx_frag_color = vec4(u_output == 1 ? L : hx_tonemap(L, polarizer ? 0.5 * u_l_ref : u_l_ref), 1.0);
}
