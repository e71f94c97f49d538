// The web trace's error table (docs/accuracy.md, "The web build against the native one"):
// mean and worst over every bone world matrix of trace_scenario.json, native against the package.
//   node tests/web/trace_error_table.mjs NATIVE_TRACE_PROGRAM PACKAGE_DIR SHARED_ASSETS_DIR
import { execFileSync } from 'node:child_process';
import { mkdtempSync, readFileSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { pathToFileURL } from 'node:url';
import { runTrace } from './trace_runner.mjs';

const [nativeProgram, packageDir, assetsDir] = process.argv.slice(2);
const scenarioPath = new URL('./trace_scenario.json', import.meta.url).pathname;
const scenario = JSON.parse(readFileSync(scenarioPath, 'utf8'));
const work = mkdtempSync(join(tmpdir(), 'marionette-trace-table-'));
try {
  execFileSync(nativeProgram, [scenarioPath, assetsDir, join(work, 'native.bin')]);
  const bytes = readFileSync(join(work, 'native.bin'));
  const a = new Float32Array(bytes.buffer, bytes.byteOffset, bytes.byteLength / 4);
  const { loadMarionette } = await import(pathToFileURL(join(packageDir, 'marionette.mjs')).href);
  const w = (await runTrace(await loadMarionette(), scenario, async (p) => new Uint8Array(readFileSync(join(assetsDir, p))))).matrices;
  let sumT = 0, sumA = 0, worstT = 0, worstA = 0, n = 0;
  for (let m = 0; m < a.length; m += 16) {
    const t = Math.hypot(a[m + 12] - w[m + 12], a[m + 13] - w[m + 13], a[m + 14] - w[m + 14]);
    let axis = 0;
    for (let c = 0; c < 3; ++c) {
      const o = m + c * 4;
      axis = Math.max(axis, Math.hypot(a[o] - w[o], a[o + 1] - w[o + 1], a[o + 2] - w[o + 2]) / Math.hypot(a[o], a[o + 1], a[o + 2]));
    }
    sumT += t; sumA += axis; worstT = Math.max(worstT, t); worstA = Math.max(worstA, axis); ++n;
  }
  console.log(`${n} bone world matrices (${scenario.frames} frames): joint position mean ${(sumT / n).toExponential(2)} m, ` +
    `worst ${worstT.toExponential(2)} m; axis columns mean ${(sumA / n).toExponential(2)}, worst ${worstA.toExponential(2)}`);
} finally {
  rmSync(work, { recursive: true, force: true });
}
