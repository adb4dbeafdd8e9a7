// hydrolux shaders: common definitions (docs/sky.md). Valid GLSL ES 3.00 and GLSL 4.50: no
// #version line; prepend "#version 300 es" (or "#version 450") and default precisions, e.g.
//   precision highp float; precision highp int; precision highp sampler2D;
//   precision highp samplerCube;
// then hydrolux_common.glsl, hydrolux_sky.glsl, hydrolux_rainbow.glsl, hydrolux_composite.glsl
// and a main (example.frag).
//
// Frame: world +y up, +z north, +x east. Directions are unit vectors in that frame. Angles the
// functions take or return are in degrees unless a name says _rad. Radiance is linear Rec.709 RGB
// in cd/m^2 (the luminance 0.2126 R + 0.7152 G + 0.0722 B in candela per square metre).

const float HX_PI = 3.14159265358979;
const float HX_DEG = 57.2957795130823;      // degrees per radian
const float HX_SUN_RADIUS_DEG = 0.265;       // the sun's angular radius
const float HX_Q_EXT = 2.0;                  // extinction efficiency of drops >> wavelength

// dir(az, el) = (sin az cos el, sin el, cos az cos el): az from north towards east, el above the
// horizon, in degrees.
vec3 hx_dir(float az_deg, float el_deg) {
  float az = az_deg / HX_DEG, el = el_deg / HX_DEG;
  return vec3(sin(az) * cos(el), sin(el), cos(az) * cos(el));
}

// The angle between two unit vectors in degrees, accurate near 0 and 180 (where acos(dot) is not).
float hx_angle_deg(vec3 a, vec3 b) {
  return atan(length(cross(a, b)), dot(a, b)) * HX_DEG;
}

// The view ray of the pinhole camera of docs/sky.md through the pixel centre `pixel` (x = i + 0.5
// from the left, y = j + 0.5 from the TOP row) of a width x height image: f forward, r = normalize(up
// x f) right, u = f x r up, tan_half_fov = tan(horizontal fov / 2).
vec3 hx_camera_ray(vec2 pixel, vec2 size, vec3 f, vec3 r, vec3 u, float tan_half_fov) {
  float px = (2.0 * pixel.x / size.x - 1.0) * tan_half_fov;
  float py = (1.0 - 2.0 * pixel.y / size.y) * tan_half_fov * size.y / size.x;
  return normalize(f + px * r + py * u);
}

// Luminance of linear Rec.709 RGB.
float hx_luminance(vec3 rgb) {
  return dot(rgb, vec3(0.2126, 0.7152, 0.0722));
}
