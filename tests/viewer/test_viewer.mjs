// Real-browser test of `clustersurf view`: builds the bunny's tree and mesh, writes the viewer
// page, opens it from disk in headless chromium (playwright-core, SwiftShader WebGL) and checks
// that the canvas is not blank, that clicking tree rows changes the picture and that the info
// panel shows the clicked node's figures. Screenshots go to ARTIFACT_DIR.
//
// Usage: node test_viewer.mjs CLI DEFAULT_DATA_DIR ARTIFACT_DIR
// Exits 77 (skipped, saying why) when chromium, playwright-core or the bunny is missing.
import { execFileSync } from 'node:child_process';
import { existsSync, mkdirSync, writeFileSync } from 'node:fs';
import { join, resolve } from 'node:path';
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

// --- the browser ----------------------------------------------------------------------------
const browser = await launch(chromium, executablePath);
try {
  const tab = await browser.newPage({ viewport: { width: 1200, height: 800 } });
  const pageErrors = [];
  tab.on('pageerror', (error) => pageErrors.push(String(error)));
  tab.on('console', (message) => { if (message.type() === 'error') pageErrors.push(message.text()); });
  const t0 = Date.now();
  await tab.goto(pathToFileURL(page).href);
  await tab.waitForFunction(() => window.clustersurfViewer?.ready === true || window.clustersurfViewer?.error, null, { timeout: 60000 });
  const loadSeconds = (Date.now() - t0) / 1000;
  const state = await tab.evaluate(() => ({ error: window.clustersurfViewer.error, readyMs: window.clustersurfViewer.readyMs,
                                            nodes: window.clustersurfViewer.nodeCount }));
  check('page is ready without errors', !state.error && pageErrors.length === 0, state.error ?? pageErrors.join('; '));
  check('page holds the whole tree', state.nodes === info.nodes, `${state.nodes} nodes`);
  console.log(`     ready ${state.readyMs.toFixed(0)} ms after navigation (${loadSeconds.toFixed(2)} s with the launch overhead)`);

  const canvas = tab.locator('#cs-view canvas');
  const shoot = async (name) => {
    await tab.evaluate(() => new Promise((done) => requestAnimationFrame(() => requestAnimationFrame(done))));
    const png = await canvas.screenshot();
    writeFileSync(join(artifacts, name), png);
    return decodePng(png);
  };
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
  check('the root\'s children split the input', counts[0] > 0 && counts[1] > 0 && counts[0] + counts[1] === inputPoints,
        `${counts[0]} + ${counts[1]} vs ${inputPoints} input points`);

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
} finally {
  await browser.close();
}
console.log(failures === 0 ? 'viewer: all checks passed' : `viewer: ${failures} check(s) failed`);
process.exit(failures === 0 ? 0 : 1);
