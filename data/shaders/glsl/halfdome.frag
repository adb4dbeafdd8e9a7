// hydrolux shaders: halfdome.frag, the half dome's 1D table slice at the radius (see halfdome.vert).
// Writes T_rgb(theta) w(theta) of the rainbow table; example.frag (u_bow_source = 2) reads it per
// pixel and adds the corona. Needs hydrolux_common.glsl and hydrolux_rainbow.glsl. Non-spherical
// drops (u_shaped = 1): theta from the dome, the position angle from the interpolated direction
// (the view ray) and u_sun_dir, looked up in the 3-D table. A polariser (example.frag's
// u_polarizer) needs the Stokes Q too: draw the dome again into a second float target
// (u_bow_screen_q), cleared to 0, with the Q tables bound in place of the intensity's (u_rainbow <-
// rainbow_q.f32, u_rainbow_shaped <- rainbow_shaped_q.f32); Q is signed.

uniform sampler2D u_rainbow;
uniform vec4 u_rainbow_rows;
uniform vec4 u_rainbow_cols;
uniform int u_shaped;
uniform highp sampler3D u_rainbow_shaped;
uniform vec4 u_rainbow_shaped_rows;
uniform vec4 u_rainbow_shaped_cols;
uniform vec3 u_sun_dir;
uniform float u_radius_um;
uniform int u_secondary;
in float v_theta;
in vec3 v_direction;

layout(location = 0) out vec4 hx_frag_color;

void main() {
  vec3 T;
  if (u_shaped != 0) {
    float column = hx_lee_column(u_rainbow_shaped_cols, u_radius_um);
    float psi = hx_position_angle_deg(normalize(v_direction), u_sun_dir);
    T = hx_shaped_rainbow_term(u_rainbow_shaped, u_rainbow_shaped_rows, column, v_theta, psi,
                               u_secondary != 0);
  } else {
    float column = hx_lee_column(u_rainbow_cols, u_radius_um);
    T = hx_rainbow_term(u_rainbow, u_rainbow_rows, column, v_theta, u_secondary != 0);
  }
  hx_frag_color = vec4(T, 1.0);
}
