// Loads what `hydrolux export --dir DIR` writes, at run time: the Lee tables (.f32 + .json), the
// non-spherical drops' 3-D table when the export made one (--shape), the tables' Stokes Q (*_q.f32,
// for the polariser) where the manifest lists them, sky.json and the GLSL files, so the page runs
// the very shaders the export ships.
import * as THREE from 'three';
import { checkSky } from './sky.js';

// The GLSL function files in the order they are concatenated (each needs the ones before it).
export const GLSL_FUNCTIONS = [
  'hydrolux_common.glsl',
  'hydrolux_sky.glsl',
  'hydrolux_rainbow.glsl',
  'hydrolux_composite.glsl',
];
export const GLSL_MAINS = ['example.frag', 'cubemap_bake.frag', 'halfdome.vert', 'halfdome.frag'];

async function fetchOk(url) {
  const r = await fetch(url);
  if (!r.ok) throw new Error(`could not load ${url}: HTTP ${r.status}`);
  return r;
}

// A Lee table as an RGBA32F texture read with texelFetch (no filtering needed), and the two vec4
// that describe its axes to the shaders (hydrolux_rainbow.glsl).
function makeTable(json, buffer, name) {
  const cols = json.width ?? json.radius_um.length;
  const rows = json.height ?? (json.angle_deg ?? json.cos_angle).length;
  const rgb = new Float32Array(buffer);
  if (rgb.length !== rows * cols * 3)
    throw new Error(`${name}.f32 holds ${rgb.length} floats, expected ${rows} x ${cols} x 3`);
  if (json.radius_scale && json.radius_scale !== 'log')
    throw new Error(`${name}: radius_scale "${json.radius_scale}" (the shaders expect "log")`);
  const rgba = new Float32Array(rows * cols * 4);
  for (let i = 0; i < rows * cols; i++) {
    rgba[4 * i] = rgb[3 * i];
    rgba[4 * i + 1] = rgb[3 * i + 1];
    rgba[4 * i + 2] = rgb[3 * i + 2];
    rgba[4 * i + 3] = 1;
  }
  const tex = new THREE.DataTexture(rgba, cols, rows, THREE.RGBAFormat, THREE.FloatType);
  tex.minFilter = THREE.NearestFilter;
  tex.magFilter = THREE.NearestFilter;
  tex.generateMipmaps = false;
  tex.flipY = false;
  tex.needsUpdate = true;
  const isCos = json.axis === 'cos';
  const axis = isCos ? json.cos_angle : json.angle_deg;
  const r = json.radius_um;
  return {
    json,
    texture: tex,
    rows: new THREE.Vector4(axis[0], axis[axis.length - 1], rows, isCos ? 1 : 0),
    cols: new THREE.Vector4(r[0], r[r.length - 1], cols, 0),
  };
}

// The non-spherical drops' 3-D table (rainbow_shaped.f32 + .json, `hydrolux export --shape`): a
// columns x rows x positions RGBA32F Data3DTexture read with texelFetch, the rows and cols vec4 as a
// 2-D table's, the positions spread evenly over 0-180 degrees (the shaders assume it), and the shape
// and the sun elevation it was computed for.
function makeTable3D(json, buffer, name) {
  const cols = json.width, rows = json.height, depth = json.depth;
  const rgb = new Float32Array(buffer);
  if (!(cols > 0 && rows > 0 && depth >= 2) || rgb.length !== depth * rows * cols * 3)
    throw new Error(`${name}.f32 holds ${rgb.length} floats, expected ${depth} x ${rows} x ${cols} x 3`);
  if (json.radius_scale !== 'log')
    throw new Error(`${name}: radius_scale "${json.radius_scale}" (the shaders expect "log")`);
  const pos = json.position_deg;
  if (!Array.isArray(pos) || pos.length !== depth || pos.some((v, k) => Math.abs(v - (180 * k) / (depth - 1)) > 1e-6))
    throw new Error(`${name}: position_deg must hold ${depth} angles spread evenly over 0-180 degrees`);
  const rgba = new Float32Array(depth * rows * cols * 4);
  for (let i = 0; i < depth * rows * cols; i++) {
    rgba[4 * i] = rgb[3 * i];
    rgba[4 * i + 1] = rgb[3 * i + 1];
    rgba[4 * i + 2] = rgb[3 * i + 2];
    rgba[4 * i + 3] = 1;
  }
  const tex = new THREE.Data3DTexture(rgba, cols, rows, depth);
  tex.format = THREE.RGBAFormat;
  tex.type = THREE.FloatType;
  tex.minFilter = THREE.NearestFilter;
  tex.magFilter = THREE.NearestFilter;
  tex.generateMipmaps = false;
  tex.flipY = false;
  tex.unpackAlignment = 1;
  tex.needsUpdate = true;
  const isCos = json.axis === 'cos';
  const axis = isCos ? json.cos_angle : json.angle_deg;
  const r = json.radius_um;
  return {
    json,
    texture: tex,
    shape: json.drop_shape?.name,
    sunElevationDeg: json.sun_elevation_deg,
    rows: new THREE.Vector4(axis[0], axis[axis.length - 1], rows, isCos ? 1 : 0),
    cols: new THREE.Vector4(r[0], r[r.length - 1], cols, 0),
  };
}

// A stand-in for a table the export did not write (the corona of large drops): one zero texel and
// a radius range no drop is in, so that hx_corona_term returns 0.
function noTable() {
  const tex = new THREE.DataTexture(new Float32Array(4), 1, 1, THREE.RGBAFormat, THREE.FloatType);
  tex.needsUpdate = true;
  return { json: null, texture: tex, rows: new THREE.Vector4(0, 90, 1, 0), cols: new THREE.Vector4(0, 0, 1, 0) };
}

export async function loadAssets(base) {
  const json = (f) => fetchOk(base + f).then((r) => r.json());
  const bin = (f) => fetchOk(base + f).then((r) => r.arrayBuffer());
  const text = (f) => fetchOk(base + 'glsl/' + f).then((r) => r.text());
  const manifest = await json('manifest.json');
  // An export of one large radius (--radius-um above 50 um) has no corona table: the manifest says so.
  const hasCorona = Boolean(manifest?.tables?.corona);
  // The Stokes Q of a table (<name>_q.f32, in its .f32's layout) where the manifest lists one.
  const qFile = (name) => manifest?.tables?.[name]?.stokes_q ?? null;
  const hasQ = Boolean(qFile('rainbow')) && (!hasCorona || Boolean(qFile('corona')));
  const [rainbowJson, coronaJson, sky, rainbowF32, coronaF32, rainbowQ, coronaQ] = await Promise.all([
    json('rainbow.json'),
    hasCorona ? json('corona.json') : null,
    json('sky.json'),
    bin('rainbow.f32'),
    hasCorona ? bin('corona.f32') : null,
    hasQ ? bin(qFile('rainbow')) : null,
    hasQ && hasCorona ? bin(qFile('corona')) : null,
  ]);
  checkSky(sky); // every sky and rain constant comes from sky.json: a missing key stops the page here
  // The non-spherical drops' table only where the export wrote one (the manifest lists it).
  let shaped = null, shapedQ = null;
  if (manifest?.tables?.rainbow_shaped) {
    const shapedQFile = qFile('rainbow_shaped');
    const [shapedJson, shapedF32, shapedQF32] = await Promise.all([json('rainbow_shaped.json'),
      bin('rainbow_shaped.f32'), shapedQFile ? bin(shapedQFile) : null]);
    shaped = makeTable3D(shapedJson, shapedF32, 'rainbow_shaped');
    if (shapedQF32) shapedQ = makeTable3D(shapedJson, shapedQF32, 'rainbow_shaped_q');
  }
  const names = [...GLSL_FUNCTIONS, ...GLSL_MAINS];
  const sources = await Promise.all(names.map(text));
  const glsl = Object.fromEntries(names.map((n, i) => [n, sources[i]]));
  return {
    rainbow: makeTable(rainbowJson, rainbowF32, 'rainbow'),
    corona: hasCorona ? makeTable(coronaJson, coronaF32, 'corona') : noTable(),
    shaped,
    // The Stokes Q tables (null without: an export from before they were written): the same axes
    // as the intensity's, signed values (the polariser, u_rainbow_q etc.).
    q: hasQ
      ? {
          rainbow: makeTable(rainbowJson, rainbowQ, 'rainbow_q'),
          corona: hasCorona ? makeTable(coronaJson, coronaQ, 'corona_q') : noTable(),
          shaped: shapedQ,
        }
      : null,
    sky,
    glsl,
  };
}

// The fragment-shader source of a main file: default precisions, the function files, the main.
// three.js's RawShaderMaterial (glslVersion GLSL3) puts "#version 300 es" in front.
export const PRECISIONS =
  'precision highp float;\nprecision highp int;\nprecision highp sampler2D;\nprecision highp samplerCube;\n';
export function fragmentSource(glsl, main) {
  return PRECISIONS + GLSL_FUNCTIONS.map((f) => glsl[f]).join('\n') + '\n' + glsl[main];
}
