// Writes the Stanford bunny shipped by the npm package `bunny` (public domain) as an ASCII PLY
// mesh: vertices in the package's order, triangles with the package's winding (outward).
// Usage: node scripts/bunny-to-ply.mjs OUT.ply   (written atomically: temp file + rename)
import { createRequire } from "node:module";
import { writeFileSync, renameSync } from "node:fs";

const require = createRequire(import.meta.url);
const { positions, cells } = require("bunny");
const out = process.argv[2];
if (!out) {
  console.error("usage: node bunny-to-ply.mjs OUT.ply");
  process.exit(2);
}
const lines = [
  "ply",
  "format ascii 1.0",
  "comment Stanford bunny from the npm package bunny@1.0.1 (public domain)",
  `element vertex ${positions.length}`,
  "property float x",
  "property float y",
  "property float z",
  `element face ${cells.length}`,
  "property list uchar int vertex_indices",
  "end_header",
];
for (const [x, y, z] of positions) lines.push(`${x} ${y} ${z}`);
for (const c of cells) lines.push(`${c.length} ${c.join(" ")}`);
const tmp = `${out}.tmp${process.pid}`;
writeFileSync(tmp, lines.join("\n") + "\n");
renameSync(tmp, out);
