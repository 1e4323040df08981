// Collects the licences of the browser packages shipped in server/static: every package esbuild bundled into
// app.js (read from its metafile) and swagger-ui-dist (copied for /docs). Writes server/static/licenses.txt
// (each package's LICENSE text) and server/static/licenses.json (name, version, licence) for the "Über /
// Lizenzen" page. Run by `npm run build` after esbuild.
import { existsSync, readFileSync, writeFileSync } from "node:fs";
import { dirname, join } from "node:path";
import { fileURLToPath } from "node:url";

const web = join(dirname(fileURLToPath(import.meta.url)), "..");
const out = join(web, "..", "server", "static");
const meta = JSON.parse(readFileSync(join(web, "..", "build", "app-meta.json"), "utf8"));
const COPIED = ["swagger-ui-dist"];  // served from server/static/swagger, not bundled

const names = new Set(COPIED);
for (const input of Object.keys(meta.inputs)) {
  const m = input.match(/node_modules\/((?:@[^/]+\/)?[^/]+)\//);
  if (m) names.add(m[1]);
}

const LICENCE_FILES = ["LICENSE", "LICENSE.md", "LICENSE.txt", "LICENCE", "license", "license.md", "LICENSE-MIT"];
const packages = [...names].sort().map((name) => {
  const root = join(web, "node_modules", name);
  const pkg = JSON.parse(readFileSync(join(root, "package.json"), "utf8"));
  const file = LICENCE_FILES.map((f) => join(root, f)).find((f) => existsSync(f));
  if (!file) throw new Error(`${name}: no licence file`);
  let text = readFileSync(file, "utf8").trim();
  const notice = join(root, "NOTICE");
  if (existsSync(notice)) text += `\n\n${readFileSync(notice, "utf8").trim()}`;
  const license = typeof pkg.license === "string" ? pkg.license : pkg.license?.type || "siehe Text";
  return { name, version: pkg.version, license, homepage: pkg.homepage || "", bundled: !COPIED.includes(name), text };
});

const rule = "=".repeat(78);
writeFileSync(join(out, "licenses.txt"), "Licences of the browser packages shipped with PAL Trainer\n"
  + "(PAL Trainer itself: Apache License 2.0, see LICENSE)\n\n"
  + packages.map((p) => `${rule}\n${p.name} ${p.version} (${p.license})\n${rule}\n\n${p.text}\n`).join("\n"));
writeFileSync(join(out, "licenses.json"), `${JSON.stringify(packages.map((p) => ({ ...p, text: undefined })), null, 1)}\n`);
console.log(`licences: ${packages.length} packages`);
