// Validate glTF/GLB files with the Khronos glTF validator; prints one JSON report per file.
// usage: node validate.mjs FILE...
import fs from 'node:fs';
import path from 'node:path';
import validator from 'gltf-validator';

const out = [];
for (const file of process.argv.slice(2)) {
  const bytes = new Uint8Array(fs.readFileSync(file));
  const report = await validator.validateBytes(bytes, {
    uri: path.basename(file),
    maxIssues: 200,
    externalResourceFunction: (uri) =>
      new Promise((resolve, reject) => {
        try {
          resolve(new Uint8Array(fs.readFileSync(path.join(path.dirname(file), decodeURIComponent(uri)))));
        } catch (e) {
          reject(e.toString());
        }
      }),
  });
  out.push({ file, numErrors: report.issues.numErrors, numWarnings: report.issues.numWarnings,
             messages: report.issues.messages.filter((m) => m.severity <= 1).slice(0, 50) });
}
console.log(JSON.stringify(out));
