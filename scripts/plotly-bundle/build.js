// plotly.js's own esbuild configuration (its esbuild-config.js), with mechdyn's entry point
const path = require("path");
const esbuild = require("esbuild");
const { environmentPlugin } = require("esbuild-plugin-environment");
const { glsl } = require("esbuild-plugin-glsl");
const InlineCSSPlugin = require("esbuild-plugin-inline-css");
const version = require("plotly.js/package.json").version;
const out = path.join(__dirname, "..", "..", "src", "mechdyn", "dashboard", "static", "plotly-mechdyn.min.js");
esbuild.build({
  entryPoints: [path.join(__dirname, "entry.js")],
  outfile: out,
  format: "iife",
  globalName: "Plotly",
  bundle: true,
  minify: true,
  plugins: [InlineCSSPlugin(), glsl({ minify: true }), environmentPlugin({ NODE_DEBUG: false })],
  alias: { regl: "@plotly/regl", stream: "stream-browserify" },
  define: { global: "window", "define.amd": "false" },
  target: "es2016",
  legalComments: "none",
  banner: { js: `/* plotly.js v${version} (MIT licence, Copyright 2012-2026 Plotly, Inc.), the trace types mechdyn's dashboard draws: scatter, bar, scattergl, histogram2dcontour, parcoords. Built by scripts/build-plotly-bundle from scripts/plotly-bundle. */` },
}).then(() => console.log("wrote " + out));
