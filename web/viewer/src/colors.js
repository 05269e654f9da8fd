// Node colors: the same golden-ratio hue walk as clustersurf::node_color() (src/mesh/mesh_colors.cpp),
// so the viewer's clusters match the ray-traced pictures.

/// [r, g, b] in 0..255 for node `index`.
export function nodeColor(index) {
  const hue = ((index * 0.618033988749895) % 1.0) * 6.0;
  const s = index % 2 === 0 ? 0.65 : 0.45, v = index % 3 === 0 ? 0.95 : 0.8;
  const sector = Math.floor(hue), f = hue - sector;
  const p = v * (1 - s), q = v * (1 - s * f), t = v * (1 - s * (1 - f));
  let r, g, b;
  switch (sector % 6) {
    case 0: r = v; g = t; b = p; break;
    case 1: r = q; g = v; b = p; break;
    case 2: r = p; g = v; b = t; break;
    case 3: r = p; g = q; b = v; break;
    case 4: r = t; g = p; b = v; break;
    default: r = v; g = p; b = q; break;
  }
  return [Math.round(r * 255), Math.round(g * 255), Math.round(b * 255)];
}

/// Colors of nodes 0..n-1, packed RGB bytes.
export function nodePalette(n) {
  const palette = new Uint8Array(3 * n);
  for (let i = 0; i < n; ++i) palette.set(nodeColor(i), 3 * i);
  return palette;
}
