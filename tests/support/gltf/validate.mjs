// tests/support/gltf/validate.mjs — the Khronos glTF-Validator (npm gltf-validator) over the files
// named, for tests/integration/gltf_validator.sh: prints one line per file (its counts of errors,
// warnings, infos and hints) and every error and warning with its pointer; exits 1 when any file
// has an error or a warning. Resources a file names (textures beside a .gltf or a GLB) are read
// from its folder. Run from the folder where scripts/install-deps.sh installed the package.
import { readFile } from "node:fs/promises";
import { dirname, resolve } from "node:path";
import { createRequire } from "node:module";

const require = createRequire(import.meta.url);
const validator = require("gltf-validator");

async function check(file) {
  const bytes = new Uint8Array(await readFile(file));
  const report = await validator.validateBytes(bytes, {
    uri: file,
    maxIssues: 100,
    externalResourceFunction: (uri) => readFile(resolve(dirname(file), decodeURIComponent(uri))),
  });
  const n = report.issues;
  console.log(
    `${file}: ${n.numErrors} errors, ${n.numWarnings} warnings, ${n.numInfos} infos, ${n.numHints} hints`,
  );
  for (const m of n.messages)
    if (m.severity <= 1)
      console.log(`  ${m.severity === 0 ? "error" : "warning"} ${m.code} at ${m.pointer ?? "-"}: ${m.message}`);
  return n.numErrors + n.numWarnings === 0;
}

let ok = true;
for (const file of process.argv.slice(2)) ok = (await check(file)) && ok;
process.exit(ok ? 0 : 1);
