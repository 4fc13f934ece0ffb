// Runs Khronos glTF-Validator (npm gltf-validator, installed by .ci/setup
// under /usr/local/lib/giharness-node) on each glTF/GLB path given, printing
// one JSON line per file:
//   {"file": ..., "errors": N, "warnings": N, "first_errors": [{"code", "pointer"}, ...]}
// A file the validator cannot even read counts as one error (code "UNREADABLE"),
// and so does one it crashes on (code "VALIDATOR_CRASH": 2.0.0-dev.3.10 throws
// asynchronously on e.g. "count": 1e400, outside the returned promise).
// Exit status: 0 when every file was reported on, 2 on bad usage, 3 when the
// validator package is missing (the message names .ci/setup).
// Used by tests/gltf_validator_test.cpp as the field's oracle.
import { createRequire } from 'node:module';
import fs from 'node:fs';
import path from 'node:path';

const modules = process.env.GIHARNESS_NODE_MODULES || '/usr/local/lib/giharness-node/node_modules';
const FIRST_ERRORS = 5;
const ERROR = 0;  // the validator's severity for errors (1 warning, 2 info, 3 hint)

function loadValidator() {
  try {
    return createRequire(path.join(modules, 'noop.js'))('gltf-validator');
  } catch (e) {
    console.error(`gltf_validate: gltf-validator not found under ${modules}; run .ci/setup as root (${e.message})`);
    process.exit(3);
  }
}

// Buffers and images referenced by relative URI, read next to the glTF file.
function resourceReader(file) {
  return (uri) => fs.promises.readFile(path.resolve(path.dirname(file), decodeURIComponent(uri)))
      .then((data) => new Uint8Array(data));
}

async function validate(validator, file) {
  try {
    const bytes = new Uint8Array(fs.readFileSync(file));
    const report = await validator.validateBytes(bytes, {
      uri: path.basename(file),
      maxIssues: 0,  // 0: no limit
      externalResourceFunction: resourceReader(file),
    });
    const errors = report.issues.messages.filter((m) => m.severity === ERROR);
    return {
      file,
      errors: report.issues.numErrors,
      warnings: report.issues.numWarnings,
      first_errors: errors.slice(0, FIRST_ERRORS).map((m) => ({ code: m.code, pointer: m.pointer ?? '' })),
    };
  } catch (e) {
    return { file, errors: 1, warnings: 0, first_errors: [{ code: 'UNREADABLE', pointer: '', message: String(e) }] };
  }
}

// The validator's asynchronous crashes escape its promise as uncaught
// exceptions; while one file is being validated, such a crash is its result.
function validateGuarded(validator, file) {
  return new Promise((resolve) => {
    const onCrash = (e) => resolve({
      file, errors: 1, warnings: 0, first_errors: [{ code: 'VALIDATOR_CRASH', pointer: '', message: String(e) }],
    });
    process.once('uncaughtException', onCrash);
    validate(validator, file).then((report) => {
      process.removeListener('uncaughtException', onCrash);
      resolve(report);
    });
  });
}

const files = process.argv.slice(2);
if (files.length === 0) {
  console.error('usage: node tests/gltf_validate.mjs FILE.gltf|FILE.glb ...');
  process.exit(2);
}
const validator = loadValidator();
for (const file of files) console.log(JSON.stringify(await validateGuarded(validator, file)));
