// The demo's frame: (1) the opaque objects into a float target (radiance, distance), (2) for the
// half-dome mode the dome into a float target, for the cube-map mode the cube map (rebaked when
// the sun, the radius or a toggle changes), (3) example.frag over the whole canvas: sky, sun and
// ground (or the objects), the rain curtain's bow, the blend and the tone map. With p.shape other
// than "sphere" every pass reads the bow from the non-spherical drops' 3-D table (u_shaped = 1).
// With a polariser (p.polarizer, degrees) example.frag also reads the Stokes Q tables, and the cube
// map and the half dome are baked a second time with the Q tables bound in place of the intensity's.
import * as THREE from 'three';
import { fragmentSource, PRECISIONS } from './assets.js';
import { skyAt, betaGeo, dir, cameraBasis } from './sky.js';
import { makeDomeGeometry } from './dome.js';
import { makeObjects } from './objects.js';

const FULLSCREEN_VERT = 'in vec3 position;\nvoid main() { gl_Position = vec4(position.xy, 0.0, 1.0); }\n';

function fullscreenScene(material) {
  const g = new THREE.BufferGeometry();
  g.setAttribute('position', new THREE.BufferAttribute(new Float32Array([-1, -1, 0, 3, -1, 0, -1, 3, 0]), 3));
  const mesh = new THREE.Mesh(g, material);
  mesh.frustumCulled = false;
  const scene = new THREE.Scene();
  scene.add(mesh);
  return scene;
}

function tableUniforms(assets) {
  const shaped = assets.shaped;
  return {
    u_rainbow: { value: assets.rainbow.texture },
    u_rainbow_rows: { value: assets.rainbow.rows },
    u_rainbow_cols: { value: assets.rainbow.cols },
    // non-spherical drops (hydrolux export --shape): the 3-D table, used when u_shaped is 1
    u_shaped: { value: 0 },
    u_rainbow_shaped: { value: shaped ? shaped.texture : null },
    u_rainbow_shaped_rows: { value: shaped ? shaped.rows : new THREE.Vector4() },
    u_rainbow_shaped_cols: { value: shaped ? shaped.cols : new THREE.Vector4(1, 1, 1, 0) },
    u_corona: { value: assets.corona.texture },
    u_corona_rows: { value: assets.corona.rows },
    u_corona_cols: { value: assets.corona.cols },
    u_radius_um: { value: 500 },
    u_secondary: { value: 1 },
    u_corona_on: { value: 0 },
  };
}

export class HydroluxRenderer {
  constructor(canvas, assets) {
    this.assets = assets;
    this.renderer = new THREE.WebGLRenderer({
      canvas,
      antialias: false,
      alpha: false,
      preserveDrawingBuffer: true,
      powerPreference: 'high-performance',
    });
    this.renderer.autoClear = false;
    this.gl = this.renderer.getContext();
    if (!(this.gl instanceof WebGL2RenderingContext)) throw new Error('WebGL2 is required');
    if (!this.renderer.extensions.has('EXT_color_buffer_float'))
      throw new Error('EXT_color_buffer_float is required (float render targets)');
    this.camera = new THREE.PerspectiveCamera(60, 1, 0.5, 50000);
    this.width = 0;
    this.height = 0;

    const glsl = assets.glsl;
    this.composite = new THREE.RawShaderMaterial({
      glslVersion: THREE.GLSL3,
      vertexShader: FULLSCREEN_VERT,
      fragmentShader: fragmentSource(glsl, 'example.frag'),
      depthTest: false,
      depthWrite: false,
      uniforms: {
        ...tableUniforms(assets),
        u_resolution: { value: new THREE.Vector2() },
        u_cam_f: { value: new THREE.Vector3() },
        u_cam_r: { value: new THREE.Vector3() },
        u_cam_u: { value: new THREE.Vector3() },
        u_tan_half_fov: { value: 1 },
        u_cam_height: { value: 0 }, // sky.json's camera_height_m, set by render()
        u_sky: {
          value: {
            perez_a: new THREE.Vector3(),
            perez_b: new THREE.Vector3(),
            perez_c: new THREE.Vector3(),
            perez_d: new THREE.Vector3(),
            perez_e: new THREE.Vector3(),
            zenith: new THREE.Vector3(),
            xyz_to_rgb: new THREE.Matrix3(),
            sun_dir: new THREE.Vector3(),
            sun_rgb: new THREE.Vector3(),
            sky_irradiance: new THREE.Vector3(),
            ground_albedo: new THREE.Vector3(),
          },
        },
        u_l_ref: { value: 1 },
        u_light_color: { value: new THREE.Vector3(1, 1, 1) },
        u_blend: { value: 0 },
        u_beta_geo: { value: 0 }, // from sky.json's rain power law, set by render()
        u_curtain: { value: new THREE.Vector2(1000, 3000) },
        u_moisture: { value: 1 },
        u_moisture_noise: { value: 0 },
        u_bow_source: { value: 0 },
        u_bow_cube: { value: null },
        u_bow_screen: { value: null },
        u_has_scene: { value: 0 },
        u_scene: { value: null },
        u_output: { value: 0 },
        // the polariser: (on, axis in radians), P90, and the Stokes Q tables and bakes
        u_polarizer: { value: new THREE.Vector2(0, 0) },
        u_sky_max_dolp: { value: 0 }, // P90, set by render()
        u_rainbow_q: { value: assets.q ? assets.q.rainbow.texture : null },
        u_corona_q: { value: assets.q ? assets.q.corona.texture : null },
        u_rainbow_shaped_q: { value: assets.q?.shaped ? assets.q.shaped.texture : null },
        u_bow_cube_q: { value: null },
        u_bow_screen_q: { value: null },
      },
    });
    this.compositeScene = fullscreenScene(this.composite);

    this.bake = new THREE.RawShaderMaterial({
      glslVersion: THREE.GLSL3,
      vertexShader: FULLSCREEN_VERT,
      fragmentShader: fragmentSource(glsl, 'cubemap_bake.frag'),
      depthTest: false,
      depthWrite: false,
      uniforms: {
        ...tableUniforms(assets),
        u_face: { value: 0 },
        u_face_size: { value: 256 },
        u_sun_dir: { value: new THREE.Vector3() },
      },
    });
    this.bakeScene = fullscreenScene(this.bake);
    this.cubeTarget = null;
    this.cubeKey = '';
    this.cubeTargetQ = null;  // the Stokes Q's cube map (with a polariser)
    this.cubeKeyQ = '';

    this.domeMaterial = new THREE.RawShaderMaterial({
      glslVersion: THREE.GLSL3,
      vertexShader: PRECISIONS + glsl['halfdome.vert'],
      fragmentShader: fragmentSource(glsl, 'halfdome.frag'),
      depthTest: false,
      depthWrite: false,
      side: THREE.DoubleSide,
      uniforms: {
        ...tableUniforms(assets),
        u_view_proj: { value: new THREE.Matrix4() },
        u_sun_dir: { value: new THREE.Vector3() },
      },
    });
    this.domeMesh = new THREE.Mesh(new THREE.BufferGeometry(), this.domeMaterial);
    this.domeMesh.frustumCulled = false;
    this.domeScene = new THREE.Scene();
    this.domeScene.add(this.domeMesh);
    this.domeKey = '';

    this.objects = makeObjects();
    this.sceneTarget = null;
    this.domeTarget = null;
  }

  setSize(width, height, pixelRatio = 1) {
    this.renderer.setPixelRatio(pixelRatio);
    this.renderer.setSize(width, height, false);
    const w = Math.round(width * pixelRatio), h = Math.round(height * pixelRatio);
    if (w === this.width && h === this.height) return;
    this.width = w;
    this.height = h;
    const opts = {
      type: THREE.FloatType,
      format: THREE.RGBAFormat,
      minFilter: THREE.NearestFilter,
      magFilter: THREE.NearestFilter,
      generateMipmaps: false,
      depthBuffer: true,
    };
    this.sceneTarget?.dispose();
    this.domeTarget?.dispose();
    this.domeTargetQ?.dispose();
    this.sceneTarget = new THREE.WebGLRenderTarget(w, h, opts);
    this.domeTarget = new THREE.WebGLRenderTarget(w, h, { ...opts, depthBuffer: false });
    this.domeTargetQ = new THREE.WebGLRenderTarget(w, h, { ...opts, depthBuffer: false });
  }

  // One frame of the settings p (params.js).
  render(p) {
    const { width: W, height: H } = this;
    const sky = skyAt(this.assets.sky, p.sun_el);
    const s = dir(p.sun_az, p.sun_el);
    const { f, r, u } = cameraBasis(p.view_az, p.view_el);
    const tanHalf = Math.tan((p.fov * Math.PI) / 360);

    // The three.js camera: docs/sky.md's frame with z negated (north = three.js's -z).
    const cam = this.camera;
    cam.fov = (2 * Math.atan((tanHalf * H) / W) * 180) / Math.PI;
    cam.aspect = W / H;
    cam.updateProjectionMatrix();
    cam.position.set(0, sky.cameraHeight, 0);
    cam.up.set(0, 1, 0);
    cam.lookAt(f[0], sky.cameraHeight + f[1], -f[2]);
    cam.updateMatrixWorld();

    const cu = this.composite.uniforms;
    const k = sky.perezY, x = sky.perezX, y = sky.perezYy;
    const su = cu.u_sky.value;
    su.perez_a.set(k[0], x[0], y[0]);
    su.perez_b.set(k[1], x[1], y[1]);
    su.perez_c.set(k[2], x[2], y[2]);
    su.perez_d.set(k[3], x[3], y[3]);
    su.perez_e.set(k[4], x[4], y[4]);
    su.zenith.set(...sky.zenith);
    // sky.json rows; Matrix3.set takes rows and stores columns, as GLSL expects.
    su.xyz_to_rgb.set(...sky.xyzToRgb[0], ...sky.xyzToRgb[1], ...sky.xyzToRgb[2]);
    su.sun_dir.set(...s);
    su.sun_rgb.set(...sky.sunRgb);
    su.sky_irradiance.set(...sky.skyIlluminanceRgb);
    su.ground_albedo.set(...sky.groundAlbedo);
    cu.u_resolution.value.set(W, H);
    cu.u_cam_f.value.set(...f);
    cu.u_cam_r.value.set(...r);
    cu.u_cam_u.value.set(...u);
    cu.u_tan_half_fov.value = tanHalf;
    cu.u_cam_height.value = sky.cameraHeight;
    cu.u_l_ref.value = sky.lRef;
    cu.u_light_color.value.set(...p.light);
    cu.u_blend.value = p.blend === 'whitepaper' ? 1 : 0;
    cu.u_beta_geo.value = betaGeo(p.rain, this.assets.sky);
    cu.u_curtain.value.set(p.curtain[0], p.curtain[1]);
    cu.u_moisture.value = p.moisture;
    cu.u_moisture_noise.value = p.noise;
    const shaped = this.shaped(p);
    const polarized = this.polarized(p, shaped);
    cu.u_polarizer.value.set(polarized ? 1 : 0, polarized ? (p.polarizer * Math.PI) / 180 : 0);
    cu.u_sky_max_dolp.value = polarized ? this.skyMaxDolp(p) : 0;
    for (const m of [this.composite, this.bake, this.domeMaterial]) {
      m.uniforms.u_shaped.value = shaped ? 1 : 0;
      m.uniforms.u_radius_um.value = p.radius;
      m.uniforms.u_secondary.value = p.secondary ? 1 : 0;
      m.uniforms.u_corona_on.value = p.corona ? 1 : 0;
    }

    const R = this.renderer;
    // (1) the objects
    cu.u_has_scene.value = p.objects ? 1 : 0;
    cu.u_scene.value = p.objects ? this.sceneTarget.texture : null;
    if (p.objects) {
      this.objects.update(s, sky.sunRgb, sky.skyIlluminanceRgb);
      R.setRenderTarget(this.sceneTarget);
      R.setClearColor(0x000000, 0);
      R.clear(true, true, false);
      R.render(this.objects.scene, cam);
    }
    // (2) the optimisations
    cu.u_bow_source.value = 0;
    cu.u_bow_cube.value = null;
    cu.u_bow_screen.value = null;
    cu.u_bow_cube_q.value = null;
    cu.u_bow_screen_q.value = null;
    if (p.mode === 'cube-map') {
      this.bakeCube(p, s);
      cu.u_bow_source.value = 1;
      cu.u_bow_cube.value = this.cubeTarget.texture;
      if (polarized) {
        this.bakeCube(p, s, true);
        cu.u_bow_cube_q.value = this.cubeTargetQ.texture;
      }
    } else if (p.mode === 'half-dome') {
      const key = [s.join(), p.rings, p.segments].join('|');
      if (key !== this.domeKey) {
        this.domeMesh.geometry.dispose();
        this.domeMesh.geometry = makeDomeGeometry(s, p.rings, p.segments);
        this.domeKey = key;
      }
      // projection x view rotation in docs/sky.md's frame: view space rows r, u, -f.
      const view = new THREE.Matrix4().set(
        r[0], r[1], r[2], 0,
        u[0], u[1], u[2], 0,
        -f[0], -f[1], -f[2], 0,
        0, 0, 0, 1,
      );
      this.domeMaterial.uniforms.u_view_proj.value.multiplyMatrices(cam.projectionMatrix, view);
      this.domeMaterial.uniforms.u_sun_dir.value.set(...s);
      // The dome, and with a polariser again with the Q tables bound (halfdome.frag).
      for (const q of polarized ? [false, true] : [false]) {
        this.bindTables(this.domeMaterial, q);
        R.setRenderTarget(q ? this.domeTargetQ : this.domeTarget);
        R.setClearColor(0x000000, 0);
        R.clear(true, false, false);
        R.render(this.domeScene, cam);
      }
      this.bindTables(this.domeMaterial, false);
      cu.u_bow_source.value = 2;
      cu.u_bow_screen.value = this.domeTarget.texture;
      if (polarized) cu.u_bow_screen_q.value = this.domeTargetQ.texture;
    }
    // (3) the composite
    R.setRenderTarget(null);
    R.render(this.compositeScene, cam);
  }

  // Whether p asks for non-spherical drops (p.shape other than "sphere"); an error when the assets
  // hold no table of that shape (hydrolux export --shape writes one).
  shaped(p) {
    if (!p.shape || p.shape === 'sphere') return false;
    const t = this.assets.shaped;
    if (!t || t.shape !== p.shape)
      throw new Error(
        `shape=${p.shape}: the assets hold ${t ? `the table of ${t.shape} drops only` : 'no table of non-spherical drops'}` +
          ` (export them with \`hydrolux export --shape ${p.shape}\`)`,
      );
    return true;
  }

  // Whether p asks for a polariser; an error when the assets hold no Stokes Q tables (an export from
  // before hydrolux export wrote them) or none for the drops' shape.
  polarized(p, shaped) {
    if (p.polarizer === null || p.polarizer === undefined) return false;
    const q = this.assets.q;
    if (!q || (shaped && !q.shaped))
      throw new Error(
        `polarizer=${p.polarizer}: the assets hold no Stokes Q table${shaped ? ' of the non-spherical drops' : 's'}` +
          ' (rainbow_q.f32; export them again with `hydrolux export`)',
      );
    return true;
  }

  // P90: p.sky_max_dolp, else sky.json's polarization.sky_max_dolp (an error where it has none).
  skyMaxDolp(p) {
    if (p.sky_max_dolp !== null && p.sky_max_dolp !== undefined) return p.sky_max_dolp;
    const v = this.assets.sky?.polarization?.sky_max_dolp;
    if (typeof v !== 'number')
      throw new Error('sky.json has no "polarization.sky_max_dolp" (re-export the assets with `hydrolux export`)');
    return v;
  }

  // The intensity's tables (q false) or the Stokes Q's (q true) on a bake material's samplers.
  bindTables(m, q) {
    const a = this.assets, t = q ? a.q : a;
    m.uniforms.u_rainbow.value = t.rainbow.texture;
    if (m.uniforms.u_corona) m.uniforms.u_corona.value = t.corona.texture;
    m.uniforms.u_rainbow_shaped.value = t.shaped ? t.shaped.texture : null;
  }

  // The cube map of the bow (q false), or of its Stokes Q with the Q tables bound (q true).
  bakeCube(p, s, q = false) {
    const n = p.cube;
    const key = [s.join(), p.radius, p.secondary, p.corona, p.shape, n].join('|');
    if (key === (q ? this.cubeKeyQ : this.cubeKey) && (q ? this.cubeTargetQ : this.cubeTarget)) return;
    const slot = q ? 'cubeTargetQ' : 'cubeTarget';
    if (!this[slot] || this[slot].width !== n) {
      this[slot]?.dispose();
      this[slot] = new THREE.WebGLCubeRenderTarget(n, {
        type: THREE.HalfFloatType,
        format: THREE.RGBAFormat,
        minFilter: THREE.LinearFilter,
        magFilter: THREE.LinearFilter,
        generateMipmaps: false,
        depthBuffer: false,
      });
    }
    const b = this.bake.uniforms;
    b.u_face_size.value = n;
    b.u_sun_dir.value.set(...s);
    this.bindTables(this.bake, q);
    for (let face = 0; face < 6; face++) {
      b.u_face.value = face;
      this.renderer.setRenderTarget(this[slot], face);
      this.renderer.render(this.bakeScene, this.camera);
    }
    this.bindTables(this.bake, false);
    if (q) this.cubeKeyQ = key;
    else this.cubeKey = key;
  }

  // Waits for the GPU (a 1-pixel read) so that a time measured around render() is the frame's.
  sync() {
    const gl = this.gl;
    const px = new Uint8Array(4);
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
    gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, px);
  }

  // The canvas's pixels, top row first, RGBA.
  readPixels() {
    const gl = this.gl;
    const { width: W, height: H } = this;
    const buf = new Uint8Array(W * H * 4);
    this.renderer.setRenderTarget(null);
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
    gl.readPixels(0, 0, W, H, gl.RGBA, gl.UNSIGNED_BYTE, buf);
    const out = new Uint8Array(W * H * 4);
    for (let j = 0; j < H; j++) out.set(buf.subarray((H - 1 - j) * W * 4, (H - j) * W * 4), j * W * 4);
    return out;
  }
}
