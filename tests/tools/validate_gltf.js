// Runs the Khronos glTF-Validator (npm package gltf-validator) on one .gltf file and prints its
// issue summary and messages as JSON. Exit status: 0 without errors or warnings, 1 with, 2 when
// the validator cannot run. NODE_PATH must hold the package (scripts/install-deps.sh installs it
// under .deps/npm/node_modules).
const fs = require('fs');
const path = require('path');
const validator = require('gltf-validator');

const file = process.argv[2];
validator
  .validateBytes(new Uint8Array(fs.readFileSync(file)), {uri: path.basename(file), maxIssues: 200})
  .then((report) => {
    console.log(JSON.stringify(report.issues, null, 1));
    process.exit(report.issues.numErrors + report.issues.numWarnings > 0 ? 1 : 0);
  })
  .catch((error) => {
    console.error(String(error));
    process.exit(2);
  });
