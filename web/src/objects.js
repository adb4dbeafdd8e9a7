// A few simple opaque objects (houses and trees) in front of the rain: they hide the bow behind
// them (the rain's path ends at them, like at the ground: the whitepaper's moisture mask). They are
// rendered into a float target: rgb = radiance (cd/m^2), a = distance from the camera (m).
import * as THREE from 'three';

const vertexShader = /* glsl */ `
uniform mat4 u_world_from_three;
out vec3 v_world;
out vec3 v_normal;
void main() {
  vec4 w = modelMatrix * vec4(position, 1.0);
  v_world = w.xyz;
  v_normal = normalize(mat3(modelMatrix) * normal);
  gl_Position = projectionMatrix * viewMatrix * w;
}`;

// Lambertian: albedo / pi * (sun_rgb max(0, n.s) + E_sky (1 + n.y) / 2), s and n in three.js's
// world (its z is the negated north of docs/sky.md's frame).
const fragmentShader = /* glsl */ `
precision highp float;
uniform vec3 u_albedo;
uniform vec3 u_sun_dir_three;
uniform vec3 u_sun_rgb;
uniform vec3 u_sky_irradiance;
in vec3 v_world;
in vec3 v_normal;
out vec4 hx_out;
void main() {
  vec3 n = normalize(v_normal);
  if (!gl_FrontFacing) n = -n;
  vec3 e = u_sun_rgb * max(dot(n, u_sun_dir_three), 0.0) + u_sky_irradiance * (0.5 + 0.5 * n.y);
  hx_out = vec4(u_albedo / 3.14159265 * e, length(v_world - cameraPosition));
}`;

// Positions in docs/sky.md's frame (x east, z north), metres; the group flips z into three.js's.
const HOUSES = [
  { x: -60, z: 140, w: 12, d: 9, h: 7, roof: 4, color: [0.45, 0.3, 0.22], yaw: 0.3 },
  { x: 35, z: 190, w: 16, d: 10, h: 9, roof: 5, color: [0.5, 0.45, 0.38], yaw: -0.2 },
  { x: 120, z: 240, w: 10, d: 10, h: 6, roof: 3, color: [0.35, 0.32, 0.3], yaw: 0.8 },
];
const TREES = [
  { x: -20, z: 90, h: 14, r: 3.5 },
  { x: -110, z: 160, h: 18, r: 5 },
  { x: 80, z: 120, h: 12, r: 3 },
  { x: 150, z: 160, h: 16, r: 4.5 },
  { x: -170, z: 230, h: 20, r: 6 },
];

export function makeObjects() {
  const group = new THREE.Group();
  group.scale.set(1, 1, -1); // docs/sky.md's north (+z) is three.js's -z
  const materials = [];
  const mat = (rgb) => {
    const m = new THREE.ShaderMaterial({
      glslVersion: THREE.GLSL3,
      vertexShader,
      fragmentShader,
      side: THREE.DoubleSide,
      uniforms: {
        u_albedo: { value: new THREE.Vector3(...rgb) },
        u_sun_dir_three: { value: new THREE.Vector3() },
        u_sun_rgb: { value: new THREE.Vector3() },
        u_sky_irradiance: { value: new THREE.Vector3() },
      },
    });
    materials.push(m);
    return m;
  };
  for (const h of HOUSES) {
    const house = new THREE.Group();
    const body = new THREE.Mesh(new THREE.BoxGeometry(h.w, h.h, h.d), mat(h.color));
    body.position.y = h.h / 2;
    house.add(body);
    const roof = new THREE.Mesh(new THREE.ConeGeometry(Math.hypot(h.w, h.d) / 2, h.roof, 4), mat([0.3, 0.12, 0.1]));
    roof.position.y = h.h + h.roof / 2;
    roof.rotation.y = Math.PI / 4;
    house.add(roof);
    house.position.set(h.x, 0, h.z);
    house.rotation.y = h.yaw;
    group.add(house);
  }
  for (const t of TREES) {
    const trunk = new THREE.Mesh(new THREE.CylinderGeometry(0.4, 0.6, t.h * 0.35, 8), mat([0.25, 0.17, 0.1]));
    trunk.position.set(t.x, (t.h * 0.35) / 2, t.z);
    const crown = new THREE.Mesh(new THREE.ConeGeometry(t.r, t.h * 0.75, 10), mat([0.06, 0.16, 0.05]));
    crown.position.set(t.x, t.h * 0.25 + (t.h * 0.75) / 2, t.z);
    group.add(trunk, crown);
  }
  const scene = new THREE.Scene();
  scene.add(group);
  const update = (sunDir, sunRgb, skyIrradiance) => {
    for (const m of materials) {
      m.uniforms.u_sun_dir_three.value.set(sunDir[0], sunDir[1], -sunDir[2]);
      m.uniforms.u_sun_rgb.value.set(...sunRgb);
      m.uniforms.u_sky_irradiance.value.set(...skyIrradiance);
    }
  };
  return { scene, update };
}
