// web.browser: the three.js example in headless Chromium (Debian's, driven by playwright-core),
// served from 127.0.0.1 (docs/web.md). Checks: the page loads with no console error; the
// character animates (pixels change inside its box on screen); BML feedback arrives; a
// malformed block shows its line:column error on the page; visemes reach a VRM's mouth morphs; the trace scenario played in the
// page matches the native C API within 1e-4. Writes a screenshot and figures to OUT_DIR.
//   node tests/web/browser_test.mjs NATIVE_TRACE_PROGRAM PACKAGE_DIR SHARED_ASSETS_DIR NODE_MODULES OUT_DIR
import { execFileSync } from 'node:child_process';
import { mkdirSync, readFileSync, writeFileSync } from 'node:fs';
import { createRequire } from 'node:module';
import { join } from 'node:path';
import { startServer } from '../../examples/web/serve.mjs';
import { compareTraces } from './trace_runner.mjs';

const [nativeProgram, packageDir, assetsDir, nodeModules, outDir] = process.argv.slice(2);
if (!outDir) {
  console.error('usage: node browser_test.mjs NATIVE_TRACE_PROGRAM PACKAGE_DIR SHARED_ASSETS_DIR NODE_MODULES OUT_DIR');
  process.exit(2);
}
mkdirSync(outDir, { recursive: true });
const require = createRequire(join(nodeModules, 'noop.js'));
const { chromium } = require('playwright-core');

const failures = [];
const check = (ok, what) => { console.log(`${ok ? 'ok  ' : 'FAIL'} ${what}`); if (!ok) failures.push(what); };

const server = await startServer({ packageDir, nodeModules, assets: assetsDir });
// As root in a container: no sandbox; no network beyond 127.0.0.1 (docs/web.md).
const browser = await chromium.launch({
  executablePath: process.env.MARIONETTE_CHROMIUM || '/usr/bin/chromium',
  headless: true,
  args: ['--no-sandbox', '--disable-background-networking', '--disable-component-update', '--disable-sync',
    '--no-first-run', '--disable-quic', '--use-angle=swiftshader', '--enable-unsafe-swiftshader'],
});
try {
  const page = await browser.newPage({ viewport: { width: 960, height: 640 } });
  const consoleErrors = [];
  page.on('console', (m) => { if (m.type() === 'error') consoleErrors.push(m.text()); });
  page.on('pageerror', (e) => consoleErrors.push(String(e)));
  const started = Date.now();
  await page.goto(`${server.url}/examples/web/index.html`);
  await page.waitForFunction(() => window.marionetteDemo && window.marionetteDemo.ready && window.marionetteDemo.frames > 5,
    null, { timeout: 120000 });
  const firstFrameMs = await page.evaluate(() => window.marionetteDemo.firstFrameMs);
  console.log(`page ready in ${Date.now() - started} ms; first frame ${firstFrameMs.toFixed(0)} ms after the module started loading`);

  // Feedback: a block sent through the page's BML box starts and ends.
  await page.evaluate(() => { document.getElementById('bml').value = '<bml id="check1" characterId="c"><head id="h" lexeme="NOD" repetition="2"/></bml>'; });
  await page.click('#send');
  await page.waitForFunction(() => window.marionetteDemo.feedback.some((f) => f.block === 'check1' && f.kind === 'blockProgress' && f.syncPoint === 'end'),
    null, { timeout: 60000 }).catch(() => {});
  const fb = await page.evaluate(() => window.marionetteDemo.feedback.filter((f) => f.block === 'check1').map((f) => `${f.kind}:${f.syncPoint}`));
  check(fb.includes('blockProgress:start') && fb.includes('blockProgress:end'), `BML feedback arrives (${fb.join(', ')})`);

  // The character animates: its box on screen changes between frames while it nods and looks.
  await page.evaluate(() => window.marionetteDemo.send('<bml id="move1" characterId="c"><gaze id="g" target="camera"/><head id="h" lexeme="SHAKE" repetition="3"/></bml>'));
  await page.waitForTimeout(300);
  const box = await page.evaluate(() => window.marionetteDemo.characterScreenBox());
  const clip = { x: Math.max(0, box.x - 10), y: Math.max(0, box.y - 10), width: Math.min(960, box.width + 20), height: Math.min(640, box.height + 20) };
  check(clip.width > 20 && clip.height > 50, `the character is on screen (${clip.width.toFixed(0)} x ${clip.height.toFixed(0)} px)`);
  const a = await page.screenshot({ clip });
  await page.waitForTimeout(400);
  const b = await page.screenshot({ clip });
  const changed = await page.evaluate(async ([x, y]) => {
    const load = async (b64) => { const img = new Image(); img.src = `data:image/png;base64,${b64}`; await img.decode(); return img; };
    const [p, q] = [await load(x), await load(y)];
    const c = document.createElement('canvas');
    c.width = p.width; c.height = p.height;
    const g = c.getContext('2d', { willReadFrequently: true });
    g.drawImage(p, 0, 0); const d1 = g.getImageData(0, 0, c.width, c.height).data;
    g.drawImage(q, 0, 0); const d2 = g.getImageData(0, 0, c.width, c.height).data;
    let n = 0;
    for (let i = 0; i < d1.length; i += 4) if (Math.abs(d1[i] - d2[i]) + Math.abs(d1[i + 1] - d2[i + 1]) + Math.abs(d1[i + 2] - d2[i + 2]) > 30) ++n;
    return n / (d1.length / 4);
  }, [a.toString('base64'), b.toString('base64')]);
  check(changed > 0.005, `the character animates: ${(100 * changed).toFixed(1)} % of its box changed in 0.4 s`);

  // A malformed block: its line:column error on the page, thrown as a MarionetteError.
  await page.evaluate(() => { document.getElementById('bml').value = '<bml id="bad" characterId="c">\n  <gaze id="g" target="camera">\n</bml>'; });
  await page.click('#send');
  const error = await page.textContent('#error');
  check(/\b3:\d+\b/.test(error) && /bad|malformed|mismatch/i.test(error), `a malformed block shows its line:column: "${error.trim()}"`);

  await page.screenshot({ path: join(outDir, 'web_example.png') });

  // Visemes reach three's morph targets: Godette (VRM) says the recorded line.
  const vrm = await browser.newPage({ viewport: { width: 960, height: 640 } });
  vrm.on('console', (m) => { if (m.type() === 'error') consoleErrors.push(m.text()); });
  vrm.on('pageerror', (e) => consoleErrors.push(String(e)));
  await vrm.goto(`${server.url}/examples/web/index.html?character=Godette_vrm_v4.vrm`);
  await vrm.waitForFunction(() => window.marionetteDemo && window.marionetteDemo.ready && window.marionetteDemo.frames > 5, null, { timeout: 120000 });
  await vrm.click('button[data-bml="speech"]');
  await vrm.waitForTimeout(2500);
  const mouth = await vrm.evaluate(() => ({ visemes: window.marionetteDemo.visemes.length, peaks: window.marionetteDemo.morphPeaks }));
  const mouthPeak = Math.max(...['ah', 'ih', 'uu', 'ee', 'oh'].map((m) => mouth.peaks[m] || 0));
  check(mouth.visemes > 10 && mouthPeak > 0.3,
    `visemes reach the VRM's mouth morphs: ${mouth.visemes} visemes, largest mouth weight ${mouthPeak.toFixed(2)}`);
  await vrm.screenshot({ path: join(outDir, 'web_example_vrm.png') });
  await vrm.close();

  // The trace scenario in the page against the native C API.
  const scenario = JSON.parse(readFileSync(new URL('./trace_scenario.json', import.meta.url), 'utf8'));
  const nativeOut = join(outDir, 'native_trace.bin');
  process.stdout.write(execFileSync(nativeProgram, [new URL('./trace_scenario.json', import.meta.url).pathname, assetsDir, nativeOut], { encoding: 'utf8' }));
  const bytes = readFileSync(nativeOut);
  const native = new Float32Array(bytes.buffer, bytes.byteOffset, bytes.byteLength / 4);
  const web = await page.evaluate(async (s) => {
    const { runTrace } = await import('/tests/web/trace_runner.mjs');
    const read = async (p) => new Uint8Array(await (await fetch(`/assets/${p}`)).arrayBuffer());
    const r = await runTrace(window.marionetteDemo.marionette, s, read);
    const u8 = new Uint8Array(r.matrices.buffer);
    let bin = '';
    for (let i = 0; i < u8.length; i += 0x8000) bin += String.fromCharCode(...u8.subarray(i, i + 0x8000));
    return { b64: btoa(bin), medianMicros: r.medianMicros };
  }, scenario);
  const webBytes = Buffer.from(web.b64, 'base64');
  const r = compareTraces(native, new Float32Array(webBytes.buffer, webBytes.byteOffset, webBytes.byteLength / 4));
  check(r.sameLength && r.maxAbs <= 1e-4, `page trace vs native: max |difference| ${r.maxAbs.toExponential(2)} (translation ${r.maxTranslation.toExponential(2)} m, axes ${r.maxAxis.toExponential(2)}; largest raw float difference ${r.maxRaw.toExponential(2)}) over ${scenario.frames} frames`);
  console.log(`page trace: median update ${web.medianMicros.toFixed(1)} us for ${scenario.characters.length} characters`);

  check(consoleErrors.length === 0, `no console error${consoleErrors.length ? ': ' + consoleErrors.join(' | ') : ''}`);
  writeFileSync(join(outDir, 'browser_figures.json'), JSON.stringify({ firstFrameMs, changed, trace: r, pageTraceMedianMicros: web.medianMicros }, null, 1));
} finally {
  await browser.close();
  await server.close();
}
if (failures.length) {
  console.error(`${failures.length} check(s) failed`);
  process.exit(1);
}
