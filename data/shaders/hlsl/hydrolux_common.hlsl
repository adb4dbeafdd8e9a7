// hydrolux shaders (HLSL, shader model 5): common definitions (docs/sky.md). The same functions as
// ../glsl/hydrolux_common.glsl. Include order: hydrolux_common.hlsl, hydrolux_sky.hlsl,
// hydrolux_rainbow.hlsl, hydrolux_composite.hlsl (each includes what it needs; guarded).
//
// Frame: world +y up, +z north, +x east. Directions are unit vectors in that frame. Angles are in
// degrees unless a name says _rad. Radiance is linear Rec.709 RGB in cd/m^2.
#ifndef HYDROLUX_COMMON_HLSL
#define HYDROLUX_COMMON_HLSL

static const float HX_PI = 3.14159265358979;
static const float HX_DEG = 57.2957795130823;      // degrees per radian
static const float HX_SUN_RADIUS_DEG = 0.265;       // the sun's angular radius
static const float HX_Q_EXT = 2.0;                  // extinction efficiency of drops >> wavelength

// dir(az, el) = (sin az cos el, sin el, cos az cos el): az from north towards east, el above the
// horizon, in degrees.
float3 hx_dir(float az_deg, float el_deg) {
  float az = az_deg / HX_DEG, el = el_deg / HX_DEG;
  return float3(sin(az) * cos(el), sin(el), cos(az) * cos(el));
}

// The angle between two unit vectors in degrees, accurate near 0 and 180 (where acos(dot) is not).
float hx_angle_deg(float3 a, float3 b) {
  return atan2(length(cross(a, b)), dot(a, b)) * HX_DEG;
}

// The view ray of the pinhole camera of docs/sky.md through the pixel centre `pixel` (x = i + 0.5
// from the left, y = j + 0.5 from the TOP row: SV_Position.xy) of a width x height image: f forward,
// r = normalize(cross(up, f)) right, u = cross(f, r) up, tan_half_fov = tan(horizontal fov / 2).
float3 hx_camera_ray(float2 pixel, float2 size, float3 f, float3 r, float3 u, float tan_half_fov) {
  float px = (2.0 * pixel.x / size.x - 1.0) * tan_half_fov;
  float py = (1.0 - 2.0 * pixel.y / size.y) * tan_half_fov * size.y / size.x;
  return normalize(f + px * r + py * u);
}

// Luminance of linear Rec.709 RGB.
float hx_luminance(float3 rgb) {
  return dot(rgb, float3(0.2126, 0.7152, 0.0722));
}

#endif
