// The text tables' check (npm run check; .ci/run): src/texts-de.js and src/texts-en.js have the same keys in the same
// order, each with the same {placeholders} and a text in both; every key the pages ask for by name (t("…") in
// src, data-i18n and data-i18n-label in the server's page templates, title.{page} for each page) is in them; and no other module of src
// writes a German text (a string with ä, ö, ü or ß, with a German word such as "und", "nicht", "Sie", or one of
// the German table's own texts).
import fs from "node:fs";
import path from "node:path";
import { fileURLToPath } from "node:url";
import ts from "typescript";
import { DE } from "../src/texts-de.js";
import { EN } from "../src/texts-en.js";

const web = path.dirname(path.dirname(fileURLToPath(import.meta.url)));
const src = path.join(web, "src");
const pages = path.join(web, "..", "server", "pages");
const TABLES = new Set(["texts-de.js", "texts-en.js"]);
const problems = [];

// -- the two tables ------------------------------------------------------------------------------------------
const placeholders = (text) => [...new Set([...text.matchAll(/\{(\w+)\}/g)].map((m) => m[1]))].sort().join(", ");
const de = Object.keys(DE);
const en = Object.keys(EN);
for (const key of de.filter((k) => !(k in EN))) problems.push(`texts-en.js lacks "${key}"`);
for (const key of en.filter((k) => !(k in DE))) problems.push(`texts-de.js lacks "${key}"`);
const shared = de.filter((k) => k in EN);
const order = en.filter((k) => k in DE);
const moved = shared.findIndex((k, i) => order[i] !== k);
if (moved >= 0) problems.push(`the tables' order differs from "${shared[moved]}" on (keep the same key on the same line)`);
for (const key of shared) {
  for (const [name, table] of [["texts-de.js", DE], ["texts-en.js", EN]]) {
    if (typeof table[key] !== "string" || !table[key].trim()) problems.push(`${name}: "${key}" has no text`);
  }
  if (placeholders(DE[key]) !== placeholders(EN[key])) {
    problems.push(`"${key}": placeholders {${placeholders(DE[key])}} in German, {${placeholders(EN[key])}} in English`);
  }
}

// -- the other modules ---------------------------------------------------------------------------------------
// the strings of a module: string literals and the literal parts of template strings, with their lines
function strings(file) {
  const text = fs.readFileSync(file, "utf8");
  const source = ts.createSourceFile(file, text, ts.ScriptTarget.ES2022, true);
  const found = [];
  const visit = (node) => {
    if (ts.isImportDeclaration(node) || ts.isExportDeclaration(node)) return;  // module paths
    if (ts.isStringLiteral(node) || ts.isNoSubstitutionTemplateLiteral(node) || ts.isTemplateHead(node)
      || ts.isTemplateMiddle(node) || ts.isTemplateTail(node)) {
      found.push({ line: source.getLineAndCharacterOfPosition(node.getStart()).line + 1, text: node.text, node });
    }
    ts.forEachChild(node, visit);
  };
  visit(source);
  return found;
}

const GERMAN_LETTERS = /[äöüÄÖÜß]/;
const GERMAN_WORDS = new RegExp(`(?<![\\w-])(?:${["und", "oder", "nicht", "kein", "keine", "der", "die", "das", "den",
  "dem", "des", "ein", "eine", "einen", "ist", "sind", "wird", "werden", "wurde", "mit", "von", "vom", "zum", "zur",
  "auf", "bei", "nach", "noch", "bitte", "Bitte", "Sie", "Ihr", "Ihre", "Ihren", "Ihres"].join("|")})(?![\\w-])`);
const germanTexts = new Set(shared.filter((k) => DE[k] !== EN[k] && DE[k].length > 1).map((k) => DE[k]));
const german = (text) => GERMAN_LETTERS.test(text) || GERMAN_WORDS.test(text) || germanTexts.has(text.trim());

const asked = new Map();  // key → where a page asks for it by name
for (const name of fs.readdirSync(src).filter((f) => f.endsWith(".js")).sort()) {
  for (const { line, text, node } of strings(path.join(src, name))) {
    const call = node.parent;
    if (ts.isStringLiteral(node) && ts.isCallExpression(call) && call.arguments[0] === node
      && call.expression.getText() === "t") {
      asked.set(text, `${name}:${line}`);
    } else if (!TABLES.has(name) && german(text)) {
      problems.push(`${name}:${line}: German text outside the tables (texts-de.js / texts-en.js): ${JSON.stringify(text)}`);
    }
  }
}
if (fs.existsSync(pages)) {
  for (const name of fs.readdirSync(pages).filter((f) => f.endsWith(".html")).sort()) {
    const html = fs.readFileSync(path.join(pages, name), "utf8");
    for (const m of html.matchAll(/data-i18n(?:-label)?="([^"$]+)"/g)) asked.set(m[1], `server/pages/${name}`);
    // the layout's <title data-i18n="$title_key">: title.{the page's name}
    if (html.includes("data-page") || name === "layout.html" || !html.includes("<main")) continue;
    asked.set(`title.${name.replace(/\.html$/, "")}`, `server/pages/${name} (its title)`);
  }
}
for (const [key, where] of asked) if (!(key in DE)) problems.push(`${where}: "${key}" is in no text table`);

if (problems.length) {
  console.error(`check-texts: ${problems.length} problem(s)\n  ${problems.join("\n  ")}`);
  process.exit(1);
}
console.log(`check-texts: ${shared.length} texts in German and English, ${asked.size} asked for by name`);
