// The linter of the page scripts (npm run check; .ci/run): ESLint's recommended rules for browser modules.
import js from "@eslint/js";
import globals from "globals";

export default [
  js.configs.recommended,
  {
    files: ["src/**/*.js"],
    languageOptions: { ecmaVersion: 2022, sourceType: "module", globals: { ...globals.browser } },
  },
  { files: ["src/swagger-init.js"], languageOptions: { sourceType: "script", globals: { SwaggerUIBundle: "readonly" } } },
  { files: ["scripts/**/*.mjs", "eslint.config.js"], languageOptions: { globals: { ...globals.node } } },
];
