// /docs: Swagger UI from our own copy of swagger-ui-dist (no CDN), started from this file rather than an
// inline script, so that the page keeps the site's Content-Security-Policy (script-src 'self').
window.ui = SwaggerUIBundle({
  url: "/openapi.json",
  dom_id: "#swagger-ui",
  layout: "BaseLayout",
  deepLinking: true,
  showExtensions: true,
  showCommonExtensions: true,
  presets: [SwaggerUIBundle.presets.apis, SwaggerUIBundle.SwaggerUIStandalonePreset],
  validatorUrl: null,  // no badge from validator.swagger.io: the page loads nothing from elsewhere
});
