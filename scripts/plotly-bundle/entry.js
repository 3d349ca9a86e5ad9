// The trace types mechdyn's dashboard draws (scatter comes with the core). Adding a view that needs
// another type means adding it here and running scripts/build-plotly-bundle.
var Plotly = require("plotly.js/lib/core");
Plotly.register([
  require("plotly.js/lib/bar"),
  require("plotly.js/lib/scattergl"),
  require("plotly.js/lib/histogram2dcontour"),
  require("plotly.js/lib/parcoords"),
]);
module.exports = Plotly;
