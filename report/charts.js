// Line charts as inline SVG, drawn from log.csv's columns in the page: no plotting library, nothing fetched.

const SVG_NS = "http://www.w3.org/2000/svg";
const SERIES_COLOURS = ["#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b"];

function svgElement(name, attributes, parent) {
  const e = document.createElementNS(SVG_NS, name);
  for (const [k, v] of Object.entries(attributes || {})) e.setAttribute(k, v);
  if (parent) parent.append(e);
  return e;
}

function formatNumber(v) {
  if (v === 0) return "0";
  const a = Math.abs(v);
  if (Number.isInteger(v) && a < 1e5) return String(v);  // steps and samples: counts read as counts
  // Short exponents ("1e5", "2.5e-4"): a tick's label stays inside its chart.
  if (a >= 1e4 || a < 1e-3) return v.toExponential(1).replace(".0e", "e").replace("e+", "e");
  return String(Number(v.toPrecision(3)));
}

// Ticks of a linear axis: about n round values across [lo, hi].
function linearTicks(lo, hi, n) {
  const step0 = (hi - lo) / n, mag = Math.pow(10, Math.floor(Math.log10(step0)));
  const step = [1, 2, 5, 10].map(m => m * mag).find(s => s >= step0) || step0;
  const ticks = [];
  for (let v = Math.ceil(lo / step) * step; v <= hi + step * 1e-9; v += step) ticks.push(Number(v.toPrecision(12)));
  return ticks;
}

// chart = {title, xLabel, yLabel, logX, logY, series: [{label, x: [], y: [], colour, markers, hollow, names, group,
// legend, legendColour}]}; points with a missing coordinate (null, NaN) or one <= 0 on a log axis are left out. Each series is one
// <g class="series" data-series=GROUP> (its group, else its label), so that a table row can pick out its curve
// (highlightSeries); `legend: false` leaves a series out of the legend (a run's paper point beside its curve).
// Returns the <svg>, or null when no point remains.
function lineChart(chart) {
  const W = 420, H = 280, L = 62, R = 12, T = 26, B = 40;
  const usable = (x, y) =>
    Number.isFinite(x) && Number.isFinite(y) && (!chart.logY || y > 0) && (!chart.logX || x > 0);
  const series = chart.series.map(s => {
    const pts = [];
    for (let i = 0; i < s.x.length; i++)
      if (usable(s.x[i], s.y[i])) pts.push([s.x[i], s.y[i], s.names ? s.names[i] : s.label]);
    return Object.assign({}, s, {pts});
  }).filter(s => s.pts.length > 0);
  if (series.length === 0) return null;
  const all = series.flatMap(s => s.pts);
  const fx = chart.logX ? Math.log10 : (v => v);
  let x0 = Math.min(...all.map(p => fx(p[0]))), x1 = Math.max(...all.map(p => fx(p[0])));
  if (chart.logX) { x0 = Math.floor(x0); x1 = Math.ceil(x1); }
  if (x1 === x0) { x0 -= 0.5; x1 += 0.5; }
  const fy = chart.logY ? Math.log10 : (v => v);
  let y0 = Math.min(...all.map(p => fy(p[1]))), y1 = Math.max(...all.map(p => fy(p[1])));
  if (chart.logY) { y0 = Math.floor(y0); y1 = Math.ceil(y1); }
  if (y1 === y0) { y0 -= 0.5; y1 += 0.5; }
  const sx = v => L + (fx(v) - x0) / (x1 - x0) * (W - L - R);
  const sy = v => T + (1 - (fy(v) - y0) / (y1 - y0)) * (H - T - B);

  const svg = svgElement("svg", {width: W, height: H, viewBox: `0 0 ${W} ${H}`, class: "chart"});
  svg.dataset.title = chart.title;
  svgElement("text", {x: W / 2, y: 16, "text-anchor": "middle", "font-weight": "bold"}, svg).textContent = chart.title;
  svgElement("text", {x: (L + W - R) / 2, y: H - 6, "text-anchor": "middle"}, svg).textContent = chart.xLabel;
  svgElement("text", {x: 14, y: (T + H - B) / 2, "text-anchor": "middle",
                      transform: `rotate(-90 14 ${(T + H - B) / 2})`}, svg).textContent = chart.yLabel;
  const xTicks = chart.logX ? Array.from({length: x1 - x0 + 1}, (_, i) => Math.pow(10, x0 + i))
                            : linearTicks(x0, x1, 5);
  for (const t of xTicks) {
    svgElement("line", {x1: sx(t), x2: sx(t), y1: T, y2: H - B, class: "gridline"}, svg);
    svgElement("text", {x: sx(t), y: H - B + 14, "text-anchor": "middle"}, svg).textContent = formatNumber(t);
  }
  const yTicks = chart.logY ? Array.from({length: y1 - y0 + 1}, (_, i) => Math.pow(10, y0 + i))
                            : linearTicks(y0, y1, 5);
  for (const t of yTicks) {
    svgElement("line", {x1: L, x2: W - R, y1: sy(t), y2: sy(t), class: "gridline"}, svg);
    svgElement("text", {x: L - 4, y: sy(t) + 4, "text-anchor": "end"}, svg).textContent = formatNumber(t);
  }
  svgElement("rect", {x: L, y: T, width: W - L - R, height: H - T - B, fill: "none", class: "axis"}, svg);
  let legendRow = 0;
  series.forEach((s, i) => {
    const colour = s.colour || SERIES_COLOURS[i % SERIES_COLOURS.length];
    const g = svgElement("g", {class: "series"}, svg);
    g.dataset.series = s.group || s.label;
    if (s.pts.length > 1)
      svgElement("polyline", {points: s.pts.map(p => `${sx(p[0]).toFixed(1)},${sy(p[1]).toFixed(1)}`).join(" "),
                              fill: "none", stroke: colour, "stroke-width": s.dashed ? 2.5 : 1.5,
                              "stroke-dasharray": s.dashed ? "6 4" : "none"}, g);
    // Points carry their values as a tooltip (hover), thinned to at most 200 a series to keep the page light.
    const every = Math.max(1, Math.ceil(s.pts.length / 200));
    s.pts.forEach((p, j) => {
      if (!s.markers && j % every && j !== s.pts.length - 1) return;
      const c = svgElement("circle", {cx: sx(p[0]), cy: sy(p[1]), r: s.markers || s.hollow ? 5 : 2,
                                      fill: s.hollow ? "none" : colour, stroke: colour,
                                      "stroke-width": s.hollow ? 2 : 0}, g);
      svgElement("title", {}, c).textContent = `${p[2]}: ${formatNumber(p[1])} at ${chart.xLabel} ${formatNumber(p[0])}`;
    });
    if (s.legend === false) return;
    const y = T + 6 + 14 * legendRow++, key = s.legendColour || colour;
    svgElement("rect", {x: W - R - 130, y, width: 10, height: 10, fill: s.hollow ? "none" : key, stroke: key}, svg);
    svgElement("text", {x: W - R - 116, y: y + 9}, svg).textContent = s.label;
  });
  return svg;
}

// Picks out one group's curves and points in every chart under `root` (the others dimmed); null shows them all.
function highlightSeries(root, group) {
  for (const g of root.querySelectorAll("g.series"))
    g.classList.toggle("dim", group !== null && g.dataset.series !== group);
}
