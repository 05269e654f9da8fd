// Bundles the viewer (three.js + src/) with esbuild into one minified IIFE and inlines it into
// index.html, giving the page template the clustersurf CLI embeds: the CLI replaces the
// <!--CLUSTERSURF_DATA--> marker with the data blocks. Run by the CMake build:
//   node web/viewer/build.mjs OUTPUT.html
// The page is also checked in (web/viewer/dist/viewer.html), so that building the library needs
// no Node.js: scripts/bundle-viewer regenerates it, and the build tests that it is current.
import { build } from 'esbuild';
import { readFile, writeFile, mkdir } from 'node:fs/promises';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';

const here = dirname(fileURLToPath(import.meta.url));
const output = process.argv[2];
if (!output) {
  console.error('usage: node web/viewer/build.mjs OUTPUT.html');
  process.exit(2);
}

const result = await build({
  entryPoints: [join(here, 'src', 'main.js')],
  bundle: true,
  format: 'iife',
  minify: true,
  target: ['chrome100', 'firefox100', 'safari15'],
  legalComments: 'eof',  // three.js's licence notice stays with its code
  write: false,
  logLevel: 'warning',
  absWorkingDir: join(here, '..', '..'),
});
const script = result.outputFiles[0].text;
if (/<\/script/i.test(script)) throw new Error('the bundle contains "</script": it cannot be inlined');
const template = await readFile(join(here, 'index.html'), 'utf8');
for (const marker of ['<!--CLUSTERSURF_DATA-->', '<!--CLUSTERSURF_SCRIPT-->'])
  if (template.split(marker).length !== 2) throw new Error(`index.html must hold ${marker} exactly once`);
const page = template.replace('<!--CLUSTERSURF_SCRIPT-->', () => `<script>${script}</script>`);
await mkdir(dirname(output), { recursive: true });
await writeFile(output, page);
console.log(`viewer: ${output} (${(page.length / 1024).toFixed(0)} KiB, script ${(script.length / 1024).toFixed(0)} KiB)`);
