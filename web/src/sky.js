// Sky and rain quantities from the exported sky.json at any sun elevation (docs/sky.md): its rows
// are 1 degree apart, interpolated linearly here; at a tabulated elevation the values are exact.

// sky.json's keys, tolerant of per-elevation arrays or one value for all elevations.
function rowOf(sky, key, i, f) {
  const a = sky[key];
  if (a === undefined) throw new Error(`sky.json has no "${key}"`);
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
    groundAlbedo: sky.ground_albedo,
    xyzToRgb: sky.xyz_to_rgb,
    cameraHeight: sky.camera_height_m ?? 1.7,
  };
}

// beta_geo = pi M2 (m^-1) of Marshall and Palmer's rain: n(a) = N0 exp(-Lambda a) per metre of
// radius with N0 = 1.6e7 m^-4 (their 8e6 per metre of diameter) and Lambda = 8200 R^-0.21 m^-1,
// so M2 = 2 N0 / Lambda^3 (5.0e-4 m^-1 at 5 mm/h).
// sky.json's "rain" (coefficient x R^exponent, the same power law) is used when present.
export function betaGeo(rainMmh, sky) {
  if (sky?.rain?.coefficient !== undefined) return sky.rain.coefficient * Math.pow(rainMmh, sky.rain.exponent);
  const lambda = 8200 * Math.pow(rainMmh, -0.21);
  return (Math.PI * 2 * 1.6e7) / (lambda * lambda * lambda);
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
