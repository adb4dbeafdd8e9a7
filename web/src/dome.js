// The half dome of docs/sky.md: a hemisphere of directions around the antisolar point, rings x
// segments quads (two triangles each) whose vertices carry theta (halfdome.vert describes it).
import * as THREE from 'three';
import { cross, normalize } from './sky.js';

// The dome's frame, as the CPU reference builds it (scene/compositor.cpp): the axis a = -s, a
// helper h = +y (or +x when |a.y| >= 0.9), e1 = normalize(h x a), e2 = a x e1.
export function domeBasis(s) {
  const a = [-s[0], -s[1], -s[2]];
  const h = Math.abs(a[1]) < 0.9 ? [0, 1, 0] : [1, 0, 0];
  const e1 = normalize(cross(h, a));
  const e2 = cross(a, e1);
  return { e1, e2 };
}

export function makeDomeGeometry(sunDir, rings, segments) {
  const s = sunDir;
  const a = [-s[0], -s[1], -s[2]];
  const { e1, e2 } = domeBasis(s);
  const n = (rings + 1) * (segments + 1);
  const direction = new Float32Array(3 * n);
  const theta = new Float32Array(n);
  let k = 0;
  for (let i = 0; i <= rings; i++) {
    const th = 180 - (90 * i) / rings;
    const alpha = ((180 - th) * Math.PI) / 180;
    for (let j = 0; j <= segments; j++) {
      const phi = (2 * Math.PI * j) / segments;
      const c = Math.cos(phi), sn = Math.sin(phi);
      for (let m = 0; m < 3; m++)
        direction[3 * k + m] = Math.cos(alpha) * a[m] + Math.sin(alpha) * (c * e1[m] + sn * e2[m]);
      theta[k] = th;
      k++;
    }
  }
  const index = [];
  const v = (i, j) => i * (segments + 1) + j;
  for (let i = 0; i < rings; i++)
    for (let j = 0; j < segments; j++) {
      index.push(v(i, j), v(i + 1, j), v(i + 1, j + 1));
      index.push(v(i, j), v(i + 1, j + 1), v(i, j + 1));
    }
  const g = new THREE.BufferGeometry();
  g.setAttribute('hx_direction', new THREE.BufferAttribute(direction, 3));
  g.setAttribute('hx_theta', new THREE.BufferAttribute(theta, 1));
  g.setIndex(index);
  g.boundingSphere = new THREE.Sphere(new THREE.Vector3(), 1);
  return g;
}
