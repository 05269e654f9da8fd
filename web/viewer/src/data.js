// Decodes the data the clustersurf CLI embeds in the page: a JSON description (#cs-meta) and
// base64 little-endian binary blobs (<script type="application/octet-stream" id="cs-blob-NAME">),
// straight into typed arrays (no per-point objects).

const ARRAY_TYPES = { f32: Float32Array, f64: Float64Array, i32: Int32Array, u32: Uint32Array, u8: Uint8Array };

function decodeBase64(text) {
  if (typeof Uint8Array.fromBase64 === 'function') return Uint8Array.fromBase64(text.trim());
  const binary = atob(text.trim());
  const bytes = new Uint8Array(binary.length);
  for (let i = 0; i < binary.length; ++i) bytes[i] = binary.charCodeAt(i);
  return bytes;
}

/// Reads #cs-meta and every blob it lists; returns { meta, blobs: { name: TypedArray } }.
export function loadData(doc) {
  const metaElement = doc.getElementById('cs-meta');
  if (!metaElement) throw new Error('this page holds no clustersurf data');
  const meta = JSON.parse(metaElement.textContent);
  const blobs = {};
  for (const [name, info] of Object.entries(meta.blobs)) {
    const element = doc.getElementById('cs-blob-' + name);
    if (!element) throw new Error('missing data block ' + name);
    const bytes = decodeBase64(element.textContent);
    const Type = ARRAY_TYPES[info.type];
    if (bytes.byteLength !== info.length * Type.BYTES_PER_ELEMENT)
      throw new Error(`data block ${name}: ${bytes.byteLength} bytes, expected ${info.length * Type.BYTES_PER_ELEMENT}`);
    blobs[name] = new Type(bytes.buffer, bytes.byteOffset, info.length);
    element.textContent = '';  // frees the text
  }
  return { meta, blobs };
}

/// The node table as struct-of-arrays, with derived fields: `end[i]` (one past the last node of
/// i's pre-order subtree, so a point whose leaf is in [i, end[i]) belongs to i's cluster).
export function nodeTable(meta, blobs) {
  const n = meta.nodes;
  const ints = blobs.node_int, floats = blobs.node_float;
  const parent = new Int32Array(n), left = new Int32Array(n), right = new Int32Array(n);
  const depth = new Int32Array(n), count = new Float64Array(n);
  for (let i = 0; i < n; ++i) {
    parent[i] = ints[5 * i]; left[i] = ints[5 * i + 1]; right[i] = ints[5 * i + 2];
    depth[i] = ints[5 * i + 3]; count[i] = ints[5 * i + 4] >>> 0;
  }
  const end = new Int32Array(n);
  for (let i = n - 1; i >= 0; --i) end[i] = left[i] < 0 ? i + 1 : end[right[i]];
  let maxDepth = 0;
  for (let i = 0; i < n; ++i) if (depth[i] > maxDepth) maxDepth = depth[i];
  return {
    n, parent, left, right, depth, count, end, maxDepth,
    kind: blobs.node_kind,
    rms: (i) => floats[6 * i], max: (i) => floats[6 * i + 1],
    sphere: (i) => [floats[6 * i + 2], floats[6 * i + 3], floats[6 * i + 4], floats[6 * i + 5]],
  };
}

export const PROXY_NAMES = ['point', 'plane', 'poly', 'quadric', 'crease'];
