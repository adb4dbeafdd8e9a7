// hydrolux shaders: cubemap_bake.frag, the cube-map optimisation's bake (docs/sky.md, "Seed 002's
// optimisations"): draw a full-screen pass into each face (u_face 0..5 = +X, -X, +Y, -Y, +Z, -Z) of
// an N x N RGBA16F/32F cube map (u_face_size = N) with linear filtering; every texel gets the bow
// colour T_rgb(theta) w(theta) of its direction for the current sun and radius (the corona
// included when on; for non-spherical drops, u_shaped = 1, each texel's rainbow from the 3-D table at
// its own position angle). Rebake when the sun, the radius or a toggle changes; look it up with the view
// direction (example.frag, u_bow_source = 1). Needs hydrolux_common.glsl and hydrolux_rainbow.glsl.
// The cube's directions are the world frame's (+y up, +z north, +x east), texel row 0 at
// gl_FragCoord.y = 0.5 (the GL and D3D cube-face conventions agree in these terms).
// A polariser (example.frag's u_polarizer) needs the bow's Stokes Q baked too: run this same pass
// into a second cube map (u_bow_cube_q) with the Q tables bound in place of the intensity's
// (u_rainbow <- rainbow_q.f32, u_corona <- corona_q.f32, u_rainbow_shaped <- rainbow_shaped_q.f32;
// the same rows and cols vec4). Q is signed: a float format (RGBA16F/32F), never a unorm one.

uniform int u_face;
uniform float u_face_size;
uniform vec3 u_sun_dir;
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

layout(location = 0) out vec4 hx_frag_color;

// The direction through face coordinates (sc, tc) in [-1, 1] (texel centres: (2 (i + 0.5) / N - 1)).
vec3 hx_cube_face_dir(int face, vec2 st) {
  float sc = st.x, tc = st.y;
  if (face == 0) return vec3(1.0, -tc, -sc);
  if (face == 1) return vec3(-1.0, -tc, sc);
  if (face == 2) return vec3(sc, 1.0, tc);
  if (face == 3) return vec3(sc, -1.0, -tc);
  if (face == 4) return vec3(sc, -tc, 1.0);
  return vec3(-sc, -tc, -1.0);
}

void main() {
  vec2 st = gl_FragCoord.xy / u_face_size * 2.0 - 1.0;
  vec3 d = normalize(hx_cube_face_dir(u_face, st));
  float theta = hx_angle_deg(d, u_sun_dir);
  vec3 T = hx_corona_term(u_corona, u_corona_rows, u_corona_cols, u_radius_um, theta,
                          u_corona_on != 0);
  if (u_shaped != 0) {
    float column = hx_lee_column(u_rainbow_shaped_cols, u_radius_um);
    T += hx_shaped_rainbow_term(u_rainbow_shaped, u_rainbow_shaped_rows, column, theta,
                                hx_position_angle_deg(d, u_sun_dir), u_secondary != 0);
  } else {
    float column = hx_lee_column(u_rainbow_cols, u_radius_um);
    T += hx_rainbow_term(u_rainbow, u_rainbow_rows, column, theta, u_secondary != 0);
  }
  hx_frag_color = vec4(T, 1.0);
}
