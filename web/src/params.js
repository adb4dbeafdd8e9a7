// Every setting of the demo, readable from and writable to URL query parameters, so that a test
// (or a shared link) reproduces a frame exactly. Names follow `hydrolux sky`'s flags.

export const MODES = ['per-pixel', 'cube-map', 'half-dome'];
export const BLENDS = ['physical', 'whitepaper'];

export const DEFAULTS = {
  sun_az: 180, // sun azimuth (deg from north towards east)
  sun_el: 25, // sun elevation (deg), 0..90
  view_az: 0, // camera azimuth (deg)
  view_el: 10, // camera elevation (deg)
  fov: 90, // horizontal field of view (deg)
  radius: 500, // drop radius (um), 5..800
  rain: 5, // rain rate (mm/h)
  curtain: [1000, 3000], // the rain fills d0..d1 metres from the camera
  moisture: 1, // global moisture multiplier, 0..1
  noise: 0, // moisture noise amount, 0..1
  secondary: true,
  corona: false,
  objects: true, // houses and trees that hide the rain behind them
  // drop shape, as `hydrolux sky --shape`: 'sphere', or the shape of the assets' non-spherical
  // drops' table (rainbow_shaped.json, `hydrolux export --shape beard-chuang`): the "real drops" toggle
  shape: 'sphere',
  mode: 'per-pixel',
  blend: 'physical',
  light: [1, 1, 1], // light colour multiplier of the bow
  // a linear polariser in front of the camera, as `hydrolux sky --polarizer-deg`: null (none) or its
  // axis in degrees from the image's horizontal towards its up (the dial: -90..90; 0 passes the top
  // of the bow, 90 its sides); needs the assets' Stokes Q tables (hydrolux export writes them)
  polarizer: null,
  // P90, the sky's degree of polarisation 90 degrees from the sun (`hydrolux sky --sky-max-dolp`);
  // null: sky.json's polarization.sky_max_dolp (0.8)
  sky_max_dolp: null,
  cube: 512, // cube-map face size (texels), as `hydrolux sky --cube-face-size`
  rings: 90, // half-dome rings (90 degrees), as `hydrolux sky --dome-rings`
  segments: 180, // half-dome segments (360 degrees), as `hydrolux sky --dome-segments`
  size: null, // [W, H]: a canvas of exactly W x H pixels (pixel ratio 1); null: the window
  test: false, // test mode: no animation loop; window.__hydroluxReady after the first frame
  ui: true, // show the control panel
  assets: 'assets/', // where rainbow.f32/.json, corona.f32/.json, sky.json and glsl/ are
};

const num = (s, lo = -Infinity, hi = Infinity) => {
  const v = Number(s);
  if (!Number.isFinite(v)) throw new Error(`not a number: ${s}`);
  return Math.min(hi, Math.max(lo, v));
};
const bool = (s) => !(s === '0' || s === 'false' || s === 'off' || s === 'no');
const list = (s, n) => {
  const parts = s.split(/[,:x]/).map((p) => num(p));
  if (parts.length !== n) throw new Error(`expected ${n} numbers: ${s}`);
  return parts;
};

const PARSERS = {
  sun_az: (s) => num(s),
  sun_el: (s) => num(s, 0, 90),
  view_az: (s) => num(s),
  view_el: (s) => num(s, -89, 89),
  fov: (s) => num(s, 1, 170),
  radius: (s) => num(s, 1, 1000),
  rain: (s) => num(s, 0.01, 1000),
  curtain: (s) => list(s, 2),
  moisture: (s) => num(s, 0, 1),
  noise: (s) => num(s, 0, 1),
  secondary: bool,
  corona: bool,
  objects: bool,
  shape: (s) => {
    if (!/^(sphere|beard-chuang|spheroid:[0-9.]+)$/.test(s))
      throw new Error(`shape: sphere, beard-chuang or spheroid:Q (the assets' table of non-spherical drops)`);
    return s;
  },
  mode: (s) => {
    if (!MODES.includes(s)) throw new Error(`mode: one of ${MODES.join(', ')}`);
    return s;
  },
  blend: (s) => {
    if (!BLENDS.includes(s)) throw new Error(`blend: one of ${BLENDS.join(', ')}`);
    return s;
  },
  light: (s) => list(s, 3),
  polarizer: (s) => (s === 'off' || s === 'none' || s === '' ? null : num(s, -180, 180)),
  sky_max_dolp: (s) => num(s, 0, 1),
  cube: (s) => Math.round(num(s, 4, 2048)),
  rings: (s) => Math.round(num(s, 1, 1024)),
  segments: (s) => Math.round(num(s, 3, 4096)),
  size: (s) => list(s, 2).map((v) => Math.round(v)),
  test: bool,
  ui: bool,
  assets: (s) => (s.endsWith('/') ? s : s + '/'),
};

export function readParams(search) {
  const p = structuredClone(DEFAULTS);
  const q = new URLSearchParams(search);
  for (const [key, value] of q) {
    if (!(key in PARSERS)) throw new Error(`unknown URL parameter "${key}"`);
    p[key] = PARSERS[key](value);
  }
  if (p.test && q.get('ui') === null) p.ui = false;
  return p;
}

// The query string of the settings that differ from the defaults.
export function writeParams(p) {
  const q = new URLSearchParams();
  for (const key of Object.keys(DEFAULTS)) {
    const v = p[key], d = DEFAULTS[key];
    if (JSON.stringify(v) === JSON.stringify(d)) continue;
    if (v === null) q.set(key, 'off');
    else if (Array.isArray(v)) q.set(key, v.join(key === 'curtain' ? ':' : key === 'size' ? 'x' : ','));
    else if (typeof v === 'boolean') q.set(key, v ? '1' : '0');
    else q.set(key, String(v));
  }
  const s = q.toString();
  return s ? '?' + s : '';
}
