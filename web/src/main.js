// hydrolux web demo: the rain curtain's rainbow over the Preetham sky, in three.js, with the GLSL
// files and the Lee tables that `hydrolux export` writes (loaded at run time from ?assets=URL).
import { readParams, writeParams, checkSettings, tableRadii, ParamError, SPEC, MODES, BLENDS } from './params.js';
import { loadAssets } from './assets.js';
import { HydroluxRenderer } from './renderer.js';
import { dir } from './sky.js';

const $ = (id) => document.getElementById(id);

function showError(e) {
  console.error(e);
  const box = $('error');
  box.hidden = false;
  // A refused setting is the user's, not a bug: its message alone (parameter, value, valid range).
  box.textContent = e instanceof ParamError ? e.message : String(e && e.stack ? e.stack : e);
  window.__hydroluxError = String(e);
}
window.addEventListener('error', (ev) => showError(ev.error || ev.message));
window.addEventListener('unhandledrejection', (ev) => showError(ev.reason));

function toBase64(bytes) {
  let s = '';
  for (let i = 0; i < bytes.length; i += 0x8000) s += String.fromCharCode(...bytes.subarray(i, i + 0x8000));
  return btoa(s);
}

async function main() {
  const p = readParams(location.search);
  const canvas = $('view');
  const assets = await loadAssets(p.assets);
  checkSettings(p, assets); // the radius within the assets' table: refused before any frame, as the CLI does
  narrowRadius(assets);
  const hx = new HydroluxRenderer(canvas, assets);

  const resize = () => {
    if (p.size) {
      document.body.classList.add('fixed');
      canvas.style.width = p.size[0] + 'px';
      canvas.style.height = p.size[1] + 'px';
      $('panel').style.left = p.size[0] + 10 + 'px';
      hx.setSize(p.size[0], p.size[1], 1);
    } else {
      hx.setSize(window.innerWidth, window.innerHeight, Math.min(window.devicePixelRatio || 1, 2));
    }
  };
  resize();
  window.addEventListener('resize', () => {
    resize();
    dirty = true;
  });

  // Frame time: render + a 1-pixel read (waits for the GPU), averaged over the last 60 frames.
  const times = [];
  const frame = () => {
    const t0 = performance.now();
    hx.render(p);
    hx.sync();
    const dt = performance.now() - t0;
    times.push(dt);
    if (times.length > 60) times.shift();
    return dt;
  };
  const averageMs = () => times.reduce((a, b) => a + b, 0) / Math.max(times.length, 1);

  let dirty = true;
  const changed = () => {
    dirty = true;
    const keep = new URLSearchParams(location.search);
    const q = new URLSearchParams(writeParams(p));
    for (const k of ['assets', 'test', 'size', 'ui']) if (keep.has(k)) q.set(k, keep.get(k));
    const s = q.toString();
    history.replaceState(null, '', s ? '?' + s : location.pathname);
  };
  shapedTable = assets.shaped;
  hasStokes = Boolean(assets.q);
  skyMaxDolpDefault = assets.sky?.polarization?.sky_max_dolp ?? null;
  if (p.ui) buildUi(p, changed);
  setupPointer(canvas, p, hx, changed);

  frame();
  window.__hydrolux = {
    params: p,
    // Applies settings (params.js names), renders one frame, returns its time in ms.
    // Refused (a ParamError, p unchanged, no frame) as the URL's values are.
    set(settings) {
      checkSettings({ ...p, ...settings }, assets);
      Object.assign(p, settings);
      return frame();
    },
    render: frame,
    // The mean time of n frames (render + GPU sync) after one warm-up frame.
    measure(n = 20) {
      frame();
      let sum = 0;
      for (let i = 0; i < n; i++) sum += frame();
      return sum / n;
    },
    size: () => [hx.width, hx.height],
    readPixelsBase64: () => toBase64(hx.readPixels()),
    // Decodes an image (PNG) by the browser, without colour conversion: RGBA, top row first.
    async loadImageBase64(url) {
      const blob = await (await fetch(url)).blob();
      const bmp = await createImageBitmap(blob, { colorSpaceConversion: 'none', premultiplyAlpha: 'none' });
      const c = new OffscreenCanvas(bmp.width, bmp.height);
      const ctx = c.getContext('2d');
      ctx.drawImage(bmp, 0, 0);
      const d = ctx.getImageData(0, 0, bmp.width, bmp.height).data;
      return { width: bmp.width, height: bmp.height, data: toBase64(new Uint8Array(d.buffer)) };
    },
  };
  window.__hydroluxReady = true;

  if (p.test) return; // test mode: frames on request only
  const loop = () => {
    if (dirty || p.noise > 0 || times.length < 60) {
      frame();
      dirty = false;
    }
    const ms = $('frame-ms');
    if (ms) ms.textContent = averageMs().toFixed(2);
    requestAnimationFrame(loop);
  };
  requestAnimationFrame(loop);
}

// Drag: look around; Shift+drag, or a drag that starts within 6 degrees of the sun, moves the sun.
function setupPointer(canvas, p, hx, changed) {
  let drag = null;
  const rayAt = (ev) => {
    const rect = canvas.getBoundingClientRect();
    const x = (ev.clientX - rect.left) / rect.width, y = (ev.clientY - rect.top) / rect.height;
    const t = Math.tan((p.fov * Math.PI) / 360);
    const px = (2 * x - 1) * t, py = (1 - 2 * y) * t * (rect.height / rect.width);
    const f = dir(p.view_az, p.view_el);
    const r0 = [f[2], 0, -f[0]], rl = Math.hypot(r0[0], r0[2]);
    const r = [r0[0] / rl, 0, r0[2] / rl];
    const u = [f[1] * r[2] - f[2] * r[1], f[2] * r[0] - f[0] * r[2], f[0] * r[1] - f[1] * r[0]];
    const v = [0, 1, 2].map((k) => f[k] + px * r[k] + py * u[k]);
    const l = Math.hypot(...v);
    return v.map((c) => c / l);
  };
  const azEl = (v) => [((Math.atan2(v[0], v[2]) * 180) / Math.PI + 360) % 360, (Math.asin(v[1]) * 180) / Math.PI];
  canvas.addEventListener('pointerdown', (ev) => {
    const v = rayAt(ev);
    const s = dir(p.sun_az, p.sun_el);
    const near = (Math.acos(Math.min(1, v[0] * s[0] + v[1] * s[1] + v[2] * s[2])) * 180) / Math.PI < 6;
    drag = { sun: ev.shiftKey || near, x: ev.clientX, y: ev.clientY, az: p.view_az, el: p.view_el };
    canvas.setPointerCapture(ev.pointerId);
  });
  canvas.addEventListener('pointermove', (ev) => {
    if (!drag) return;
    if (drag.sun) {
      const [az, el] = azEl(rayAt(ev));
      p.sun_az = Math.round(az * 10) / 10;
      p.sun_el = Math.min(SPEC.sun_el.hi, Math.max(SPEC.sun_el.lo, Math.round(el * 10) / 10));
    } else {
      const rect = canvas.getBoundingClientRect();
      const degPerPx = p.fov / rect.width;
      p.view_az = (((drag.az - (ev.clientX - drag.x) * degPerPx) % 360) + 360) % 360;
      p.view_el = Math.min(SPEC.view_el.hi, Math.max(SPEC.view_el.lo, drag.el + (ev.clientY - drag.y) * degPerPx));
      p.view_az = Math.round(p.view_az * 10) / 10;
      p.view_el = Math.round(p.view_el * 10) / 10;
    }
    syncUi(p);
    changed();
  });
  const end = () => (drag = null);
  canvas.addEventListener('pointerup', end);
  canvas.addEventListener('pointercancel', end);
}

// The control panel: sliders, toggles, selects. A slider of one of hydrolux sky's parameters spans
// the spec's range (params.js: hydrolux spec --json); the radius's is narrowed to the assets' table
// (narrowRadius), whose other radii the page refuses. The radius moves on a log scale, the rain rate
// (from 0) on a cubic one: fine steps for drizzle, the whole range to a cloudburst.
const spec = (key) => ({ min: SPEC[key].lo, max: SPEC[key].hi });
const CONTROLS = [
  { key: 'sun_az', label: 'sun azimuth', ...spec('sun_az'), step: 0.5, unit: '°' },
  { key: 'sun_el', label: 'sun elevation', ...spec('sun_el'), step: 0.5, unit: '°' },
  { key: 'radius', label: 'drop radius', ...spec('radius'), scale: 'log', unit: 'µm' },
  { key: 'rain', label: 'rain rate', ...spec('rain'), scale: 'cubic', unit: 'mm/h' },
  { key: 'moisture', label: 'moisture', min: 0, max: 1, step: 0.01 },
  { key: 'noise', label: 'moisture noise', min: 0, max: 1, step: 0.01 },
  { key: 'curtain0', label: 'rain from', min: 0, max: 5000, step: 50, unit: 'm' },
  { key: 'curtain1', label: 'rain to', min: 100, max: 20000, step: 100, unit: 'm' },
  { key: 'fov', label: 'field of view', ...spec('fov'), step: 1, unit: '°' },
  { key: 'view_az', label: 'view azimuth', min: 0, max: 360, step: 0.1, unit: '°' },
  { key: 'view_el', label: 'view elevation', ...spec('view_el'), step: 0.1, unit: '°' },
];
// The radius slider within the assets' table (spheres' radii, the spec's range cut to them).
function narrowRadius(assets) {
  const c = CONTROLS.find((k) => k.key === 'radius');
  const [lo, hi] = tableRadii(assets, 'sphere');
  Object.assign(c, { min: Math.max(SPEC.radius.lo, lo), max: Math.min(SPEC.radius.hi, hi) });
}
// A slider's position (0..1 on a log or cubic scale, else the value) and back.
const toSlider = (c, v) =>
  !c.scale ? v : c.max === c.min ? 0
    : c.scale === 'log' ? Math.log(v / c.min) / Math.log(c.max / c.min) : Math.cbrt((v - c.min) / (c.max - c.min));
const fromSlider = (c, x) => {
  if (!c.scale) return x;
  const v = c.scale === 'log' ? c.min * Math.pow(c.max / c.min, x) : c.min + (c.max - c.min) * x * x * x;
  return Math.min(c.max, Math.max(c.min, Number(v.toPrecision(3))));
};
const TOGGLES = [
  { key: 'secondary', label: 'secondary' },
  { key: 'corona', label: 'corona' },
  { key: 'objects', label: 'objects' },
];
const inputs = {};
// The assets' non-spherical drops' table (null without one): the "real drops" toggle.
let shapedTable = null;
// Whether the assets hold the Stokes Q tables (the polariser), and sky.json's P90.
let hasStokes = false;
let skyMaxDolpDefault = null;
const shapeLabel = (name) =>
  name === 'beard-chuang' ? 'Beard-Chuang' : name.startsWith('spheroid:') ? `spheroids, Q ${name.slice(9)}` : name;

const getV = (p, key) => (key === 'curtain0' ? p.curtain[0] : key === 'curtain1' ? p.curtain[1] : p[key]);
const setV = (p, key, v) => {
  if (key === 'curtain0') p.curtain = [v, Math.max(v, p.curtain[1])];
  else if (key === 'curtain1') p.curtain = [Math.min(p.curtain[0], v), v];
  else p[key] = v;
};
const fmt = (v) => (Math.abs(v) >= 100 ? v.toFixed(0) : Math.abs(v) >= 10 ? v.toFixed(1) : v.toFixed(2).replace(/0$/, ''));

function syncUi(p) {
  for (const c of CONTROLS) {
    const el = inputs[c.key];
    if (!el) continue;
    const v = getV(p, c.key);
    el.input.value = toSlider(c, v);
    el.value.textContent = fmt(v) + (c.unit ? ' ' + c.unit : '');
  }
  const box = $('ctl-shape');
  if (box) box.checked = p.shape !== 'sphere';
  // the polariser's dial: off, or its axis -90..90 degrees; and the sky's P90
  const pol = $('ctl-polarizer-on'), dial = $('ctl-polarizer');
  if (pol && dial) {
    const on = p.polarizer !== null && p.polarizer !== undefined;
    pol.checked = on;
    dial.disabled = !on || !hasStokes;
    if (on) dial.value = String(p.polarizer);
    $('val-polarizer').textContent = on ? `${fmt(p.polarizer)}°` : 'off';
  }
  const p90 = $('ctl-sky_max_dolp');
  if (p90) {
    const v = p.sky_max_dolp ?? skyMaxDolpDefault;
    if (v !== null) p90.value = String(v);
    p90.disabled = !hasStokes;
    $('val-sky_max_dolp').textContent = v === null ? '-' : v.toFixed(2);
  }
  // The table holds the bow for one sun elevation: say so when the sun is elsewhere.
  const note = $('shape-note');
  if (note) {
    const off = p.shape !== 'sphere' && shapedTable && Math.abs(p.sun_el - shapedTable.sunElevationDeg) > 0.05;
    note.hidden = !off;
    if (off)
      note.textContent = `The real drops' bow is tabulated for a sun ${shapedTable.sunElevationDeg}° up ` +
        `(hydrolux export --sun-elevation-deg): it is drawn as if the sun were there.`;
  }
}

function buildUi(p, changed) {
  $('panel').hidden = false;
  const root = $('controls');
  for (const c of CONTROLS) {
    const label = document.createElement('label');
    label.innerHTML = `<span>${c.label}</span>`;
    const input = document.createElement('input');
    input.type = 'range';
    input.id = 'ctl-' + c.key;
    if (c.scale) Object.assign(input, { min: 0, max: 1, step: 0.001, disabled: c.min === c.max });
    else Object.assign(input, { min: c.min, max: c.max, step: c.step });
    const value = document.createElement('span');
    value.className = 'value';
    label.append(input, value);
    root.append(label);
    inputs[c.key] = { input, value };
    input.addEventListener('input', () => {
      setV(p, c.key, fromSlider(c, Number(input.value)));
      syncUi(p);
      changed();
    });
  }
  const toggles = document.createElement('div');
  for (const t of TOGGLES) {
    const label = document.createElement('label');
    label.className = 'check';
    const input = document.createElement('input');
    input.type = 'checkbox';
    input.id = 'ctl-' + t.key;
    input.checked = p[t.key];
    input.addEventListener('change', () => {
      p[t.key] = input.checked;
      changed();
    });
    label.append(input, t.label);
    toggles.append(label);
  }
  {
    // "real drops": falling drops' flattened shape, from the assets' 3-D table (hydrolux export
    // --shape); switching it on puts the sun at the elevation the table was computed for.
    const t = shapedTable;
    const label = document.createElement('label');
    label.className = 'check';
    const input = document.createElement('input');
    input.type = 'checkbox';
    input.id = 'ctl-shape';
    input.checked = p.shape !== 'sphere';
    input.disabled = !t;
    label.title = t
      ? `Flattened falling drops (${t.shape}): the bow by Airy theory at 19 position angles, for a sun ` +
        `${t.sunElevationDeg}° up`
      : 'The assets hold no table of non-spherical drops: export them with hydrolux export --shape beard-chuang';
    input.addEventListener('change', () => {
      p.shape = input.checked ? t.shape : 'sphere';
      if (input.checked) p.sun_el = t.sunElevationDeg;
      syncUi(p);
      changed();
    });
    label.append(input, t ? `real drops (${shapeLabel(t.shape)})` : 'real drops');
    toggles.append(label);
  }
  root.append(toggles);
  {
    // The polariser in front of the camera (hydrolux sky --polarizer-deg): a toggle and a dial of its
    // axis in degrees from the image's horizontal over the spec's range (0 passes the top of the bow, 90 its sides),
    // and the sky's P90 (--sky-max-dolp). Without the assets' Stokes Q tables, greyed out.
    const why = 'The assets hold no Stokes Q tables (rainbow_q.f32): export them again with hydrolux export';
    const label = document.createElement('label');
    label.className = 'dial';
    label.innerHTML = '<span>polariser</span>';
    const on = document.createElement('input');
    on.type = 'checkbox';
    on.id = 'ctl-polarizer-on';
    on.disabled = !hasStokes;
    const dial = document.createElement('input');
    dial.type = 'range';
    dial.id = 'ctl-polarizer';
    Object.assign(dial, { min: SPEC.polarizer.lo, max: SPEC.polarizer.hi, step: 1, value: 0 });
    const value = document.createElement('span');
    value.className = 'value';
    value.id = 'val-polarizer';
    label.title = hasStokes
      ? 'A linear polariser in front of the camera: its axis in degrees from the image\'s horizontal ' +
        '(0 passes the top of the bow and darkens its sides, 90 the reverse and darkens the sky 90° from the sun)'
      : why;
    on.addEventListener('change', () => {
      p.polarizer = on.checked ? Number(dial.value) : null;
      syncUi(p);
      changed();
    });
    dial.addEventListener('input', () => {
      p.polarizer = Number(dial.value);
      syncUi(p);
      changed();
    });
    label.append(on, dial, value);
    root.append(label);
    const l2 = document.createElement('label');
    l2.innerHTML = '<span>sky P90</span>';
    l2.title = hasStokes
      ? "The sky's degree of polarisation 90° from the sun (0.946 for air's molecules alone, 0.6-0.85 " +
        'in clear skies); seen through the polariser'
      : why;
    const p90 = document.createElement('input');
    p90.type = 'range';
    p90.id = 'ctl-sky_max_dolp';
    Object.assign(p90, { min: SPEC.sky_max_dolp.lo, max: SPEC.sky_max_dolp.hi, step: 0.01 });
    const v2 = document.createElement('span');
    v2.className = 'value';
    v2.id = 'val-sky_max_dolp';
    p90.addEventListener('input', () => {
      p.sky_max_dolp = Number(p90.value);
      syncUi(p);
      changed();
    });
    l2.append(p90, v2);
    root.append(l2);
  }
  for (const [key, options, text] of [
    ['blend', BLENDS, 'blend'],
    ['mode', MODES, 'optimisation'],
  ]) {
    const label = document.createElement('label');
    label.innerHTML = `<span>${text}</span>`;
    const sel = document.createElement('select');
    sel.id = 'ctl-' + key;
    for (const o of options) sel.add(new Option(o, o, false, p[key] === o));
    sel.addEventListener('change', () => {
      p[key] = sel.value;
      changed();
    });
    label.append(sel, document.createElement('span'));
    root.append(label);
  }
  syncUi(p);
}

main().catch(showError);
