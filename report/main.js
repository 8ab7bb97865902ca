// The report page's start: reads the embedded data and builds the viewer, the metrics, the charts and the record.
const DATA = JSON.parse(document.getElementById("clr-data").textContent);
document.getElementById("title").textContent = DATA.title;

function formatValue(v) {
  return v === null || v === undefined ? "—" : Number.isFinite(v) ? v.toPrecision(5) : String(v);
}

// Images.
let viewer = null;
if (DATA.images.length > 0) {
  viewer = new Viewer(DATA.images, "reference", document.getElementById("panels"));
  const exposure = document.getElementById("exposure"), exposureValue = document.getElementById("exposure-value");
  const errorMax = document.getElementById("error-max"), errorMaxValue = document.getElementById("error-max-value");
  const modeButton = document.getElementById("mode");
  const showExposure = () => { exposureValue.textContent = viewer.exposure.toFixed(1); };
  exposure.addEventListener("input", () => { viewer.setExposure(Number(exposure.value)); showExposure(); });
  const showErrorMax = () => { errorMaxValue.textContent = formatValue(100 * viewer.errorMax) + " %"; drawColourBar(); };
  errorMax.addEventListener("input", () => { viewer.setErrorMax(Math.pow(10, Number(errorMax.value))); showErrorMax(); });
  const showMode = () => { modeButton.textContent = viewer.mode === "side" ? "side by side" : "flip: " + viewer.panels[viewer.flipIndex].title; };
  modeButton.addEventListener("click", () => { viewer.setMode(viewer.mode === "side" ? "flip" : "side"); showMode(); });
  document.getElementById("reset").addEventListener("click", () => { viewer.resetView(); viewer.draw(); });
  document.addEventListener("keydown", ev => {
    if (ev.target instanceof HTMLInputElement && ev.target.type !== "range") return;
    if (ev.key === "f" || ev.key === "F") {
      if (viewer.mode !== "flip") viewer.setMode("flip");
      viewer.flip(ev.key === "f" ? 1 : -1);
    } else if (ev.key === "m") viewer.setMode(viewer.mode === "side" ? "flip" : "side");
    else if (ev.key === "r") { viewer.resetView(); viewer.draw(); }
    else if (ev.key >= "1" && ev.key <= "9") { viewer.setMode("flip"); viewer.choose(Number(ev.key) - 1); }
    else return;
    showMode();
  });

  // The values under the cursor, in every image at once.
  const readout = document.getElementById("readout");
  viewer.listeners.push(() => {
    const px = viewer.cursor;
    if (!px) return;
    const values = viewer.valuesAt(px[0], px[1]);
    readout.dataset.x = px[0];
    readout.dataset.y = px[1];
    readout.dataset.values = JSON.stringify(values);
    readout.textContent = `pixel (${px[0]}, ${px[1]})\n` + viewer.panels.map(p => {
      const v = values[p.key];
      return p.title + ": " + (Array.isArray(v) ? v.map(formatValue).join("  ") : formatValue(100 * v) + " %");
    }).join("\n");
  });

  // The error maps' colour bar, from 0 to the scale chosen.
  function drawColourBar() {
    const bar = document.getElementById("colorbar");
    if (!viewer.panels.some(p => p.kind === "error")) return;
    bar.textContent = "";
    const c = document.createElement("canvas");
    c.width = 256;
    c.height = 12;
    const ctx = c.getContext("2d");
    for (let i = 0; i < 256; i++) {
      const col = errorColour(i / 255);
      ctx.fillStyle = `rgb(${col[0]},${col[1]},${col[2]})`;
      ctx.fillRect(i, 0, 1, 12);
    }
    const label = document.createElement("span");
    label.textContent = ` relative error |a − b| / (|b| + 0.01): 0 … ${formatValue(100 * viewer.errorMax)} % and above`;
    bar.append("0 ", c, label);
  }
  drawColourBar();

  // MAPE / MSE / relMSE of each image against the reference (computed by clradiosity on the float images).
  const table = document.getElementById("metrics");
  table.innerHTML = "<tr><th>image</th><th>MAPE</th><th>MSE</th><th>relMSE</th><th>mean ratio</th></tr>";
  for (const img of DATA.images) {
    if (!img.metrics) continue;
    const row = table.insertRow();
    row.dataset.key = img.key;
    [img.title, img.metrics.mape, img.metrics.mse, img.metrics.relmse, img.metrics.mean_ratio].forEach((v, i) => {
      row.insertCell().textContent = i === 0 ? v : formatValue(v);
    });
  }
}

// Convergence: log.csv's columns by name; the log may lack any but `step`.
(function charts() {
  const root = document.getElementById("charts");
  const col = name => {
    const i = DATA.log.columns.indexOf(name);
    return i < 0 ? null : DATA.log.values[i].map(v => (v === null ? NaN : v));
  };
  const step = col("step"), seconds = col("seconds"), samples = col("samples");
  const pt = DATA.path_tracer || [];
  const made = [];
  for (const [metric, label] of [["mape", "MAPE"], ["mse", "MSE"]]) {
    const y = col(metric);
    if (!y) continue;
    for (const [x, xLabel] of [[step, "step"], [seconds, "training seconds"], [samples, "samples trained on"]]) {
      if (!x) continue;
      const series = [{label: "model " + label, x, y}];
      // The path tracer at the training's seconds: a point beside the model's curve.
      if (xLabel === "training seconds" && pt.length)
        series.push({label: "path tracer", x: pt.map(p => p.seconds), y: pt.map(p => p.metrics[metric]),
                     markers: true, colour: "#d62728"});
      made.push(lineChart({title: label + " against " + xLabel, xLabel, yLabel: label, logY: true, series}));
    }
  }
  const loss = col("loss");
  if (loss && step) made.push(lineChart({title: "residual loss", xLabel: "step", yLabel: "loss", logY: true,
                                         series: [{label: "loss", x: step, y: loss}]}));
  for (const svg of made) if (svg) root.append(svg);
  if (!root.children.length) root.textContent = "log.csv holds no rows to plot.";
})();

// The record: what made the run and this report.
(function record() {
  const root = document.getElementById("record-body");
  const table = document.createElement("table");
  table.className = "record-table";
  for (const [k, v] of Object.entries(DATA.record)) {
    const row = table.insertRow();
    row.insertCell().textContent = k;
    const cell = row.insertCell();
    if (v !== null && typeof v === "object") {
      const pre = document.createElement("pre");
      pre.textContent = JSON.stringify(v, null, 2);
      cell.append(pre);
      cell.style.textAlign = "left";
    } else cell.textContent = String(v);
  }
  root.append(table);
})();

// For tests and the console: the viewer and the data.
window.clrReport = {viewer, data: DATA};
