// Validates glTF files with the Khronos glTF-Validator (npm gltf-validator,
// installed by scripts/install-test-tools.sh): prints each file's numbers of
// errors and warnings and its first messages, exits 1 if any file has an error.
// usage: node gltf-validate.js VALIDATOR_DIR FILE...
const path = require('path');
const fs = require('fs');
const validator = require(path.resolve(process.argv[2]));
(async () => {
  let failed = false;
  for (const file of process.argv.slice(3)) {
    const bytes = new Uint8Array(fs.readFileSync(file));
    const report = await validator.validateBytes(bytes, {
      uri: path.basename(file),
      externalResourceFunction: (uri) =>
        new Promise((resolve, reject) => {
          fs.readFile(path.join(path.dirname(file), decodeURIComponent(uri)), (err, data) =>
            err ? reject(err.toString()) : resolve(new Uint8Array(data)));
        }),
    });
    const i = report.issues;
    console.log(`${file}: ${i.numErrors} errors, ${i.numWarnings} warnings`);
    for (const m of i.messages.slice(0, 8)) console.log(`  ${m.severity} ${m.code} ${m.pointer || ''}: ${m.message}`);
    if (i.numErrors > 0) failed = true;
  }
  process.exit(failed ? 1 : 0);
})().catch((e) => { console.error(e); process.exit(2); });
