#!/usr/bin/env node
// Runs the Khronos glTF-Validator (npm package gltf-validator) on each FILE
// (.gltf or .glb) and prints its findings. Exit 0 when no file has an error
// or a warning (infos and hints are printed, not counted), 1 otherwise, 2 when
// the validator is missing or a file cannot be read.
// The validator is looked up in $GLTF_VALIDATOR_DIR, else in
// build-tools/gltf-validator (scripts/install-gltf-validator.sh puts it there).
import fs from 'node:fs';
import path from 'node:path';
import { createRequire } from 'node:module';
import { fileURLToPath } from 'node:url';

const repo = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '..');
const prefix = path.resolve(process.env.GLTF_VALIDATOR_DIR || path.join(repo, 'build-tools', 'gltf-validator'));
const files = process.argv.slice(2);
if (files.length === 0) {
  console.error('usage: validate-gltf.mjs FILE.gltf|FILE.glb...');
  process.exit(2);
}

let validator;
try {
  validator = createRequire(path.join(prefix, 'package.json'))('gltf-validator');
} catch {
  console.error(`validate-gltf: gltf-validator not found under ${prefix} (run scripts/install-gltf-validator.sh)`);
  process.exit(2);
}

const severities = ['error', 'warning', 'info', 'hint'];

async function validate(file) {
  const bytes = new Uint8Array(fs.readFileSync(file));
  const report = await validator.validateBytes(bytes, {
    uri: path.basename(file),
    maxIssues: 0,
    writeTimestamp: false,
    externalResourceFunction: (uri) =>
      fs.promises.readFile(path.resolve(path.dirname(file), decodeURIComponent(uri))).then((b) => new Uint8Array(b)),
  });
  const i = report.issues;
  console.log(`${file}: ${i.numErrors} errors, ${i.numWarnings} warnings, ${i.numInfos} infos, ${i.numHints} hints ` +
              `(glTF-Validator ${report.validatorVersion})`);
  for (const m of i.messages) {
    console.log(`  ${severities[m.severity] ?? m.severity} ${m.code} ${m.pointer ?? ''}: ${m.message}`);
  }
  return i.numErrors + i.numWarnings === 0;
}

let ok = true;
for (const file of files) {
  try {
    ok = (await validate(file)) && ok;
  } catch (e) {
    console.error(`validate-gltf: ${file}: ${e}`);
    process.exit(2);
  }
}
process.exit(ok ? 0 : 1);
