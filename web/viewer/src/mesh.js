// The mesh layer: the mesh the CLI embedded (arrays, or a .glb file's bytes) or a .glb file the
// user opens or drops on the view. Every mesh gets the same material under the scene's lights.
// Page coordinates are the tree's: file coordinates minus the tree's origin (meta.origin) and
// minus the bbox center (meta.center, relative to that origin).

import * as THREE from 'three';
import { GLTFLoader } from 'three/examples/jsm/loaders/GLTFLoader.js';

/// The mesh material; `vertexColors` when the mesh carries per-vertex colors.
export function meshMaterial(vertexColors) {
  return new THREE.MeshStandardMaterial({
    color: vertexColors ? 0xffffff : 0xd8d8d8, vertexColors, roughness: 0.8, metalness: 0, side: THREE.DoubleSide,
    polygonOffset: true, polygonOffsetFactor: 1, polygonOffsetUnits: 1,
  });
}

/// Vertex and triangle counts of every mesh under `object`.
export function meshCounts(object) {
  let vertices = 0, triangles = 0;
  object.traverse((o) => {
    if (!o.isMesh) return;
    const n = o.geometry.attributes.position?.count ?? 0;
    vertices += n;
    triangles += Math.floor((o.geometry.index ? o.geometry.index.count : n) / 3);
  });
  return { vertices, triangles };
}

/// The embedded arrays (float32 positions already in page coordinates, uint32 triangles, and
/// uint8 RGB colors when the mesh has them).
export function arraysMesh(vertices, triangles, colors = undefined) {
  const g = new THREE.BufferGeometry();
  g.setAttribute('position', new THREE.BufferAttribute(vertices, 3));
  g.setIndex(new THREE.BufferAttribute(triangles, 1));
  if (colors) g.setAttribute('color', new THREE.BufferAttribute(colors, 3, true));
  g.computeVertexNormals();
  return new THREE.Mesh(g, meshMaterial(Boolean(colors)));
}

/// Parses a glTF binary (ArrayBuffer or Uint8Array) into an Object3D in page coordinates. The
/// root nodes are moved by -(origin + center): a node translated by the tree's origin (as the
/// clustersurf CLI writes it) gets exactly -center, with no float cancellation. With `zUp` (a
/// tree of a z-up survey), a root node turned from z-up to glTF's y-up as the CLI writes it is
/// turned back first, its translation exactly. Materials are replaced by meshMaterial() so that
/// every mesh looks the same.
export async function glbMesh(data, origin, center, zUp = false) {
  const buffer = data instanceof ArrayBuffer ? data : data.buffer.slice(data.byteOffset, data.byteOffset + data.byteLength);
  const magic = new Uint8Array(buffer, 0, Math.min(4, buffer.byteLength));
  if (String.fromCharCode(...magic) !== 'glTF') throw new Error('not a glTF binary (.glb) file');
  const gltf = await new GLTFLoader().parseAsync(buffer, '');
  const scene = gltf.scene;
  const o = new THREE.Vector3(...origin), c = new THREE.Vector3(...center);
  const toYUp = new THREE.Quaternion(-Math.SQRT1_2, 0, 0, Math.SQRT1_2);
  for (const child of scene.children) {
    if (zUp && child.quaternion.angleTo(toYUp) < 1e-6) {
      child.quaternion.identity();
      child.position.set(child.position.x, -child.position.z, child.position.y);  // (x, z, -y) back to (x, y, z)
    }
    child.position.sub(o).sub(c);
  }
  scene.traverse((node) => {
    if (!node.isMesh) return;
    const geometry = node.geometry;
    if (!geometry.attributes.normal) geometry.computeVertexNormals();
    const old = Array.isArray(node.material) ? node.material : [node.material];
    old.forEach((m) => m.dispose());
    node.material = meshMaterial(Boolean(geometry.attributes.color));
  });
  scene.updateMatrixWorld(true);
  return scene;
}

/// Frees the GPU resources of an object built by arraysMesh() or glbMesh().
export function disposeMesh(object) {
  object.traverse((o) => {
    if (!o.isMesh) return;
    o.geometry.dispose();
    (Array.isArray(o.material) ? o.material : [o.material]).forEach((m) => m.dispose());
  });
}
