// Every setting of the demo, readable from and writable to URL query parameters, so that a test
// (or a shared link) reproduces a frame exactly.
//
// The settings that are `hydrolux sky`'s parameters take their names, valid ranges and defaults from
// the library's declaration: `hydrolux spec --json`, read at build time (vite.config.js: the module
// virtual:hydrolux-spec holds the sky's rows). SPEC_NAMES below is the one table from the demo's
// short URL names to the spec's. A value outside the declared range (a number, a choice's word, the
// parts of the curtain's span or the light's colour) is refused, as the CLI refuses it (ParamError:
// the page shows the parameter, the value and the valid range, and renders nothing), never clamped.
// The others (view_az, moisture, noise, objects, shape, size, test, ui, assets) are the demo's own.
import sky from 'virtual:hydrolux-spec';

// The demo's URL name -> the name of `hydrolux sky`'s declared parameter (hydrolux spec --json).
export const SPEC_NAMES = {
  sun_az: 'sun_azimuth_deg',
  sun_el: 'sun_elevation_deg',
  view_el: 'view_elevation_deg',
  fov: 'fov_deg',
  radius: 'radius_um',
  rain: 'rain_rate_mmh',
  secondary: 'secondary',
  corona: 'corona',
  polarizer: 'polarizer_deg',
  sky_max_dolp: 'sky_max_dolp',
  cube: 'cube_face_size',
  rings: 'dome_rings',
  segments: 'dome_segments',
  mode: 'mode',
  blend: 'blend',
  curtain: 'curtain_distance_m',
  light: 'light_color',
};

// The spec's row of each of those ({name, flag, kind, unit, lo, hi, default}), by the demo's name.
export const SPEC = Object.fromEntries(
  Object.entries(SPEC_NAMES).map(([key, name]) => {
    const row = sky.params.find((r) => r.name === name);
    if (!row) throw new Error(`${sky.command} declares no parameter "${name}" (the demo's "${key}"): hydrolux spec --json`);
    return [key, row];
  }),
);

// A refused value: the page shows its message (the parameter, the value, the valid range) and stops.
export class ParamError extends Error {
  constructor(message) {
    super(message);
    this.name = 'ParamError';
  }
}

// The words of the declared choices (hydrolux sky --mode, --blend).
export const MODES = SPEC.mode.words;
export const BLENDS = SPEC.blend.words;

// "[0.1, 5000] um", as the CLI writes a range.
export const rangeText = (row) => `[${row.lo}, ${row.hi}]${row.unit ? ' ' + row.unit : ''}`;

// A declared number, word or list of parts (the curtain's NEAR, FAR; the light's R, G, B) if it is what
// the spec's row of `key` allows (in its range; a whole number for an integer; a span's parts in order),
// else a ParamError worded as the CLI's; `text` is the value as the user wrote it.
export function checkSpec(key, value, text = String(value)) {
  const row = SPEC[key];
  const refuse = (what) => new ParamError(`${key}: ${text} ${what} (hydrolux sky ${row.flag})`);
  if (row.kind === 'choice') {
    if (row.words.includes(value)) return value;
    throw refuse(`is not one of ${row.words.join(', ')}`);
  }
  if (row.words.length > 0) {
    const parts = row.words.join(row.kind === 'span' ? ':' : ',');
    const inRange = (v) => Number.isFinite(v) && v >= row.lo && v <= row.hi;
    if (!Array.isArray(value) || value.length !== row.words.length || !value.every(inRange) ||
        (row.kind === 'span' && value[0] > value[1]))
      throw refuse(`is not ${parts}, each in the valid range ${rangeText(row)}` +
        (row.kind === 'span' ? `, ${row.words[0]} <= ${row.words[1]}` : ''));
    return value;
  }
  const whole = row.kind !== 'integer' || Number.isInteger(value);
  if (Number.isFinite(value) && value >= row.lo && value <= row.hi && whole) return value;
  const what = !Number.isFinite(value) ? 'is not a number;' : whole ? 'is outside' : 'is not a whole number in';
  throw refuse(`${what} the valid range ${rangeText(row)}`);
}

const specDefault = (key) => {
  const d = SPEC[key].default;
  return SPEC[key].kind === 'flag' ? Boolean(d) : d; // null: none (the polariser)
};

export const DEFAULTS = {
  sun_az: specDefault('sun_az'), // sun azimuth (deg from north towards east)
  sun_el: specDefault('sun_el'), // sun elevation (deg)
  view_az: 0, // camera azimuth (deg)
  view_el: specDefault('view_el'), // camera elevation (deg)
  fov: specDefault('fov'), // horizontal field of view (deg)
  radius: specDefault('radius'), // drop radius (um)
  rain: specDefault('rain'), // rain rate (mm/h)
  curtain: specDefault('curtain'), // the rain fills d0..d1 metres from the camera
  moisture: 1, // global moisture multiplier, 0..1
  noise: 0, // moisture noise amount, 0..1
  secondary: specDefault('secondary'),
  corona: specDefault('corona'),
  objects: true, // houses and trees that hide the rain behind them
  // drop shape, as `hydrolux sky --shape`: 'sphere', or the shape of the assets' non-spherical
  // drops' table (rainbow_shaped.json, `hydrolux export --shape beard-chuang`): the "real drops" toggle
  shape: 'sphere',
  mode: specDefault('mode'),
  blend: specDefault('blend'),
  light: specDefault('light'), // light colour multiplier of the bow
  // a linear polariser in front of the camera, as `hydrolux sky --polarizer-deg`: null (none) or its
  // axis in degrees from the image's horizontal towards its up (0 passes the top of the bow, 90 its
  // sides); needs the assets' Stokes Q tables (hydrolux export writes them)
  polarizer: specDefault('polarizer'),
  // P90, the sky's degree of polarisation 90 degrees from the sun (`hydrolux sky --sky-max-dolp`);
  // null: sky.json's polarization.sky_max_dolp
  sky_max_dolp: specDefault('sky_max_dolp'),
  cube: specDefault('cube'), // cube-map face size (texels), as `hydrolux sky --cube-face-size`
  rings: specDefault('rings'), // half-dome rings (90 degrees), as `hydrolux sky --dome-rings`
  segments: specDefault('segments'), // half-dome segments (360 degrees), as `hydrolux sky --dome-segments`
  size: null, // [W, H]: a canvas of exactly W x H pixels (pixel ratio 1); null: the window
  test: false, // test mode: no animation loop; window.__hydroluxReady after the first frame
  ui: true, // show the control panel
  assets: 'assets/', // where rainbow.f32/.json, corona.f32/.json, sky.json and glsl/ are
};

const num = (s) => {
  const v = s.trim() === '' ? NaN : Number(s);
  if (!Number.isFinite(v)) throw new Error(`not a number: ${s}`);
  return v;
};
// A declared number: refused outside the spec's range, never clamped.
const specNum = (key) => (s) => checkSpec(key, s.trim() === '' ? NaN : Number(s), s);
// A declared switch: on or off, as the CLI's flag; other text is refused.
const specBool = (key) => (s) => {
  if (['1', 'true', 'on', 'yes'].includes(s)) return true;
  if (['0', 'false', 'off', 'no'].includes(s)) return false;
  throw new ParamError(`${key}: ${s} is not a switch (0 or 1; hydrolux sky ${SPEC[key].flag})`);
};
const bool = (s) => !(s === '0' || s === 'false' || s === 'off' || s === 'no');
const list = (s, n) => {
  const parts = s.split(/[,:x]/).map((p) => num(p));
  if (parts.length !== n) throw new Error(`expected ${n} numbers: ${s}`);
  return parts;
};

// The demo's own fractions (moisture, its noise): refused outside [0, 1] as a declared value is, not
// clamped.
const fraction = (key) => (s) => {
  const v = s.trim() === '' ? NaN : Number(s);
  if (Number.isFinite(v) && v >= 0 && v <= 1) return v;
  throw new ParamError(`${key}: ${s} is ${Number.isFinite(v) ? 'outside' : 'not a number in'} the valid range [0, 1]`);
};

// A declared list of parts (the curtain's NEAR:FAR, the light's R,G,B), refused as the CLI refuses it.
const specList = (key, n) => (s) => {
  const parts = s.split(/[,:]/).map((p) => (p.trim() === '' ? NaN : Number(p)));
  return checkSpec(key, parts.length === n ? parts : [NaN], s);
};

const PARSERS = {
  sun_az: specNum('sun_az'),
  sun_el: specNum('sun_el'),
  view_az: (s) => num(s),
  view_el: specNum('view_el'),
  fov: specNum('fov'),
  radius: specNum('radius'),
  rain: specNum('rain'),
  curtain: specList('curtain', 2),
  moisture: fraction('moisture'),
  noise: fraction('noise'),
  secondary: specBool('secondary'),
  corona: specBool('corona'),
  objects: bool,
  shape: (s) => {
    if (!/^(sphere|beard-chuang|spheroid:[0-9.]+)$/.test(s))
      throw new Error(`shape: sphere, beard-chuang or spheroid:Q (the assets' table of non-spherical drops)`);
    return s;
  },
  mode: (s) => checkSpec('mode', s),
  blend: (s) => checkSpec('blend', s),
  light: specList('light', 3),
  polarizer: (s) => (s === 'off' || s === 'none' || s === '' ? null : specNum('polarizer')(s)),
  sky_max_dolp: specNum('sky_max_dolp'),
  cube: specNum('cube'),
  rings: specNum('rings'),
  segments: specNum('segments'),
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

// The radii (um) of the assets' table the bow is drawn from ([first, last]): a radius outside them is
// refused, as `hydrolux sky --lut` refuses it ("outside the radii of --lut").
export function tableRadii(assets, shape) {
  const json = shape !== 'sphere' && assets.shaped ? assets.shaped.json : assets.rainbow.json;
  const r = json.radius_um;
  return [r[0], r[r.length - 1]];
}

// Settings (the demo's names) checked as readParams checks a URL's, and the radius against the
// assets' table: a ParamError for the first refused one; null (none) is the polariser off or
// sky.json's P90.
export function checkSettings(p, assets) {
  for (const key of Object.keys(SPEC)) {
    if (!(key in p) || p[key] === null) continue;
    if (SPEC[key].kind === 'flag') {
      if (typeof p[key] !== 'boolean') throw new ParamError(`${key}: ${p[key]} is not a switch (true or false)`);
    } else checkSpec(key, p[key], Array.isArray(p[key]) ? p[key].join(',') : String(p[key]));
  }
  if (assets && 'radius' in p) {
    const [lo, hi] = tableRadii(assets, p.shape ?? 'sphere');
    if (!(p.radius >= lo && p.radius <= hi))
      throw new ParamError(`radius: ${p.radius} is outside the radii of the assets' table [${lo}, ${hi}] um ` +
        `(hydrolux sky --lut refuses it too; export a table that holds it)`);
  }
}

// The query string of the settings that differ from the defaults.
export function writeParams(p) {
  const q = new URLSearchParams();
  for (const key of Object.keys(DEFAULTS)) {
    const v = p[key], d = DEFAULTS[key];
    if (JSON.stringify(v) === JSON.stringify(d)) continue;
    // null: the polariser off; P90 from sky.json (no URL value: the default is the spec's)
    if (v === null) {
      if (key === 'polarizer') q.set(key, 'off');
    } else if (Array.isArray(v)) q.set(key, v.join(key === 'curtain' ? ':' : key === 'size' ? 'x' : ','));
    else if (typeof v === 'boolean') q.set(key, v ? '1' : '0');
    else q.set(key, String(v));
  }
  const s = q.toString();
  return s ? '?' + s : '';
}
