// The report page's start: reads the embedded data and builds the viewer, the metrics, the charts and the record.
// The images are inflated first (asynchronously); when everything is built, window.clrReport is set and
// <body data-ready> says so (what the browser test waits for).
const DATA = JSON.parse(document.getElementById("clr-data").textContent);
document.getElementById("title").textContent = DATA.title;

(async function main() {
await Promise.all(DATA.images.map(async img => { img.decoded = await decodeHalves(img.half_rgb); }));
const guideViews = DATA.guide ? await Promise.all(DATA.guide.views.map(async v =>
    Object.assign({}, v, {qv: (await decodeHalves(v.q)).values, tv: (await decodeHalves(v.target)).values}))) : [];

function formatValue(v) {
  if (v === null || v === undefined) return "—";
  if (Number.isInteger(v) && Math.abs(v) < 1e9) return String(v);  // steps, spp: counts read as counts
  return Number.isFinite(v) ? v.toPrecision(5) : String(v);
}

// Images.
let viewer = null;
if (DATA.images.length === 0) document.getElementById("images").hidden = true;
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
  if (DATA.log.columns.length === 0) {
    document.getElementById("convergence").hidden = true;
    return;
  }
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

// The guide (ISNR runs): the lobes and their target at the precomputed pixel nearest to a click.
(function guide() {
  if (!DATA.guide || !viewer) return;
  document.getElementById("guide").hidden = false;
  const g = DATA.guide, info = document.getElementById("guide-info"), maps = document.getElementById("guide-maps");
  const views = guideViews;
  function mapCanvas(values, lo, hi) {
    const c = document.createElement("canvas");
    c.width = g.width;
    c.height = g.height;
    c.style.width = 4 * g.width + "px";
    c.style.imageRendering = "pixelated";
    const ctx = c.getContext("2d"), data = ctx.createImageData(g.width, g.height);
    for (let i = 0; i < values.length; i++) {
      const v = values[i];
      // Below the scale's four decades: its lowest colour; zero (no light, no lobe): black.
      const col = v > 0 ? errorColour(Math.max(0, (Math.log10(v) - lo) / (hi - lo))) : [0, 0, 0];
      data.data.set([col[0], col[1], col[2], 255], 4 * i);
    }
    ctx.putImageData(data, 0, 0);
    return c;
  }
  function show(view) {
    let max = 0;
    for (const a of [view.qv, view.tv]) for (const v of a) if (v > max) max = v;
    const hi = Math.log10(max || 1), lo = hi - 4;
    maps.textContent = "";
    const figure = (values, caption) => {
      const f = document.createElement("figure");
      f.style.display = "inline-block";
      f.style.margin = "0 1em 0 0";
      const c = document.createElement("figcaption");
      c.textContent = caption;
      f.append(mapCanvas(values, lo, hi), c);
      return f;
    };
    maps.append(figure(view.qv, "q: the I-Module's 8 vMF lobes"), figure(view.tv, "target p (L_i from the N-Module)"));
    info.dataset.x = view.x;
    info.dataset.y = view.y;
    info.textContent = `pixel (${view.x}, ${view.y}): KL(p‖q) ${formatValue(view.kl)}; densities per steradian ` +
                       `${formatValue(Math.pow(10, lo))} … ${formatValue(max)}`;
  }
  for (const p of viewer.panels)
    p.canvas.addEventListener("click", ev => {
      const px = viewer.pixelAt(p.canvas, ev.offsetX, ev.offsetY);
      if (!px || !views.length) return;
      let best = views[0], d = Infinity;
      for (const v of views) {
        const dv = (v.x - px[0]) ** 2 + (v.y - px[1]) ** 2;
        if (dv < d) { d = dv; best = v; }
      }
      show(best);
    });
  if (views.length) show(views[Math.floor(views.length / 2)]);
  else info.textContent = "no precomputed pixel sees a surface the model learns";
})();

// A sweep: every configuration's error against time (and samples trained on), the path tracer's beside them, and
// the Pareto front over all of them — the lowest error reached by any configuration within each time.
(function sweep() {
  if (!DATA.sweep) return;
  document.getElementById("sweep").hidden = false;
  const rows = DATA.sweep.rows.filter(r => r.point !== "steps");
  const configurations = [...new Set(rows.map(r => r.configuration))];
  const root = document.getElementById("sweep-charts");
  for (const [metric, label] of [["mape", "MAPE"], ["relmse", "relMSE"]]) {
    for (const [xKey, xLabel] of [["seconds", "seconds (training or rendering)"], ["incident_samples", "samples trained on"]]) {
      const series = configurations.map(c => {
        const rs = rows.filter(r => r.configuration === c && r[xKey] > 0).sort((a, b) => a[xKey] - b[xKey]);
        return {label: c, x: rs.map(r => r[xKey]), y: rs.map(r => r[metric])};
      }).filter(s => s.x.length > 0);
      if (xKey === "seconds") {
        // The front: points sorted by time, kept where they beat every earlier point.
        const pts = rows.filter(r => r.seconds > 0 && r[metric] > 0).sort((a, b) => a.seconds - b.seconds);
        const front = [];
        for (const r of pts) if (!front.length || r[metric] < front[front.length - 1][metric]) front.push(r);
        series.push({label: "Pareto front", x: front.map(r => r.seconds), y: front.map(r => r[metric]),
                     colour: "#000", dashed: true, names: front.map(r => r.configuration)});
      }
      const svg = lineChart({title: label + " against " + xLabel, xLabel, yLabel: label, logY: true, series});
      if (svg) root.append(svg);
    }
  }
  const table = document.getElementById("sweep-table");
  const columns = ["configuration", "point", "budget_minutes", "steps", "seconds", "spp", "mape", "mse", "relmse",
                   "peak_device_mib", "image", "error_map"];
  const head = table.insertRow();
  for (const c of columns) head.insertCell().textContent = c.replace(/_/g, " ");
  for (const r of DATA.sweep.rows) {
    const row = table.insertRow();
    for (const c of columns) {
      const cell = row.insertCell();
      if (c === "image" || c === "error_map") {
        if (r[c]) {
          const img = document.createElement("img");
          img.src = r[c];
          img.height = 64;
          img.title = r.configuration;
          cell.append(img);
        }
      } else cell.textContent = typeof r[c] === "number" ? formatValue(r[c]) : (r[c] === null ? "—" : r[c]);
    }
  }
})();

// The paper tables: per scene, our runs' rows beside the paper's numbers as a table that sorts on a click of its
// header, every run's evaluations against steps, seconds and samples trained on, the path tracer's points beside
// them against seconds, and the paper's own points (hollow, in the run's colour) against steps — steps alone,
// since the paper's seconds are another machine's and its batch is not stated. Hovering a row picks out its run's
// curves and points in the scene's charts; hovering a curve picks out its row.
(function paper() {
  if (!DATA.paper) return;
  document.getElementById("paper").hidden = false;
  const root = document.getElementById("paper-scenes");
  if (DATA.paper.source) {
    const p = document.createElement("p");
    p.className = "hint";
    p.textContent = "The paper's numbers (the right-hand columns, the hollow points): " + DATA.paper.source;
    root.append(p);
  }
  const number = digits => v => (v === null || v === undefined ? "—" : Number(v).toPrecision(digits));
  const columns = [
    {key: "label", label: "run"}, {key: "table", label: "table"}, {key: "method", label: "method"},
    {key: "n", label: "N", title: "incident samples a point"}, {key: "batch", label: "batch"},
    {key: "step", label: "step", title: "the last evaluation's step"},
    {key: "samples_m", label: "samples seen (M)", format: number(4)},
    {key: "minutes", label: "time (min)", format: number(3), title: "training time on this machine"},
    {key: "memory_gib", label: "memory (GiB)", format: number(3), title: "peak device memory"},
    {key: "mape", label: "MAPE", format: number(4)}, {key: "mse", label: "MSE", format: number(3)},
    {key: "paper_step", label: "paper: step"},
    {key: "paper_minutes", label: "time (min)", title: "the paper's, on one RTX 4090"},
    {key: "paper_memory_gb", label: "memory (GB)"}, {key: "paper_mape", label: "MAPE", format: number(3)},
    {key: "paper_mse", label: "MSE", format: number(3)},
    {key: "mape_ratio", label: "MAPE ours / paper's", format: number(3)}];
  for (const scene of DATA.paper.scenes) {
    const section = document.createElement("div");
    section.className = "paper-scene";
    section.dataset.scene = scene.name;
    const h = document.createElement("h3");
    const paperScene = scene.record && scene.record.paper_scene;
    h.textContent = scene.name + (paperScene ? " (the paper's " + paperScene + ")" : " (not in the paper)");
    const colourOf = new Map(scene.runs.map((r, i) => [r.label, SERIES_COLOURS[i % SERIES_COLOURS.length]]));
    const rows = scene.runs.map(r => {
      const f = r.final || {}, p = (r.paper || []).find(q => q.source === "Table " + r.table) || {};
      const has = v => v !== null && v !== undefined;
      return {label: r.label, table: r.table ?? null, method: r.method ?? null, n: f.config_samples ?? null,
              batch: f.config_batch ?? null, step: f.step ?? null, samples_m: has(f.samples) ? f.samples / 1e6 : null,
              minutes: has(f.seconds) ? f.seconds / 60 : null,
              memory_gib: has(f.peak_device_mib) ? f.peak_device_mib / 1024 : null, mape: f.mape ?? null,
              mse: f.mse ?? null, paper_step: p.step ?? null, paper_minutes: p.minutes ?? null,
              paper_memory_gb: p.memory_gb ?? null, paper_mape: p.mape ?? null, paper_mse: p.mse ?? null,
              mape_ratio: has(f.mape) && p.mape ? f.mape / p.mape : null};
    });
    const table = sortableTable(columns, rows, {rowKey: r => r.label,
                                                onHover: r => highlightSeries(section, r ? r.label : null)});
    table.classList.add("paper-table");
    const charts = document.createElement("div");
    charts.className = "charts";
    section.append(h, table, charts);
    root.append(section);
    const nulls = a => (a || []).map(v => (v === null ? NaN : v));
    for (const [xKey, xLabel] of [["step", "step"], ["seconds", "seconds (training; path tracer: rendering)"],
                                  ["samples", "samples trained on"]]) {
      const series = scene.runs.filter(r => r.columns[xKey] && r.columns.mape)
                               .map(r => ({label: r.label, x: nulls(r.columns[xKey]), y: nulls(r.columns.mape),
                                           colour: colourOf.get(r.label)}));
      if (xKey === "step") {
        let first = true;
        for (const r of scene.runs.filter(r => r.paper && r.paper.length)) {
          series.push({label: "the paper", group: r.label, hollow: true, colour: colourOf.get(r.label),
                       legend: first, legendColour: "#777", x: r.paper.map(p => p.step), y: r.paper.map(p => p.mape),
                       names: r.paper.map(p => `the paper's ${p.source} (${r.label})`)});
          first = false;
        }
      }
      if (xKey === "seconds" && scene.path_tracer && scene.path_tracer.seconds)
        series.push({label: "path tracer", x: nulls(scene.path_tracer.seconds), y: nulls(scene.path_tracer.mape),
                     colour: "#000", dashed: true});
      // Steps and seconds on log axes: the paper's tens of thousands of steps beside runs of a few hundred, the
      // path tracer's fractions of a second beside minutes of training.
      const svg = lineChart({title: "MAPE against " + xKey, xLabel, yLabel: "MAPE", logY: true,
                             logX: xKey !== "samples", series});
      if (svg) charts.append(svg);
    }
    // A curve under the pointer picks out its row (and its run's other curves).
    charts.addEventListener("mouseover", ev => {
      const g = ev.target.closest && ev.target.closest("g.series");
      const label = g && colourOf.has(g.dataset.series) ? g.dataset.series : null;
      highlightSeries(section, label);
      for (const tr of table.tBodies[0].rows) tr.classList.toggle("hover", tr.dataset.key === label);
    });
    charts.addEventListener("mouseleave", () => {
      highlightSeries(section, null);
      for (const tr of table.tBodies[0].rows) tr.classList.remove("hover");
    });
  }
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
    if (typeof v === "string" && v.includes("\n")) {
      const pre = document.createElement("pre");
      pre.textContent = v;
      // Lines of prose (a preset's reasons) wrap; Markdown tables (tables.md) keep their rows and scroll.
      if (!/^\|/m.test(v)) pre.className = "wrap";
      cell.append(pre);
      cell.style.textAlign = "left";
    } else if (v !== null && typeof v === "object") {
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
document.body.dataset.ready = "1";
})().catch(e => {
  document.getElementById("title").textContent += " — the page could not be built: " + e;
  throw e;
});
