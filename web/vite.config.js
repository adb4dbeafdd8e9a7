// Vite config of the hydrolux web demo. The exported assets (`hydrolux export --dir DIR`) are
// served at /assets/ from the folder named by the HYDROLUX_ASSETS environment variable (dev server
// and `vite preview`); a built page can also be pointed at any URL with ?assets=URL.
//
// The sky's declared parameters (names, ranges, defaults: src/params.js) come from the library at
// build time: the module `virtual:hydrolux-spec` is the sky's rows of `hydrolux spec --json`, run
// from the binary HYDROLUX_BIN names (default: ../build/bin/hydrolux, which `make` builds; the e2e
// test and `make demo` pass theirs). Without the binary the build stops, naming it.
import { defineConfig } from 'vite';
import { spawnSync } from 'node:child_process';
import fs from 'node:fs';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

const here = path.dirname(fileURLToPath(import.meta.url));

const TYPES = { '.json': 'application/json', '.f32': 'application/octet-stream', '.glsl': 'text/plain',
  '.frag': 'text/plain', '.vert': 'text/plain', '.png': 'image/png', '.md': 'text/plain' };

function serveAssets() {
  const dir = process.env.HYDROLUX_ASSETS;
  const middleware = (req, res, next) => {
    if (!dir || !req.url.startsWith('/assets/')) return next();
    const rel = decodeURIComponent(req.url.slice('/assets/'.length).split('?')[0]);
    const file = path.resolve(dir, rel);
    if (!file.startsWith(path.resolve(dir) + path.sep) || !fs.existsSync(file) || !fs.statSync(file).isFile()) {
      res.statusCode = 404;
      return res.end('not found');
    }
    res.setHeader('Content-Type', TYPES[path.extname(file)] ?? 'application/octet-stream');
    fs.createReadStream(file).pipe(res);
  };
  return {
    name: 'hydrolux-assets',
    configureServer(server) {
      server.middlewares.use(middleware);
    },
    configurePreviewServer(server) {
      server.middlewares.use(middleware);
    },
  };
}

// The sky's rows of `hydrolux spec --json` as the module virtual:hydrolux-spec: {command, params:
// [{name, flag, kind, unit, lo, hi, default, words}]}.
function hydroluxSpec() {
  const id = 'virtual:hydrolux-spec';
  return {
    name: 'hydrolux-spec',
    resolveId(source) {
      return source === id ? '\0' + id : null;
    },
    load(resolved) {
      if (resolved !== '\0' + id) return null;
      const bin = path.resolve(process.env.HYDROLUX_BIN ?? path.join(here, '..', 'build', 'bin', 'hydrolux'));
      if (!fs.existsSync(bin))
        throw new Error(`the demo's parameters come from \`hydrolux spec --json\`: no hydrolux binary at ${bin} ` +
          '(build it with make, or name it with HYDROLUX_BIN)');
      const r = spawnSync(bin, ['spec', '--json'], { encoding: 'utf8', maxBuffer: 16 << 20 });
      if (r.error || r.status !== 0)
        throw new Error(`${bin} spec --json failed (${r.error?.message ?? 'exit ' + r.status}): ${r.stderr}`);
      const sky = JSON.parse(r.stdout).jobs.find((j) => j.name === 'sky');
      if (!sky) throw new Error(`${bin} spec --json lists no job "sky"`);
      this.addWatchFile(bin);
      const params = sky.params.map(({ name, flag, kind, unit, lo, hi, default: d, words }) => ({ name, flag, kind, unit, lo, hi, default: d, words }));
      return `export default ${JSON.stringify({ command: sky.command, params })};\n`;
    },
  };
}

export default defineConfig({
  base: './',
  plugins: [serveAssets(), hydroluxSpec()],
  server: { host: '127.0.0.1' },
  preview: { host: '127.0.0.1' },
  // Built files go to app/, so that /assets/ stays the exported assets' URL.
  build: { target: 'es2022', assetsDir: 'app', chunkSizeWarningLimit: 1024 },
});
