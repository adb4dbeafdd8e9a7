// hydrolux shaders: halfdome.vert, the half-dome optimisation (docs/sky.md, "Seed 002's
// optimisations"): a hemisphere of directions around the antisolar point -s, tessellated into
// rings x segments quads. Vertex (i, j), i = 0..rings, j = 0..segments: theta_i = 180 - 90 i / rings
// (i = 0 the antisolar point, i = rings the great circle 90 degrees from the sun), phi_j = 360 j /
// segments around the axis, direction cos(a) (-s) + sin(a) (cos(phi) e1 + sin(phi) e2), a = 180 -
// theta_i, e1 and e2 unit vectors normal to s and to each other. Draw it centred on the camera with
// no depth test into a screen-sized float target cleared to 0; the GPU interpolates theta across
// each flat triangle (perspective-correct), halfdome.frag looks up the table.
//   hx_direction  the vertex's unit direction (world)
//   hx_theta      its scattering angle theta_i (degrees)
//   u_view_proj   projection x view rotation (the camera at the origin: no translation)
// v_direction carries the direction across the triangle: at a fragment it points along the view ray
// (the triangle is drawn around the camera), whose position angle non-spherical drops need.

uniform mat4 u_view_proj;
in vec3 hx_direction;
in float hx_theta;
out float v_theta;
out vec3 v_direction;

void main() {
  v_theta = hx_theta;
  v_direction = hx_direction;
  gl_Position = u_view_proj * vec4(hx_direction, 1.0);
}
