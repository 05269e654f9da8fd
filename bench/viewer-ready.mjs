// Opens a `clustersurf view` page in headless chromium (SwiftShader WebGL: no GPU) and prints,
// as JSON, the milliseconds from navigation to the first picture (readyMs), to the first frame
// with every point (fullDetailMs), and those spent decoding the data and building the scene.
//   node bench/viewer-ready.mjs PAGE.html
import { resolve } from 'node:path';
import { pathToFileURL } from 'node:url';
import { chromiumPath, launch, loadPlaywright } from '../tests/viewer/browser.mjs';

const page = process.argv[2];
if (!page) {
  console.error('usage: node bench/viewer-ready.mjs PAGE.html');
  process.exit(2);
}
const chromium = await loadPlaywright();
if (!chromium || !chromiumPath()) {
  console.error('needs playwright-core and chromium: run scripts/setup');
  process.exit(1);
}
const browser = await launch(chromium, chromiumPath());
try {
  const tab = await browser.newPage({ viewport: { width: 1200, height: 800 } });
  await tab.goto(pathToFileURL(resolve(page)).href, { timeout: 120000 });
  await tab.waitForFunction(() => window.clustersurfViewer?.fullDetail || window.clustersurfViewer?.error, null, { timeout: 300000 });
  const result = await tab.evaluate(() => {
    const v = window.clustersurfViewer;
    if (v.error) return { error: v.error };
    const t = v.timings;
    return { readyMs: v.readyMs, fullDetailMs: t.fullDetail, decodeBuildMs: t.built - t.start, timings: t };
  });
  console.log(JSON.stringify(result));
  if (result.error) process.exitCode = 1;
} finally {
  await browser.close();
}
