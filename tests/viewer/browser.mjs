// Launching Debian's chromium headless through playwright-core, with software WebGL
// (SwiftShader) so the viewer renders on machines without a GPU.
import { existsSync } from 'node:fs';

/// The chromium binary: $CHROMIUM, else /usr/bin/chromium; null when absent.
export function chromiumPath() {
  const candidates = [process.env.CHROMIUM, '/usr/bin/chromium'].filter(Boolean);
  return candidates.find((p) => existsSync(p)) ?? null;
}

/// playwright-core's chromium launcher, or null when the npm package is not installed.
export async function loadPlaywright() {
  try {
    return (await import('playwright-core')).chromium;
  } catch {
    return null;
  }
}

export async function launch(chromium, executablePath) {
  return chromium.launch({
    executablePath,
    headless: true,
    args: ['--no-sandbox', '--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--ignore-gpu-blocklist'],
  });
}
