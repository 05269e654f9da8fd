// Proxy patches: each node's proxy drawn as a G×G height field over its cluster's extent in the
// node's frame. The CLI stores per node the frame (origin, e1, e2, e3), the [umin, umax] × [vmin,
// vmax] extent and the heights at the grid vertices (NaN where the proxy has no surface).

import * as THREE from 'three';

const FRAME_FLOATS = 16;

/// True when node i has a patch (point proxies and empty clusters have none).
export function hasPatch(frames, i) {
  return frames[FRAME_FLOATS * i + 13] > frames[FRAME_FLOATS * i + 12];
}

/// One BufferGeometry holding the patches of `indices`; `color(i)` gives [r, g, b] bytes.
export function patchGeometry(indices, frames, heights, grid, color) {
  const perPatch = grid * grid;
  const list = indices.filter((i) => hasPatch(frames, i));
  const positions = new Float32Array(3 * perPatch * list.length);
  const colors = new Uint8Array(3 * perPatch * list.length);
  const triangles = [];
  const valid = new Uint8Array(perPatch);
  list.forEach((node, k) => {
    const f = FRAME_FLOATS * node, base = k * perPatch;
    const [umin, umax, vmin, vmax] = [frames[f + 12], frames[f + 13], frames[f + 14], frames[f + 15]];
    const rgb = color(node);
    for (let a = 0; a < grid; ++a) {
      for (let b = 0; b < grid; ++b) {
        const g = a * grid + b;
        const u = umin + ((umax - umin) * a) / (grid - 1), v = vmin + ((vmax - vmin) * b) / (grid - 1);
        const h = heights[node * perPatch + g];
        valid[g] = Number.isFinite(h) ? 1 : 0;
        const w = valid[g] ? h : 0;
        for (let c = 0; c < 3; ++c)
          positions[3 * (base + g) + c] = frames[f + c] + u * frames[f + 3 + c] + v * frames[f + 6 + c] + w * frames[f + 9 + c];
        colors.set(rgb, 3 * (base + g));
      }
    }
    for (let a = 0; a + 1 < grid; ++a) {
      for (let b = 0; b + 1 < grid; ++b) {
        const g00 = a * grid + b, g10 = g00 + grid, g01 = g00 + 1, g11 = g10 + 1;
        if (valid[g00] && valid[g10] && valid[g11]) triangles.push(base + g00, base + g10, base + g11);
        if (valid[g00] && valid[g11] && valid[g01]) triangles.push(base + g00, base + g11, base + g01);
      }
    }
  });
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute('position', new THREE.BufferAttribute(positions, 3));
  geometry.setAttribute('color', new THREE.BufferAttribute(colors, 3, true));
  geometry.setIndex(new THREE.BufferAttribute(new Uint32Array(triangles), 1));
  geometry.computeVertexNormals();
  return geometry;
}
