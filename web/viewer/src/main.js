// The clustersurf viewer: input points colored by cluster at a tree level, the mesh, proxy
// patches and support spheres (three.js), next to the collapsible cluster tree. What it shows
// comes from the data the CLI embedded in the page (see data.js), plus any .glb mesh the user
// opens or drops on the view (mesh.js). Without points, the leaf proxies and their support
// spheres are shown by default. Rendering is on demand: a frame is drawn only when something
// changed.

import * as THREE from 'three';
import { OrbitControls } from 'three/examples/jsm/controls/OrbitControls.js';
import { loadData, nodeTable, PROXY_NAMES } from './data.js';
import { nodePalette } from './colors.js';
import { patchGeometry, hasPatch } from './patches.js';
import { TreePanel } from './tree_panel.js';
import { arraysMesh, disposeMesh, glbMesh, meshCounts } from './mesh.js';

const GREY = [205, 205, 205];
const HIGHLIGHT = 0xe02020;

function formatLength(x, diagonal) {
  return `${x.toPrecision(4)} (${((100 * x) / diagonal).toPrecision(3)} % of diagonal)`;
}

function start() {
  const timings = { start: performance.now() };
  const { meta, blobs } = loadData(document);
  timings.decoded = performance.now();
  const nodes = nodeTable(meta, blobs);
  const palette = nodePalette(nodes.n);
  const diagonal = meta.diagonal > 0 ? meta.diagonal : 1;
  document.title = `${meta.title} · clustersurf view`;
  document.getElementById('cs-title').textContent = meta.title;
  const origin = meta.origin ?? [0, 0, 0], center = meta.center ?? [0, 0, 0];
  const showSummary = (triangles) => {
    document.getElementById('cs-summary').textContent =
      `${nodes.n} nodes, ${meta.leaves} leaves, depth ${nodes.maxDepth}; ` +
      `${meta.points} of ${meta.input_points} points shown${triangles !== null ? `; mesh ${triangles} triangles` : ''}`;
  };
  showSummary(meta.mesh ? meta.mesh.triangles : null);

  // Default layers: the points when the page holds them, else the leaf proxies and their
  // support spheres (the index.html defaults are for points).
  if (meta.points === 0) {
    const pointBox = document.getElementById('cs-show-points');
    pointBox.checked = false;
    pointBox.disabled = true;
    document.getElementById('cs-point-size').disabled = true;
    document.getElementById('cs-show-proxies').checked = true;
    document.getElementById('cs-show-spheres').checked = true;
  }

  // --- renderer, camera, lights ------------------------------------------------------------
  const view = document.getElementById('cs-view');
  const renderer = new THREE.WebGLRenderer({ antialias: false, preserveDrawingBuffer: true });
  renderer.setPixelRatio(window.devicePixelRatio);
  renderer.setClearColor(0xffffff);
  view.prepend(renderer.domElement);
  const scene = new THREE.Scene();
  const camera = new THREE.PerspectiveCamera(35, 1, diagonal / 1000, diagonal * 20);
  const distance = diagonal / 2 / Math.sin(THREE.MathUtils.degToRad(35 / 2));
  // The render command's default view: azimuth 30 degrees from the front axis (+z when +y is up,
  // +x when +z is, as georeferenced surveys are) toward the side axis, 20 degrees up.
  const az = THREE.MathUtils.degToRad(30), el = THREE.MathUtils.degToRad(20);
  const zUp = meta.up === 'z';
  if (zUp) {
    camera.up.set(0, 0, 1);
    camera.position.set(Math.cos(az) * Math.cos(el), Math.sin(az) * Math.cos(el), Math.sin(el)).multiplyScalar(distance);
  } else {
    camera.position.set(Math.sin(az) * Math.cos(el), Math.sin(el), Math.cos(az) * Math.cos(el)).multiplyScalar(distance);
  }
  scene.add(camera);
  scene.add(new THREE.HemisphereLight(0xffffff, 0x606060, 1.6));
  const headlight = new THREE.DirectionalLight(0xffffff, 1.8);
  headlight.position.set(0.3, 0.5, 1);
  camera.add(headlight);
  const controls = new OrbitControls(camera, renderer.domElement);
  controls.enableDamping = false;

  // Large clouds: frames drawn while things change show a prefix of the points (the CLI stores
  // them so that every prefix is an even subsample); the full cloud follows once idle.
  const previewPoints = Math.min(meta.points, 100000);
  let frameRequested = false, idleTimer = 0, pointGeometry = null;
  const draw = (full) => {
    if (pointGeometry) pointGeometry.setDrawRange(0, full ? meta.points : previewPoints);
    renderer.render(scene, camera);
  };
  const requestRender = () => {
    if (frameRequested) return;
    frameRequested = true;
    requestAnimationFrame(() => {
      frameRequested = false;
      draw(previewPoints === meta.points);
      if (previewPoints < meta.points) {
        clearTimeout(idleTimer);
        idleTimer = setTimeout(() => draw(true), 300);
      }
    });
  };
  controls.addEventListener('change', requestRender);
  const resize = () => {
    const w = Math.max(1, view.clientWidth), h = Math.max(1, view.clientHeight);
    renderer.setSize(w, h);
    camera.aspect = w / h;
    camera.updateProjectionMatrix();
    requestRender();
  };
  new ResizeObserver(resize).observe(view);
  resize();

  // --- points --------------------------------------------------------------------------------
  const pointCount = meta.points;
  const leafOf = blobs.point_leaf;
  const pointColors = new Uint8Array(3 * pointCount);
  pointGeometry = new THREE.BufferGeometry();
  pointGeometry.setAttribute('position', new THREE.BufferAttribute(blobs.positions, 3));
  const colorAttribute = new THREE.BufferAttribute(pointColors, 3, true);
  pointGeometry.setAttribute('color', colorAttribute);
  const pointSize = pointCount < 200000 ? 4 : 2;  // pixels; sparse clouds get larger dots
  const pointMaterial = new THREE.PointsMaterial({ size: pointSize, sizeAttenuation: false, vertexColors: true });
  const points = new THREE.Points(pointGeometry, pointMaterial);
  points.frustumCulled = false;
  scene.add(points);

  // --- mesh ----------------------------------------------------------------------------------
  // One mesh at a time: the embedded one, replaced by any .glb the user opens.
  let mesh = null, meshInfo = null;
  const meshBox = document.getElementById('cs-show-mesh');
  const status = document.getElementById('cs-status');
  const setStatus = (text, error = false) => {
    status.textContent = text;
    status.classList.toggle('error', error);
  };
  const setMesh = (object, source) => {
    if (mesh) { scene.remove(mesh); disposeMesh(mesh); }
    mesh = object;
    const bounds = new THREE.Box3().setFromObject(object);
    meshInfo = { source, ...meshCounts(object), min: bounds.min.toArray(), max: bounds.max.toArray() };
    meshBox.disabled = false;
    mesh.visible = meshBox.checked;
    scene.add(mesh);
    showSummary(meshInfo.triangles);
    requestRender();
  };
  /// Parses a .glb (ArrayBuffer or Uint8Array) and shows it as the mesh; `source` names it.
  const loadGlb = async (data, source) => setMesh(await glbMesh(data, origin, center, meta.up === 'z'), source);
  if (meta.mesh && meta.mesh.format !== 'glb') setMesh(arraysMesh(blobs.mesh_vertices, blobs.mesh_triangles, blobs.mesh_colors), 'embedded');
  if (!meta.mesh) {
    meshBox.checked = false;
    meshBox.disabled = true;
  }

  // A .glb the user picks (file input) or drops on the view: shown as the mesh, checked on.
  const openFile = async (file) => {
    if (!file) return;
    setStatus(`loading ${file.name} …`);
    try {
      await loadGlb(await file.arrayBuffer(), file.name);
      meshBox.checked = true;
      mesh.visible = true;
      requestRender();
      setStatus(`${file.name}: ${meshInfo.vertices} vertices, ${meshInfo.triangles} triangles`);
    } catch (error) {
      setStatus(`${file.name}: ${error.message}`, true);
      console.warn(`clustersurf view: ${file.name}: ${error.message}`);
    }
  };
  const fileInput = document.getElementById('cs-open-mesh');
  fileInput.addEventListener('change', () => { openFile(fileInput.files[0]).finally(() => { fileInput.value = ''; }); });
  view.addEventListener('dragover', (event) => {
    if (!event.dataTransfer?.types.includes('Files')) return;
    event.preventDefault();
    event.dataTransfer.dropEffect = 'copy';
    view.classList.add('dropping');
  });
  view.addEventListener('dragleave', (event) => { if (event.target === view || !view.contains(event.relatedTarget)) view.classList.remove('dropping'); });
  view.addEventListener('drop', (event) => {
    view.classList.remove('dropping');
    if (!event.dataTransfer?.files.length) return;
    event.preventDefault();
    openFile(event.dataTransfer.files[0]);
  });

  // --- proxies and spheres -------------------------------------------------------------------
  const frames = blobs.patch_frame, heights = blobs.patch_height, grid = meta.patch_grid;
  const patchMaterial = new THREE.MeshLambertMaterial({ vertexColors: true, side: THREE.DoubleSide });
  let leafPatches = null;  // built on first use
  const selectedPatch = new THREE.Mesh(new THREE.BufferGeometry(),
    new THREE.MeshLambertMaterial({ color: HIGHLIGHT, side: THREE.DoubleSide, transparent: true, opacity: 0.5, depthWrite: false }));
  selectedPatch.frustumCulled = false;
  scene.add(selectedPatch);

  const sphereWire = new THREE.WireframeGeometry(new THREE.SphereGeometry(1, 20, 12));
  const selectedSphere = new THREE.LineSegments(sphereWire,
    new THREE.LineBasicMaterial({ color: HIGHLIGHT, transparent: true, opacity: 0.6 }));
  selectedSphere.visible = false;
  scene.add(selectedSphere);
  let cutSpheres = null;

  // --- state ---------------------------------------------------------------------------------
  let level = nodes.maxDepth;
  let selected = -1;
  const ancestor = new Int32Array(nodes.n);  // ancestor of each node at depth min(level, depth)

  const recolor = () => {
    for (let i = 0; i < nodes.n; ++i) ancestor[i] = nodes.depth[i] <= level ? i : ancestor[nodes.parent[i]];
    const lo = selected >= 0 ? selected : 0, hi = selected >= 0 ? nodes.end[selected] : nodes.n;
    for (let p = 0; p < pointCount; ++p) {
      const leaf = leafOf[p];
      const o = 3 * p;
      if (leaf >= lo && leaf < hi) {
        const c = 3 * ancestor[leaf];
        pointColors[o] = palette[c]; pointColors[o + 1] = palette[c + 1]; pointColors[o + 2] = palette[c + 2];
      } else {
        pointColors[o] = GREY[0]; pointColors[o + 1] = GREY[1]; pointColors[o + 2] = GREY[2];
      }
    }
    colorAttribute.needsUpdate = true;
  };

  const levelCut = () => {
    const cut = [];
    for (let i = 0; i < nodes.n; ++i) if (nodes.depth[i] === level || (nodes.left[i] < 0 && nodes.depth[i] < level)) cut.push(i);
    return cut;
  };

  const updateSpheres = () => {
    if (cutSpheres) { scene.remove(cutSpheres); cutSpheres.dispose(); cutSpheres = null; }
    if (!document.getElementById('cs-show-spheres').checked) return;
    const cut = levelCut();
    cutSpheres = new THREE.InstancedMesh(new THREE.SphereGeometry(1, 16, 10),
      new THREE.MeshBasicMaterial({ wireframe: true, transparent: true, opacity: 0.18, vertexColors: false }), cut.length);
    const m = new THREE.Matrix4(), color = new THREE.Color();
    cut.forEach((i, k) => {
      const [x, y, z, r] = nodes.sphere(i);
      m.makeScale(r, r, r).setPosition(x, y, z);
      cutSpheres.setMatrixAt(k, m);
      cutSpheres.setColorAt(k, color.setRGB(palette[3 * i] / 255, palette[3 * i + 1] / 255, palette[3 * i + 2] / 255, THREE.SRGBColorSpace));
    });
    cutSpheres.frustumCulled = false;
    scene.add(cutSpheres);
  };

  const info = document.getElementById('cs-info');
  const showInfo = (i) => {
    const rows = i < 0
      ? [['', 'no node selected', 'none']]
      : [
          ['node', `#${i}${nodes.left[i] < 0 ? ' (leaf)' : ''}`, 'node'],
          ['depth', String(nodes.depth[i]), 'depth'],
          ['points', String(nodes.count[i]), 'point_count'],
          ['proxy', PROXY_NAMES[nodes.kind[i]] ?? '?', 'proxy'],
          ['rms error', formatLength(nodes.rms(i), diagonal), 'rms_error'],
          ['max error', formatLength(nodes.max(i), diagonal), 'max_error'],
          ['support r', formatLength(nodes.sphere(i)[3], diagonal), 'support_radius'],
          ['parent', nodes.parent[i] >= 0 ? `#${nodes.parent[i]}` : '—', 'parent'],
        ];
    info.replaceChildren(...rows.flatMap(([label, value, field]) => {
      const dt = document.createElement('dt'), dd = document.createElement('dd');
      dt.textContent = label;
      dd.textContent = value;
      dd.dataset.field = field;
      return [dt, dd];
    }));
  };

  const panel = new TreePanel(document.getElementById('cs-tree'), nodes, (i) => selectNode(i === selected ? -1 : i));

  function selectNode(i) {
    selected = i >= 0 && i < nodes.n ? i : -1;
    panel.select(selected);
    showInfo(selected);
    selectedPatch.geometry.dispose();
    selectedPatch.geometry = selected >= 0 && hasPatch(frames, selected)
      ? patchGeometry([selected], frames, heights, grid, () => [255, 255, 255])
      : new THREE.BufferGeometry();
    if (selected >= 0) {
      const [x, y, z, r] = nodes.sphere(selected);
      selectedSphere.position.set(x, y, z);
      selectedSphere.scale.setScalar(r);
    }
    selectedSphere.visible = selected >= 0;
    recolor();
    requestRender();
  }

  function setLevel(l) {
    level = Math.max(0, Math.min(nodes.maxDepth, Math.round(l)));
    slider.value = String(level);
    document.getElementById('cs-level-value').textContent = String(level);
    recolor();
    updateSpheres();
    requestRender();
  }

  // --- controls ------------------------------------------------------------------------------
  const slider = document.getElementById('cs-level');
  slider.max = String(nodes.maxDepth);
  slider.addEventListener('input', () => setLevel(Number(slider.value)));
  const bindToggle = (id, apply) => {
    const box = document.getElementById(id);
    box.addEventListener('change', () => { apply(box.checked); requestRender(); });
    apply(box.checked);
  };
  bindToggle('cs-show-points', (on) => { points.visible = on; });
  bindToggle('cs-show-mesh', (on) => { if (mesh) mesh.visible = on; });
  bindToggle('cs-show-spheres', () => updateSpheres());
  bindToggle('cs-show-proxies', (on) => {
    if (on && !leafPatches) {
      const leaves = [];
      for (let i = 0; i < nodes.n; ++i) if (nodes.left[i] < 0) leaves.push(i);
      leafPatches = new THREE.Mesh(patchGeometry(leaves, frames, heights, grid, (i) => palette.subarray(3 * i, 3 * i + 3)), patchMaterial);
      leafPatches.frustumCulled = false;
      scene.add(leafPatches);
    }
    if (leafPatches) leafPatches.visible = on;
  });
  const sizeSlider = document.getElementById('cs-point-size');
  sizeSlider.value = String(pointSize);
  sizeSlider.addEventListener('input', () => { pointMaterial.size = Number(sizeSlider.value); requestRender(); });
  window.addEventListener('keydown', (event) => { if (event.key === 'Escape') selectNode(-1); });

  // A click (not a drag) on a point selects its cluster at the current level.
  const raycaster = new THREE.Raycaster();
  raycaster.params.Points.threshold = diagonal * 0.004;
  let downAt = null;
  renderer.domElement.addEventListener('pointerdown', (e) => { downAt = [e.clientX, e.clientY]; });
  renderer.domElement.addEventListener('pointerup', (e) => {
    if (!downAt || Math.hypot(e.clientX - downAt[0], e.clientY - downAt[1]) > 4 || !points.visible || pointCount === 0) return;
    const rect = renderer.domElement.getBoundingClientRect();
    raycaster.setFromCamera(new THREE.Vector2(((e.clientX - rect.left) / rect.width) * 2 - 1, -((e.clientY - rect.top) / rect.height) * 2 + 1), camera);
    const hit = raycaster.intersectObject(points)[0];
    if (hit && leafOf[hit.index] >= 0) selectNode(ancestor[leafOf[hit.index]]);
  });

  slider.value = String(level);
  document.getElementById('cs-level-value').textContent = String(level);
  showInfo(-1);
  timings.built = performance.now();
  recolor();
  timings.colored = performance.now();

  // --- test and scripting hook ---------------------------------------------------------------
  const hook = {
    ready: false,  // true once the first frame is drawn (a preview of large clouds)
    readyMs: 0,
    fullDetail: false,  // true once a frame with every point is drawn
    nodeCount: nodes.n,
    timings,  // performance.now() at the start, after decoding, building, coloring, the first and the first full frame
    selectNode,
    setLevel,
    /// Draws one frame and waits for it; returns the milliseconds it took (benchmarks).
    timeFrame: () => {
      const t = performance.now();
      draw(true);
      finish();
      return performance.now() - t;
    },
    selected: () => selected,
    /// Which layers are shown (the toggles' states, and whether each layer exists).
    layers: () => ({ points: points.visible && pointCount > 0, mesh: Boolean(mesh?.visible),
                     spheres: Boolean(cutSpheres?.visible), proxies: Boolean(leafPatches?.visible) }),
    /// The mesh shown: { source ('embedded' or the file's name), vertices, triangles, min, max (page frame) }, or null.
    mesh: () => meshInfo,
    /// Parses a .glb (ArrayBuffer / Uint8Array) and shows it as the mesh, like an opened file.
    loadGlb: (data, name = 'script') => loadGlb(data, name).then(() => meshInfo),
    origin, center,
    up: zUp ? 'z' : 'y',
    /// The camera's up vector and where it stands relative to the target (page frame).
    camera: () => ({ up: camera.up.toArray(), position: camera.position.toArray() }),
    node: (i) => ({ index: i, depth: nodes.depth[i], point_count: nodes.count[i], proxy: PROXY_NAMES[nodes.kind[i]],
                    rms_error: nodes.rms(i), max_error: nodes.max(i), parent: nodes.parent[i], left: nodes.left[i], right: nodes.right[i] }),
  };
  window.clustersurfViewer = hook;
  const finish = () => {  // waits for the frame drawn
    const gl = renderer.getContext();
    gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, new Uint8Array(4));
  };
  // The first frame follows the embedded .glb's parsing (asynchronous), if any.
  const meshReady = meta.mesh?.format === 'glb' ? loadGlb(blobs.mesh_glb, 'embedded') : Promise.resolve();
  meshReady.then(() => requestAnimationFrame(() => {
    draw(previewPoints === meta.points);
    finish();
    hook.readyMs = performance.now();
    timings.rendered = hook.readyMs;
    hook.ready = true;
    document.body.dataset.ready = 'true';
    setTimeout(() => {
      if (previewPoints < meta.points) {
        draw(true);
        finish();
      }
      timings.fullDetail = performance.now();
      hook.fullDetail = true;
    }, 0);
  }), (error) => fail(error, hook));
}

/// Shows a fatal error over the view and in the hook.
function fail(error, hook = {}) {
  const box = document.createElement('div');
  box.id = 'cs-error';
  box.textContent = `clustersurf view: ${error.message}`;
  document.getElementById('cs-view').appendChild(box);
  window.clustersurfViewer = Object.assign(hook, { ready: false, error: String(error.message) });
}

try {
  start();
} catch (error) {
  fail(error);
  throw error;
}
