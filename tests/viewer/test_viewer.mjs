// Real-browser test of `clustersurf view`: builds the bunny's tree and mesh, writes the viewer
// page, opens it from disk in headless chromium (playwright-core, SwiftShader WebGL) and checks
// that the canvas is not blank, that clicking tree rows changes the picture and that the info
// panel shows the clicked node's figures. Then: a page without points shows the proxies and
// spheres; a .glb mesh written by the CLI is shown when embedded (`view --mesh M.glb`, for a
// cloud far from zero: the mesh must land on the tree), opened with the file input or dropped
// on the view; a z-up tree is viewed z-up, and a scan's colors show on its mesh. Screenshots go to
// ARTIFACT_DIR.
//
// Usage: node test_viewer.mjs CLI DEFAULT_DATA_DIR ARTIFACT_DIR
// Exits 77 (skipped, saying why) when chromium, playwright-core or the bunny is missing.
import { execFileSync } from 'node:child_process';
import { existsSync, mkdirSync, readFileSync, writeFileSync } from 'node:fs';
import { basename, join, resolve } from 'node:path';
import { pathToFileURL } from 'node:url';
import { chromiumPath, launch, loadPlaywright } from './browser.mjs';
import { decodePng, fractionChanged, fractionNot } from './png.mjs';

const [cli, dataDir, artifactArg] = process.argv.slice(2);
if (!cli || !dataDir || !artifactArg) {
  console.error('usage: node test_viewer.mjs CLI DEFAULT_DATA_DIR ARTIFACT_DIR');
  process.exit(2);
}
const skip = (why) => {
  console.log(`SKIP: ${why}`);
  process.exit(77);
};
const bunny = join(dataDir, 'bunny.ply');
if (!existsSync(bunny)) skip(`${bunny} is missing (run scripts/setup)`);
const executablePath = chromiumPath();
if (!executablePath) skip('chromium is not installed (run scripts/setup, or set CHROMIUM to its binary)');
const chromium = await loadPlaywright();
if (!chromium) skip('the npm package playwright-core is not installed (run scripts/setup)');

const artifacts = resolve(artifactArg);
mkdirSync(artifacts, { recursive: true });
let failures = 0;
const check = (name, ok, detail = '') => {
  console.log(`${ok ? 'ok  ' : 'FAIL'} - ${name}${detail ? ` (${detail})` : ''}`);
  if (!ok) ++failures;
};
const run = (...args) => execFileSync(cli, args, { encoding: 'utf8', stdio: ['ignore', 'pipe', 'pipe'] });

// --- the page -------------------------------------------------------------------------------
const tree = join(artifacts, 'bunny.cstree'), mesh = join(artifacts, 'bunny-mesh.ply'), page = join(artifacts, 'bunny.html');
run('--quiet', 'reconstruct', bunny, '-o', tree, '--mesh', mesh, '--resolution', '128');
const inputPoints = JSON.parse(run('--json', 'stats', bunny)).points;
const info = JSON.parse(run('--json', 'info', tree));
const written = JSON.parse(run('--json', 'view', tree, '-o', page, '--points', bunny, '--mesh', mesh));
check('view embeds every point', written.points === inputPoints, `${written.points} of ${inputPoints}`);
check('view embeds every node', written.nodes === info.nodes, `${written.nodes} vs info ${info.nodes}`);

// The GLB inputs: the bunny's mesh, and the same bunny moved far from zero (the CLI stores it
// relative to an origin, which becomes the GLB node's translation).
const glb = join(artifacts, 'bunny-mesh.glb');
const glbMesh = JSON.parse(run('--json', 'mesh', tree, '-o', glb, '--points', bunny, '--resolution', '128'));
const far = join(artifacts, 'bunny-far.xyz'), farTree = join(artifacts, 'bunny-far.cstree'), farGlb = join(artifacts, 'bunny-far.glb');
const shift = [1e6 + 0.25, -2e6, 5e5];
const plyLines = readFileSync(bunny, 'latin1').split('\n');
const vertexCount = Number(plyLines.find((l) => l.startsWith('element vertex')).split(/\s+/)[2]);
const firstVertex = plyLines.indexOf('end_header') + 1;
writeFileSync(far, plyLines.slice(firstVertex, firstVertex + vertexCount)
  .map((l) => l.trim().split(/\s+/).slice(0, 3).map((x, k) => (Number(x) + shift[k]).toFixed(6)).join(' ')).join('\n') + '\n');
run('--quiet', 'reconstruct', far, '-o', farTree, '--resolution', '128');
const farMesh = JSON.parse(run('--json', 'mesh', farTree, '-o', farGlb, '--points', far, '--resolution', '128'));
const farOrigin = JSON.parse(run('--json', 'stats', far)).origin;
const farInfo = JSON.parse(run('--json', 'info', farTree));
const glbJson = (file) => {  // the JSON chunk of a .glb
  const bytes = readFileSync(file);
  return JSON.parse(bytes.toString('utf8', 20, 20 + bytes.readUInt32LE(12)));
};
check('the far bunny has an origin, the GLB node its translation',
      farOrigin.some((x) => Math.abs(x) > 1000) && JSON.stringify(glbJson(farGlb).nodes[0].translation) === JSON.stringify(farOrigin),
      `origin ${farOrigin}, translation ${glbJson(farGlb).nodes[0].translation}`);
/// `view ARGS` (JSON stats), or null after recording the failure.
const view = (name, ...args) => {
  try {
    return JSON.parse(run('--json', 'view', ...args));
  } catch (error) {
    check(name, false, String(error.stderr || error.message).trim());
    return null;
  }
};
// A z-up survey: the far bunny as a PLY that says so ("comment up z", as the CLI writes meshes
// of LAS, E57 and PTX inputs). Its .glb is turned to glTF's +y up; the page looks at it z-up.
const zup = join(artifacts, 'bunny-zup.ply'), zupTree = join(artifacts, 'bunny-zup.cstree'), zupGlb = join(artifacts, 'bunny-zup.glb');
writeFileSync(zup, ['ply', 'format ascii 1.0', 'comment up z', `element vertex ${vertexCount}`, 'property double x',
                    'property double y', 'property double z', 'end_header',
                    ...readFileSync(far, 'latin1').trim().split('\n')].join('\n') + '\n');
run('--quiet', 'reconstruct', zup, '-o', zupTree, '--resolution', '128');
run('--quiet', 'mesh', zupTree, '-o', zupGlb, '--points', zup, '--resolution', '128');
const zupInfo = JSON.parse(run('--json', 'info', zupTree));
check('the z-up .glb is turned to +y up', JSON.stringify(glbJson(zupGlb).nodes[0].rotation) === JSON.stringify([-Math.SQRT1_2, 0, 0, Math.SQRT1_2]),
      JSON.stringify(glbJson(zupGlb).nodes[0]));
const noPointsPage = join(artifacts, 'bunny-nopoints.html'), farPage = join(artifacts, 'bunny-far-glb.html');
const zupPage = join(artifacts, 'bunny-zup.html');
// A scan with colors: the bunny's left half red, its right half blue; its mesh carries them.
const colored = join(artifacts, 'bunny-colored.ply'), coloredTree = join(artifacts, 'bunny-colored.cstree');
const coloredMesh = join(artifacts, 'bunny-colored-mesh.ply'), coloredPage = join(artifacts, 'bunny-colored.html');
const bunnyPoints = plyLines.slice(firstVertex, firstVertex + vertexCount).map((l) => l.trim().split(/\s+/).slice(0, 3));
writeFileSync(colored, ['ply', 'format ascii 1.0', `element vertex ${vertexCount}`, 'property float x', 'property float y',
                        'property float z', 'property uchar red', 'property uchar green', 'property uchar blue', 'end_header',
                        ...bunnyPoints.map((p) => `${p.join(' ')} ${Number(p[0]) < -0.02 ? '220 30 30' : '30 40 220'}`)].join('\n') + '\n');
run('--quiet', 'reconstruct', colored, '-o', coloredTree, '--mesh', coloredMesh, '--mesh-samples', '0');
const coloredWritten = view('view embeds a colored mesh', coloredTree, '-o', coloredPage, '--mesh', coloredMesh);
const zupWritten = view('view embeds a z-up .glb mesh', zupTree, '-o', zupPage, '--mesh', zupGlb);
view('view writes a page without points', tree, '-o', noPointsPage);
const farWritten = view('view embeds a .glb mesh', farTree, '-o', farPage, '--mesh', farGlb);
if (farWritten) check('view counts the .glb\'s triangles', farWritten.triangles === farMesh.triangles, `${farWritten.triangles} vs ${farMesh.triangles}`);

// --- the browser ----------------------------------------------------------------------------
/// Opens a page in a new tab and waits until it is ready; returns { tab, state, shoot, errors }.
const openViewer = async (file) => {
  const tab = await browser.newPage({ viewport: { width: 1200, height: 800 } });
  const errors = [];
  tab.on('pageerror', (error) => errors.push(String(error)));
  tab.on('console', (message) => { if (message.type() === 'error') errors.push(message.text()); });
  const t0 = Date.now();
  await tab.goto(pathToFileURL(file).href);
  await tab.waitForFunction(() => window.clustersurfViewer?.ready === true || window.clustersurfViewer?.error, null, { timeout: 60000 });
  const state = await tab.evaluate(() => ({ error: window.clustersurfViewer.error, readyMs: window.clustersurfViewer.readyMs,
                                            nodes: window.clustersurfViewer.nodeCount }));
  state.loadSeconds = (Date.now() - t0) / 1000;
  const canvas = tab.locator('#cs-view canvas');
  const shoot = async (name) => {
    await tab.evaluate(() => new Promise((done) => requestAnimationFrame(() => requestAnimationFrame(done))));
    const png = await canvas.screenshot();
    writeFileSync(join(artifacts, name), png);
    return decodePng(png);
  };
  return { tab, state, shoot, errors };
};
/// Mean brightness (0-255) of the pixels that are not the white background.
const meanShade = (image) => {
  let sum = 0, count = 0;
  for (let i = 0; i < image.width * image.height; ++i) {
    const [r, g, b] = [image.data[4 * i], image.data[4 * i + 1], image.data[4 * i + 2]];
    if (Math.max(255 - r, 255 - g, 255 - b) > 8) sum += (r + g + b) / 3, ++count;
  }
  return count ? sum / count : 0;
};
/// True when the mesh's box (page frame) is centered on the tree's bbox (centered at zero) and
/// about as large, within 10 % of the diagonal (the surface reaches a little past the points).
const onTree = (mesh, treeInfo) => {
  const slack = 0.1 * treeInfo.diagonal;
  return [0, 1, 2].every((k) => {
    const half = (treeInfo.bbox_max[k] - treeInfo.bbox_min[k]) / 2;
    return Math.abs(mesh.min[k] + mesh.max[k]) / 2 < slack && mesh.min[k] > -half - slack && mesh.max[k] < half + slack &&
           mesh.max[k] - mesh.min[k] > half;
  });
};
const guarded = async (name, body) => {
  try {
    await body();
  } catch (error) {
    check(name, false, String(error.message).split('\n')[0]);
  }
};

const browser = await launch(chromium, executablePath);
try {
  const { tab, state, shoot, errors: pageErrors } = await openViewer(page);
  check('page is ready without errors', !state.error && pageErrors.length === 0, state.error ?? pageErrors.join('; '));
  check('page holds the whole tree', state.nodes === info.nodes, `${state.nodes} nodes`);
  console.log(`     ready ${state.readyMs.toFixed(0)} ms after navigation (${state.loadSeconds.toFixed(2)} s with the launch overhead)`);
  const initial = await shoot('viewer-initial.png');
  const covered = fractionNot(initial, [255, 255, 255]);
  check('canvas is not blank', covered > 0.05, `${(100 * covered).toFixed(1)} % of pixels not background`);
  let distinct = new Set();
  for (let i = 0; i < initial.width * initial.height; i += 7) distinct.add(initial.data.readUInt32LE(4 * i) >>> 8);
  check('canvas shows many colors (clusters)', distinct.size > 50, `${distinct.size} distinct colors sampled`);

  // Expand the root, click its left child, then its right child.
  await tab.click('#cs-tree li[data-node="0"] > .row > .toggle');
  const root = await tab.evaluate(() => window.clustersurfViewer.node(0));
  const panelFigures = async () => ({
    node: await tab.textContent('#cs-info [data-field="node"]'),
    depth: Number(await tab.textContent('#cs-info [data-field="depth"]')),
    points: Number(await tab.textContent('#cs-info [data-field="point_count"]')),
    proxy: await tab.textContent('#cs-info [data-field="proxy"]'),
  });
  const counts = [];
  for (const [child, picture] of [[root.left, 'viewer-selected-left.png'], [root.right, 'viewer-selected-right.png']]) {
    await tab.click(`#cs-tree li[data-node="${child}"] > .row > .label`);
    await tab.waitForFunction((i) => window.clustersurfViewer.selected() === i, child);
    const shown = await panelFigures();
    const node = await tab.evaluate((i) => window.clustersurfViewer.node(i), child);
    const image = await shoot(picture);
    const changed = fractionChanged(initial, image);
    check(`selecting node ${child} changes the picture`, changed > 0.02, `${(100 * changed).toFixed(1)} % of pixels changed`);
    check(`panel shows node ${child}`, shown.node.startsWith(`#${child}`) && shown.depth === 1 && shown.points === node.point_count &&
          shown.proxy === node.proxy, JSON.stringify(shown));
    counts.push(shown.points);
  }
  // The root holds the input but its outliers (isolated points left out of every cluster).
  check('the root\'s children split the input', counts[0] > 0 && counts[1] > 0 && counts[0] + counts[1] === root.point_count &&
        root.point_count <= inputPoints && root.point_count >= 0.99 * inputPoints,
        `${counts[0]} + ${counts[1]} vs root ${root.point_count} of ${inputPoints} input points`);

  // The level slider recolors the points; the toggles hide them.
  await tab.keyboard.press('Escape');
  check('Escape clears the selection', (await tab.evaluate(() => window.clustersurfViewer.selected())) === -1);
  await tab.uncheck('#cs-show-mesh');
  const leaves = await shoot('viewer-points-leaves.png');
  await tab.locator('#cs-level').fill('1');
  const level1 = await shoot('viewer-points-level-1.png');
  const recolored = fractionChanged(leaves, level1);
  check('level 1 colors the points differently from the leaves', recolored > 0.005, `${(100 * recolored).toFixed(2)} % of pixels changed`);
  await tab.uncheck('#cs-show-points');
  await tab.check('#cs-show-proxies');
  const proxies = await shoot('viewer-proxies.png');
  check('proxy patches are drawn', fractionNot(proxies, [255, 255, 255]) > 0.05 && fractionChanged(level1, proxies) > 0.02);
  await tab.screenshot({ path: join(artifacts, 'viewer-page.png') });
  check('no page errors', pageErrors.length === 0, pageErrors.join('; '));
  await tab.close();

  // --- no points: the proxies and spheres by default; a .glb opened with the file input ------
  await guarded('page without points', async () => {
    const v = await openViewer(noPointsPage);
    check('page without points is ready without errors', !v.state.error && v.errors.length === 0, v.state.error ?? v.errors.join('; '));
    const layers = await v.tab.evaluate(() => window.clustersurfViewer.layers?.());
    check('without points, proxies and spheres are shown', layers?.proxies === true && layers?.spheres === true && layers?.points === false,
          JSON.stringify(layers));
    const image = await v.shoot('viewer-nopoints.png');
    const covered = fractionNot(image, [255, 255, 255]);
    check('page without points is not blank', covered > 0.05, `${(100 * covered).toFixed(1)} % of pixels not background`);

    await v.tab.uncheck('#cs-show-proxies');
    await v.tab.uncheck('#cs-show-spheres');
    await v.tab.setInputFiles('#cs-open-mesh', glb, { timeout: 5000 });
    await v.tab.waitForFunction((name) => window.clustersurfViewer.mesh?.()?.source === name, basename(glb), { timeout: 30000 });
    const mesh = await v.tab.evaluate(() => window.clustersurfViewer.mesh());
    check('an opened .glb has the mesh\'s vertices and triangles', mesh.vertices === glbMesh.vertices && mesh.triangles === glbMesh.triangles,
          `${mesh.vertices} vertices, ${mesh.triangles} triangles vs ${glbMesh.vertices}, ${glbMesh.triangles}`);
    check('an opened .glb lies on the tree', onTree(mesh, info), JSON.stringify([mesh.min, mesh.max]));
    const opened = await v.shoot('viewer-open-glb.png');
    const meshCovered = fractionNot(opened, [255, 255, 255]), shade = meanShade(opened);
    check('an opened .glb is drawn, lit', meshCovered > 0.05 && shade > 90,
          `${(100 * meshCovered).toFixed(1)} % of pixels, mean shade ${shade.toFixed(0)}`);
    check('no page errors (no points, opened .glb)', v.errors.length === 0, v.errors.join('; '));
    await v.tab.close();
  });

  // --- an embedded .glb of a cloud far from zero, then the same file dropped on the view -----
  if (farWritten) await guarded('page with an embedded .glb', async () => {
    const v = await openViewer(farPage);
    check('page with a .glb is ready without errors', !v.state.error && v.errors.length === 0, v.state.error ?? v.errors.join('; '));
    const shown = await v.tab.evaluate(() => ({ mesh: window.clustersurfViewer.mesh(), origin: window.clustersurfViewer.origin }));
    check('the page holds the tree\'s origin', JSON.stringify(shown.origin) === JSON.stringify(farOrigin), `${shown.origin}`);
    check('the embedded .glb has the mesh\'s vertices and triangles',
          shown.mesh?.vertices === farMesh.vertices && shown.mesh?.triangles === farMesh.triangles,
          `${shown.mesh?.vertices} vertices, ${shown.mesh?.triangles} triangles vs ${farMesh.vertices}, ${farMesh.triangles}`);
    check('the embedded .glb lies on the tree (node translation = origin)', shown.mesh && onTree(shown.mesh, farInfo),
          JSON.stringify([shown.mesh?.min, shown.mesh?.max]));
    await v.tab.uncheck('#cs-show-proxies');
    await v.tab.uncheck('#cs-show-spheres');
    const image = await v.shoot('viewer-embedded-glb.png');
    const covered = fractionNot(image, [255, 255, 255]), shade = meanShade(image);
    check('the embedded .glb is drawn, lit', covered > 0.05 && shade > 90,
          `${(100 * covered).toFixed(1)} % of pixels, mean shade ${shade.toFixed(0)}`);

    await v.tab.uncheck('#cs-show-mesh');
    const base64 = readFileSync(farGlb).toString('base64');
    await v.tab.evaluate(({ data, name }) => {
      const bytes = Uint8Array.from(atob(data), (c) => c.charCodeAt(0));
      const transfer = new DataTransfer();
      transfer.items.add(new File([bytes], name, { type: 'model/gltf-binary' }));
      const target = document.querySelector('#cs-view canvas');
      target.dispatchEvent(new DragEvent('dragover', { dataTransfer: transfer, bubbles: true, cancelable: true }));
      target.dispatchEvent(new DragEvent('drop', { dataTransfer: transfer, bubbles: true, cancelable: true }));
    }, { data: base64, name: 'dropped.glb' });
    await v.tab.waitForFunction(() => window.clustersurfViewer.mesh()?.source === 'dropped.glb', null, { timeout: 30000 });
    const dropped = await v.tab.evaluate(() => ({ mesh: window.clustersurfViewer.mesh(), layers: window.clustersurfViewer.layers() }));
    check('a dropped .glb replaces the mesh and is shown', dropped.mesh.vertices === farMesh.vertices && dropped.layers.mesh &&
          onTree(dropped.mesh, farInfo), JSON.stringify(dropped));
    const after = await v.shoot('viewer-dropped-glb.png');
    check('the dropped .glb draws the same picture', fractionChanged(image, after) < 0.01,
          `${(100 * fractionChanged(image, after)).toFixed(2)} % of pixels changed`);
    check('no page errors (embedded and dropped .glb)', v.errors.length === 0, v.errors.join('; '));
    await v.tab.close();
  });

  // --- a scan's colors on the embedded mesh: red and blue pixels both -------------------------
  if (coloredWritten) await guarded('page of a colored mesh', async () => {
    const v = await openViewer(coloredPage);
    check('colored-mesh page is ready without errors', !v.state.error && v.errors.length === 0, v.state.error ?? v.errors.join('; '));
    await v.tab.uncheck('#cs-show-proxies');
    await v.tab.uncheck('#cs-show-spheres');
    const image = await v.shoot('viewer-colored-mesh.png');
    let red = 0, blue = 0;
    for (let i = 0; i < image.width * image.height; ++i) {
      const [r, g, b] = [image.data[4 * i], image.data[4 * i + 1], image.data[4 * i + 2]];
      if (r > 2 * b && r > 2 * g && r > 60) ++red;
      if (b > 2 * r && b > 2 * g && b > 60) ++blue;
    }
    const n = image.width * image.height;
    check('the mesh is drawn in the scan\'s colors', red > 0.03 * n && blue > 0.03 * n,
          `${(100 * red / n).toFixed(1)} % red, ${(100 * blue / n).toFixed(1)} % blue pixels`);
    await v.tab.close();
  });

  // --- a z-up survey: the camera's up is +z, above the target; its .glb lands on the tree -----
  if (zupWritten) await guarded('page of a z-up tree', async () => {
    const v = await openViewer(zupPage);
    check('z-up page is ready without errors', !v.state.error && v.errors.length === 0, v.state.error ?? v.errors.join('; '));
    const shown = await v.tab.evaluate(() => ({ up: window.clustersurfViewer.up, camera: window.clustersurfViewer.camera(),
                                                mesh: window.clustersurfViewer.mesh() }));
    check('a z-up tree is viewed z-up, from above', shown.up === 'z' && shown.camera.up[2] === 1 && shown.camera.position[2] > 0,
          JSON.stringify(shown.camera));
    check('the z-up .glb lies on the tree', shown.mesh && onTree(shown.mesh, zupInfo), JSON.stringify([shown.mesh?.min, shown.mesh?.max]));
    await v.tab.uncheck('#cs-show-proxies');
    await v.tab.uncheck('#cs-show-spheres');
    const image = await v.shoot('viewer-zup-glb.png');
    check('the z-up .glb is drawn', fractionNot(image, [255, 255, 255]) > 0.05);
    await v.tab.close();
  });
} finally {
  await browser.close();
}
console.log(failures === 0 ? 'viewer: all checks passed' : `viewer: ${failures} check(s) failed`);
process.exit(failures === 0 ? 0 : 1);
