// What the pages share through window, and what the Swagger UI page gets from its own script (type check only).
interface Window {
  PalTrainer: Record<string, unknown>;  // index.js: the bundle's entry points for the pages
  editor: import("@codemirror/view").EditorView | undefined;  // page-practice.js: the practice page's editor
  ui: unknown;  // swagger-init.js: the Swagger UI instance
}
declare const SwaggerUIBundle: any;  // swagger-ui-bundle.js, loaded before swagger-init.js on /docs
