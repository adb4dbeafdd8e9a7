// Sky and rain quantities from the exported sky.json at any sun elevation (docs/sky.md): its rows
// are 1 degree apart, interpolated linearly here; at a tabulated elevation the values are exact.

// The keys of sky.json (written by `hydrolux export`) that the page reads. Every constant comes from
// there, with no copy here: a missing key is an error (checkSky, when the assets load), never a
// silent default.
export const SKY_KEYS = [
  'elevations_deg',
  'sun_illuminance_lux',
  'sun_rgb',
  'sky_illuminance_rgb',
  'l_ref',
  'zenith_Y_kcd',
  'zenith_x',
  'zenith_y',
  'perez_Y',
  'perez_x',
  'perez_y',
  'ground_albedo',
  'xyz_to_rgb',
  'camera_height_m',
  'rain.coefficient',
  'rain.exponent',
];

// The value at a dotted key ("rain.coefficient"), undefined where any part is missing.
function lookup(sky, key) {
  return key.split('.').reduce((o, k) => (o !== null && typeof o === 'object' ? o[k] : undefined), sky);
}

// Throws, naming every key of SKY_KEYS that sky.json lacks.
export function checkSky(sky) {
  const missing = SKY_KEYS.filter((k) => lookup(sky, k) === undefined);
  if (missing.length)
    throw new Error(
      `sky.json has no ${missing.map((k) => `"${k}"`).join(', ')} (re-export the assets with \`hydrolux export\`)`,
    );
  if (!Array.isArray(sky.elevations_deg) || sky.elevations_deg.length < 2)
    throw new Error('sky.json: "elevations_deg" must list at least two elevations');
}

// sky.json's value at a key, which must be there.
function need(sky, key) {
  const v = lookup(sky, key);
  if (v === undefined) throw new Error(`sky.json has no "${key}"`);
  return v;
}

// sky.json's keys, tolerant of per-elevation arrays or one value for all elevations.
function rowOf(sky, key, i, f) {
  const a = need(sky, key);
  if (!Array.isArray(a) || a.length !== sky.elevations_deg.length) return a; // one value for all
  const lerp = (x, y) => (Array.isArray(x) ? x.map((xi, k) => lerp(xi, y[k])) : x + (y - x) * f);
  return f === 0 ? a[i] : lerp(a[i], a[i + 1]);
}

export function skyAt(sky, elevationDeg) {
  const e = sky.elevations_deg;
  let i = 0;
  while (i < e.length - 2 && elevationDeg > e[i + 1]) i++;
  let f = (elevationDeg - e[i]) / (e[i + 1] - e[i]);
  f = Math.min(1, Math.max(0, f));
  if (f === 1) {
    i += 1;
    f = 0;
  }
  if (i === e.length - 1) {
    i -= 1;
    f = 1;
  }
  const get = (k) => rowOf(sky, k, i, f);
  return {
    sunIlluminanceLux: get('sun_illuminance_lux'),
    sunRgb: get('sun_rgb'),
    skyIlluminanceRgb: get('sky_illuminance_rgb'),
    lRef: get('l_ref'),
    zenith: [get('zenith_Y_kcd') * 1000, get('zenith_x'), get('zenith_y')],
    perezY: get('perez_Y'),
    perezX: get('perez_x'),
    perezYy: get('perez_y'),
    groundAlbedo: need(sky, 'ground_albedo'),
    xyzToRgb: need(sky, 'xyz_to_rgb'),
    cameraHeight: need(sky, 'camera_height_m'),
  };
}

// beta_geo = pi M2 (m^-1) of Marshall and Palmer's rain at rainMmh (mm/h): sky.json's "rain", the
// power law coefficient x R^exponent that `hydrolux export` fits to the library's one law
// (scene::rain_beta_geo_per_m, from scatter::SizeDistribution::marshall_palmer).
export function betaGeo(rainMmh, sky) {
  return need(sky, 'rain.coefficient') * Math.pow(rainMmh, need(sky, 'rain.exponent'));
}

// dir(az, el) in the world frame of docs/sky.md: +y up, +z north, +x east.
export function dir(azDeg, elDeg) {
  const az = (azDeg * Math.PI) / 180, el = (elDeg * Math.PI) / 180;
  return [Math.sin(az) * Math.cos(el), Math.sin(el), Math.cos(az) * Math.cos(el)];
}

export function cross(a, b) {
  return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
}
export function normalize(a) {
  const l = Math.hypot(a[0], a[1], a[2]);
  return [a[0] / l, a[1] / l, a[2] / l];
}

// The camera basis of docs/sky.md: f = dir(view_az, view_el), r = normalize(up x f), u = f x r.
export function cameraBasis(viewAz, viewEl) {
  const f = dir(viewAz, viewEl);
  const r = normalize(cross([0, 1, 0], f));
  const u = cross(f, r);
  return { f, r, u };
}
