// tests/support/k8s/check.mjs — reads Kubernetes manifests (multi-document YAML) for
// tests/integration/kubernetes.sh, as YAML 1.1 like the API server (0440 is octal). `validate FILE...` checks every object against the API's JSON
// schema for its apiVersion and kind (the kubernetes-models package) and refuses duplicate keys,
// unknown kinds and fields the schema does not know; `json FILE...` prints the objects as one
// JSON array. Run from the folder where scripts/install-deps.sh installed its packages.
import { readdirSync, readFileSync } from "node:fs";
import { dirname, join } from "node:path";
import { fileURLToPath } from "node:url";
import { parseAllDocuments } from "yaml";

function objects(file) {
  const docs = parseAllDocuments(readFileSync(file, "utf8"), { uniqueKeys: true, version: "1.1" });
  const out = [];
  for (const doc of docs) {
    if (doc.errors.length) throw new Error(`${file}: ${doc.errors[0].message}`);
    const obj = doc.toJS();
    if (obj !== null) out.push(obj);
  }
  return out;
}

async function model(obj) {
  const path = `kubernetes-models/${obj.apiVersion}/${obj.kind}`;
  try {
    return (await import(path))[obj.kind];
  } catch {
    throw new Error(`no schema for apiVersion ${obj.apiVersion} kind ${obj.kind}`);
  }
}

// Fields the schema does not declare: the API server drops or refuses them, so a typo in a probe
// or a securityContext would pass the schema check unnoticed. The field lists come from the
// package's type declarations (its compiled validators do not check for unknown fields).
function declarations(dir, types) {
  for (const entry of readdirSync(dir, { withFileTypes: true })) {
    const path = join(dir, entry.name);
    if (entry.isDirectory()) declarations(path, types);
    else if (entry.name.endsWith(".d.ts")) declared(readFileSync(path, "utf8"), types);
  }
  return types;
}

function declared(text, types) {
  const code = text.replace(/\/\*[\s\S]*?\*\//g, "");
  const local = {};
  for (const m of code.matchAll(/export interface (\w+)[^{]*\{/g)) {
    let depth = 1;
    let i = m.index + m[0].length;
    for (; depth > 0 && i < code.length; i++) depth += code[i] === "{" ? 1 : code[i] === "}" ? -1 : 0;
    const fields = {};
    const body = code.slice(m.index + m[0].length, i - 1);
    for (const f of body.matchAll(/^ {4}"([^"]+)"\??: ([^;\n]+)/gm)) fields[f[1]] = f[2];
    local[m[1]] = fields;
  }
  for (const m of code.matchAll(/export type \{ (\w+) as (\w+)/g))
    if (local[m[1]]) types[m[2]] = local[m[1]];
}

function unknownFields(value, type, types, where, found) {
  const array = /^Array<(\w+)>$/.exec(type);
  if (array && Array.isArray(value)) {
    value.forEach((v, i) => unknownFields(v, array[1], types, `${where}[${i}]`, found));
    return found;
  }
  const fields = types[type];
  if (!fields || value === null || typeof value !== "object" || Array.isArray(value)) return found;
  for (const [k, v] of Object.entries(value)) {
    if (!(k in fields)) found.push(`${where}.${k}`);
    else unknownFields(v, fields[k], types, `${where}.${k}`, found);
  }
  return found;
}

const here = dirname(fileURLToPath(import.meta.url));
let typeIndex = null;
function typeName(obj) {
  const [group, version] = obj.apiVersion.includes("/") ? obj.apiVersion.split("/") : ["core", obj.apiVersion];
  const g = group.split(".")[0];
  const cap = (s) => s.charAt(0).toUpperCase() + s.slice(1);
  return `IIoK8sApi${cap(g)}${cap(version)}${obj.kind}`;
}

async function validate(files) {
  let bad = 0;
  for (const file of files) {
    for (const obj of objects(file)) {
      const name = `${obj.kind}/${obj.metadata?.name}`;
      try {
        const Model = await model(obj);
        new Model(obj).validate();
        typeIndex ||= ["kubernetes-models", "@kubernetes-models/apimachinery"].reduce(
          (t, pkg) => declarations(join(here, "node_modules", pkg), t), {});
        if (!typeIndex[typeName(obj)]) throw new Error(`no field list for ${typeName(obj)}`);
        const extra = unknownFields(obj, typeName(obj), typeIndex, name, []);
        if (extra.length) throw new Error(`fields the API does not know: ${extra.join(", ")}`);
        console.log(`ok ${file} ${name}`);
      } catch (e) {
        console.log(`FAIL ${file} ${name}: ${e.message}`);
        bad++;
      }
    }
  }
  return bad === 0;
}

const [mode, ...files] = process.argv.slice(2);
try {
  if (mode === "validate") process.exitCode = (await validate(files)) ? 0 : 1;
  else if (mode === "json") console.log(JSON.stringify(files.flatMap(objects)));
  else {
    console.error("usage: node check.mjs validate|json FILE...");
    process.exitCode = 2;
  }
} catch (e) {
  console.error(`check.mjs: ${e.message.split("\n")[0]}`);
  process.exitCode = 1;
}
