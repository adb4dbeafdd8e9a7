// hydrolux shaders: halfdome.frag, the half dome's 1D table slice at the radius (see halfdome.vert).
// Writes T_rgb(theta) w(theta) of the rainbow table; example.frag (u_bow_source = 2) reads it per
// pixel and adds the corona. Needs hydrolux_common.glsl and hydrolux_rainbow.glsl.

uniform sampler2D u_rainbow;
uniform vec4 u_rainbow_rows;
uniform vec4 u_rainbow_cols;
uniform float u_radius_um;
uniform int u_secondary;
in float v_theta;

layout(location = 0) out vec4 hx_frag_color;

void main() {
  float column = hx_lee_column(u_rainbow_cols, u_radius_um);
  hx_frag_color = vec4(hx_rainbow_term(u_rainbow, u_rainbow_rows, column, v_theta, u_secondary != 0),
                       1.0);
}
