// Vite config of the hydrolux web demo. The exported assets (`hydrolux export --dir DIR`) are
// served at /assets/ from the folder named by the HYDROLUX_ASSETS environment variable (dev server
// and `vite preview`); a built page can also be pointed at any URL with ?assets=URL.
import { defineConfig } from 'vite';
import fs from 'node:fs';
import path from 'node:path';

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

export default defineConfig({
  base: './',
  plugins: [serveAssets()],
  server: { host: '127.0.0.1' },
  preview: { host: '127.0.0.1' },
  // Built files go to app/, so that /assets/ stays the exported assets' URL.
  build: { target: 'es2022', assetsDir: 'app', chunkSizeWarningLimit: 1024 },
});
