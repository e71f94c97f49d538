// The web build's figures (docs/benchmarks.md, "Web build"), in one run on one machine:
// update cost per character native (the C API) and in headless Chromium, for 1 and 100
// characters, as a ratio; the wasm's size raw and gzipped; the example page's start-up to
// its first frame. Each figure is the median of RUNS alternating native and browser runs.
//   node tests/web/bench_web.mjs NATIVE_TRACE_PROGRAM PACKAGE_DIR SHARED_ASSETS_DIR NODE_MODULES [RUNS]
import { execFileSync } from 'node:child_process';
import { readFileSync } from 'node:fs';
import { createRequire } from 'node:module';
import { join } from 'node:path';
import { gzipSync } from 'node:zlib';
import { startServer } from '../../examples/web/serve.mjs';

const [nativeProgram, packageDir, assetsDir, nodeModules, runsArg] = process.argv.slice(2);
const runs = Number(runsArg || 3);
const require = createRequire(join(nodeModules, 'noop.js'));
const { chromium } = require('playwright-core');
const robot = join(assetsDir, 'characters', 'RobotExpressive.glb');
const median = (v) => [...v].sort((a, b) => a - b)[v.length >> 1];

const wasm = readFileSync(join(packageDir, 'marionette_wasm.wasm'));
const gz = gzipSync(wasm, { level: 9 }).length;
const server = await startServer({ packageDir, nodeModules, assets: assetsDir });
const browser = await chromium.launch({ executablePath: process.env.MARIONETTE_CHROMIUM || '/usr/bin/chromium', headless: true,
  args: ['--no-sandbox', '--disable-background-networking', '--disable-component-update', '--disable-sync', '--no-first-run',
    '--use-angle=swiftshader', '--enable-unsafe-swiftshader'] });
const results = { 1: { native: [], web: [] }, 100: { native: [], web: [] } };
const firstFrame = [];
try {
  for (let run = 0; run < runs; ++run) {
    const page = await browser.newPage({ viewport: { width: 960, height: 640 } });
    await page.goto(`${server.url}/examples/web/index.html?character=RobotExpressive.glb`);
    await page.waitForFunction(() => window.marionetteDemo && window.marionetteDemo.frames > 2, null, { timeout: 120000 });
    firstFrame.push(await page.evaluate(() => window.marionetteDemo.firstFrameMs));
    for (const n of [1, 100]) {
      const frames = n === 1 ? 6000 : 600;
      const native = JSON.parse(execFileSync(nativeProgram, ['--bench', String(n), String(frames), robot], { encoding: 'utf8' }));
      results[n].native.push(native.usPerCharacter);
      const web = await page.evaluate(async ([count, f]) => {
        const { benchUpdate } = await import('/tests/web/bench_runner.mjs');
        const bytes = new Uint8Array(await (await fetch('/assets/characters/RobotExpressive.glb')).arrayBuffer());
        return benchUpdate(window.marionetteDemo.marionette, bytes, 'RobotExpressive.glb', count, f);
      }, [n, frames]);
      results[n].web.push(web.usPerCharacter);
    }
    await page.close();
  }
} finally {
  await browser.close();
  await server.close();
}
console.log(`| characters | native µs/character | Chromium µs/character | ratio |`);
console.log(`|---|---|---|---|`);
for (const n of [1, 100]) {
  const ratios = results[n].web.map((w, i) => w / results[n].native[i]);
  console.log(`| ${n} | ${median(results[n].native).toFixed(3)} | ${median(results[n].web).toFixed(3)} | ${median(ratios).toFixed(2)} (runs: ${ratios.map((r) => r.toFixed(2)).join(', ')}) |`);
}
console.log(`wasm: ${wasm.length} bytes, ${gz} gzipped (-9); first frame of the example page: median ${median(firstFrame).toFixed(0)} ms (${firstFrame.map((v) => v.toFixed(0)).join(', ')})`);
