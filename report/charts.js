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
  return a >= 1e4 || a < 1e-3 ? v.toExponential(1) : String(Number(v.toPrecision(3)));
}

// Ticks of a linear axis: about n round values across [lo, hi].
function linearTicks(lo, hi, n) {
  const step0 = (hi - lo) / n, mag = Math.pow(10, Math.floor(Math.log10(step0)));
  const step = [1, 2, 5, 10].map(m => m * mag).find(s => s >= step0) || step0;
  const ticks = [];
  for (let v = Math.ceil(lo / step) * step; v <= hi + step * 1e-9; v += step) ticks.push(Number(v.toPrecision(12)));
  return ticks;
}

// chart = {title, xLabel, yLabel, logY, series: [{label, x: [], y: [], colour, markers}]}; points with a missing
// coordinate (null, NaN) or y <= 0 on a log axis are left out. Returns the <svg>, or null when no point remains.
function lineChart(chart) {
  const W = 420, H = 280, L = 62, R = 12, T = 26, B = 40;
  const usable = (x, y) => Number.isFinite(x) && Number.isFinite(y) && (!chart.logY || y > 0);
  const series = chart.series.map(s => {
    const pts = [];
    for (let i = 0; i < s.x.length; i++)
      if (usable(s.x[i], s.y[i])) pts.push([s.x[i], s.y[i], s.names ? s.names[i] : s.label]);
    return Object.assign({}, s, {pts});
  }).filter(s => s.pts.length > 0);
  if (series.length === 0) return null;
  const all = series.flatMap(s => s.pts);
  let x0 = Math.min(...all.map(p => p[0])), x1 = Math.max(...all.map(p => p[0]));
  if (x1 === x0) { x0 -= 0.5; x1 += 0.5; }
  const fy = chart.logY ? Math.log10 : (v => v);
  let y0 = Math.min(...all.map(p => fy(p[1]))), y1 = Math.max(...all.map(p => fy(p[1])));
  if (chart.logY) { y0 = Math.floor(y0); y1 = Math.ceil(y1); }
  if (y1 === y0) { y0 -= 0.5; y1 += 0.5; }
  const sx = v => L + (v - x0) / (x1 - x0) * (W - L - R);
  const sy = v => T + (1 - (fy(v) - y0) / (y1 - y0)) * (H - T - B);

  const svg = svgElement("svg", {width: W, height: H, viewBox: `0 0 ${W} ${H}`, class: "chart"});
  svg.dataset.title = chart.title;
  svgElement("text", {x: W / 2, y: 16, "text-anchor": "middle", "font-weight": "bold"}, svg).textContent = chart.title;
  svgElement("text", {x: (L + W - R) / 2, y: H - 6, "text-anchor": "middle"}, svg).textContent = chart.xLabel;
  svgElement("text", {x: 14, y: (T + H - B) / 2, "text-anchor": "middle",
                      transform: `rotate(-90 14 ${(T + H - B) / 2})`}, svg).textContent = chart.yLabel;
  for (const t of linearTicks(x0, x1, 5)) {
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
  series.forEach((s, i) => {
    const colour = s.colour || SERIES_COLOURS[i % SERIES_COLOURS.length];
    if (s.pts.length > 1)
      svgElement("polyline", {points: s.pts.map(p => `${sx(p[0]).toFixed(1)},${sy(p[1]).toFixed(1)}`).join(" "),
                              fill: "none", stroke: colour, "stroke-width": s.dashed ? 2.5 : 1.5,
                              "stroke-dasharray": s.dashed ? "6 4" : "none"}, svg);
    // Points carry their values as a tooltip (hover), thinned to at most 200 a series to keep the page light.
    const every = Math.max(1, Math.ceil(s.pts.length / 200));
    s.pts.forEach((p, j) => {
      if (!s.markers && j % every && j !== s.pts.length - 1) return;
      const c = svgElement("circle", {cx: sx(p[0]), cy: sy(p[1]), r: s.markers ? 5 : 2, fill: colour}, svg);
      svgElement("title", {}, c).textContent = `${p[2]}: ${formatNumber(p[1])} at ${chart.xLabel} ${formatNumber(p[0])}`;
    });
    svgElement("rect", {x: W - R - 130, y: T + 6 + 14 * i, width: 10, height: 10, fill: colour}, svg);
    svgElement("text", {x: W - R - 116, y: T + 15 + 14 * i}, svg).textContent = s.label;
  });
  return svg;
}
