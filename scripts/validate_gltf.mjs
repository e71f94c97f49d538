// Validates glTF / GLB files with the Khronos glTF-Validator (npm gltf-validator).
// Usage: node validate_gltf.mjs VALIDATOR_DIR FILE...
// Prints, per file, the counts and every message; exits 1 when any file has errors
// (or cannot be validated), 2 when the validator package is not installed.
import { readFile } from "node:fs/promises";
import { createRequire } from "node:module";
import path from "node:path";

const [validatorDir, ...files] = process.argv.slice(2);
let validator;
try {
  validator = createRequire(path.join(validatorDir, "package.json"))("gltf-validator");
} catch {
  console.error(`validate-gltf: the Khronos glTF-Validator is not installed in ${validatorDir}; run scripts/setup`);
  process.exit(2);
}

const severityName = ["error", "warning", "info", "hint"];
let failed = false;
for (const file of files) {
  let bytes;
  try {
    bytes = new Uint8Array(await readFile(file));
  } catch (e) {
    console.log(`${file}: cannot read: ${e.message}`);
    failed = true;
    continue;
  }
  const dir = path.dirname(path.resolve(file));
  let report;
  try {
    report = await validator.validateBytes(bytes, {
      uri: path.basename(file),
      maxIssues: 0,
      writeTimestamp: false,
      // Buffers and images beside a .gltf are checked too; a missing one is an error in the report.
      externalResourceFunction: (uri) => readFile(path.resolve(dir, decodeURIComponent(uri))).then((b) => new Uint8Array(b)),
    });
  } catch (e) {
    console.log(`${file}: the validator could not read the file: ${e}`);
    failed = true;
    continue;
  }
  const i = report.issues;
  console.log(`${file}: ${i.numErrors} errors, ${i.numWarnings} warnings, ${i.numInfos} infos, ${i.numHints} hints`);
  for (const m of i.messages)
    console.log(`  ${severityName[m.severity] ?? m.severity}: ${m.code} ${m.pointer ?? ""} ${m.message}`);
  if (i.numErrors > 0) failed = true;
}
process.exit(failed ? 1 : 0);
