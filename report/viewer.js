// The image viewer of a clradiosity report: HDR images (half floats in the page) drawn into canvases at an exposure,
// side by side or flipped in place, zoom and pan shared by every canvas, the values under the cursor, and the
// per-pixel relative error |a − b| / (|b| + 0.01) that MAPE averages, in false colour.

// IEEE half (as OpenEXR stores it) to a JS number.
function halfToFloat(h) {
  const s = (h & 0x8000) ? -1 : 1;
  const e = (h >> 10) & 0x1f;
  const f = h & 0x3ff;
  if (e === 0) return s * f * Math.pow(2, -24);
  if (e === 31) return f ? NaN : s * Infinity;
  return s * (1 + f / 1024) * Math.pow(2, e - 15);
}

// The page's packed halves (host/report/half_image.hpp: zlib-compressed byte planes, high bytes then low, in
// base64) -> their bits and values (through a 65536-entry table: one lookup a value). Asynchronous: the browser's
// DecompressionStream inflates them.
const HALF_TABLE = (() => {
  const t = new Float32Array(65536);
  for (let i = 0; i < 65536; i++) t[i] = halfToFloat(i);
  return t;
})();
async function decodeHalves(text) {
  const bin = atob(text);
  const packed = new Uint8Array(bin.length);
  for (let i = 0; i < bin.length; i++) packed[i] = bin.charCodeAt(i);
  const stream = new Blob([packed]).stream().pipeThrough(new DecompressionStream("deflate"));
  const planes = new Uint8Array(await new Response(stream).arrayBuffer());
  const n = planes.length >> 1;
  const bits = new Uint16Array(n), values = new Float32Array(n);
  for (let i = 0; i < n; i++) {
    bits[i] = (planes[i] << 8) | planes[n + i];
    values[i] = HALF_TABLE[bits[i]];
  }
  return {bits, values};
}

// Linear to sRGB's transfer curve, as `render --png` tonemaps (clamped, no other operator).
function srgbByte(v) {
  if (!(v > 0)) return 0;
  if (v >= 1) return 255;
  const s = v <= 0.0031308 ? 12.92 * v : 1.055 * Math.pow(v, 1 / 2.4) - 0.055;
  return Math.round(s * 255);
}

// Error colours: a perceptual ramp (viridis' endpoints and midpoints), 0 -> dark blue, 1 -> yellow.
const ERROR_RAMP = [[68, 1, 84], [59, 82, 139], [33, 145, 140], [94, 201, 98], [253, 231, 37]];
function errorColour(t) {
  if (!(t >= 0)) return [255, 0, 255];  // NaN: magenta, never a colour of the ramp
  t = Math.min(t, 1) * (ERROR_RAMP.length - 1);
  const i = Math.min(Math.floor(t), ERROR_RAMP.length - 2);
  const f = t - i, a = ERROR_RAMP[i], b = ERROR_RAMP[i + 1];
  return [0, 1, 2].map(c => Math.round(a[c] + f * (b[c] - a[c])));
}
// The ramp in 1024 steps, so that a map of a large image costs a lookup a pixel.
const ERROR_LUT = (() => {
  const t = new Uint8Array(3 * 1025);
  for (let i = 0; i <= 1024; i++) t.set(errorColour(i / 1024), 3 * i);
  return t;
})();

// Per-pixel relative error, the channel mean of |a − b| / (|b| + 0.01): what MAPE averages.
function relativeError(a, ref) {
  const n = a.length / 3, out = new Float32Array(n);
  for (let p = 0; p < n; p++) {
    let e = 0;
    for (let c = 0; c < 3; c++) {
      const i = 3 * p + c;
      e += Math.abs(a[i] - ref[i]) / (Math.abs(ref[i]) + 0.01);
    }
    out[p] = e / 3;
  }
  return out;
}

class Viewer {
  // `images`: the page's images, each with `decoded` (decodeHalves' result).
  constructor(images, referenceKey, root) {
    this.width = images[0].width;
    this.height = images[0].height;
    this.exposure = 0;
    this.errorMax = 1;
    this.mode = "side";
    this.flipIndex = 0;
    this.listeners = [];
    this.panels = [];
    for (const img of images)
      this.panels.push(Object.assign({key: img.key, title: img.title, notes: img.notes, kind: "hdr"}, img.decoded));
    const ref = this.panels.find(p => p.key === referenceKey);
    if (ref)
      for (const p of this.panels.slice())
        if (p.kind === "hdr" && p !== ref)
          this.panels.push({key: p.key + "_error", title: "relative error of " + p.title, notes: {},
                            kind: "error", values: relativeError(p.values, ref.values)});
    // The base scale fits the longer side into about 400 CSS pixels (whole multiples for small images, so that
    // pixels stay square blocks).
    const side = Math.max(this.width, this.height);
    this.baseScale = side < 400 ? Math.max(1, Math.floor(400 / side)) : 400 / side;
    this.root = root;
    this.resetView();
    this.build();
  }

  resetView() {
    this.zoom = 1;
    this.cx = this.width / 2;
    this.cy = this.height / 2;
  }

  build() {
    this.root.textContent = "";
    for (const p of this.panels) {
      const div = document.createElement("div");
      div.className = "panel";
      div.dataset.key = p.key;
      const title = document.createElement("div");
      title.className = "title";
      title.textContent = p.title;
      const canvas = document.createElement("canvas");
      canvas.width = Math.round(this.width * this.baseScale);
      canvas.height = Math.round(this.height * this.baseScale);
      canvas.dataset.key = p.key;
      const notes = document.createElement("div");
      notes.className = "notes";
      notes.textContent = Object.entries(p.notes).map(([k, v]) => k + ": " + v).join(" · ");
      div.append(title, canvas, notes);
      this.root.append(div);
      p.div = div;
      p.canvas = canvas;
      p.offscreen = document.createElement("canvas");
      p.offscreen.width = this.width;
      p.offscreen.height = this.height;
      this.attach(canvas);
    }
    this.tonemapAll();
  }

  // Each panel's pixels at the current exposure (or error scale) into its full-resolution offscreen canvas.
  tonemap(p) {
    const ctx = p.offscreen.getContext("2d");
    const data = ctx.createImageData(this.width, this.height);
    const out = data.data, v = p.values, n = this.width * this.height;
    if (p.kind === "hdr") {
      // The values are halves: one table of the 65536 of them at this exposure, then a lookup a value.
      const lut = this.exposureTable(), b = p.bits;
      for (let i = 0; i < n; i++) {
        out[4 * i] = lut[b[3 * i]];
        out[4 * i + 1] = lut[b[3 * i + 1]];
        out[4 * i + 2] = lut[b[3 * i + 2]];
        out[4 * i + 3] = 255;
      }
    } else {
      const scale = 1024 / this.errorMax;
      for (let i = 0; i < n; i++) {
        const e = v[i];
        const j = e >= 0 ? 3 * Math.min(1024, Math.round(e * scale)) : -1;
        out[4 * i] = j < 0 ? 255 : ERROR_LUT[j];
        out[4 * i + 1] = j < 0 ? 0 : ERROR_LUT[j + 1];
        out[4 * i + 2] = j < 0 ? 255 : ERROR_LUT[j + 2];
        out[4 * i + 3] = 255;
      }
    }
    ctx.putImageData(data, 0, 0);
  }
  exposureTable() {
    if (this.lutExposure !== this.exposure) {
      const k = Math.pow(2, this.exposure);
      this.lut = new Uint8Array(65536);
      for (let h = 0; h < 65536; h++) this.lut[h] = srgbByte(HALF_TABLE[h] * k);
      this.lutExposure = this.exposure;
    }
    return this.lut;
  }
  tonemapAll() {
    for (const p of this.panels) this.tonemap(p);
    this.draw();
  }

  setExposure(e) {
    this.exposure = e;
    for (const p of this.panels) if (p.kind === "hdr") this.tonemap(p);
    this.draw();
  }
  setErrorMax(m) {
    this.errorMax = m;
    for (const p of this.panels) if (p.kind === "error") this.tonemap(p);
    this.draw();
  }

  visiblePanels() {
    return this.mode === "side" ? this.panels : [this.panels[this.flipIndex]];
  }
  setMode(mode) {
    this.mode = mode;
    this.draw();
  }
  flip(step) {
    this.flipIndex = (this.flipIndex + step + this.panels.length) % this.panels.length;
    this.draw();
  }
  choose(i) {
    if (i < 0 || i >= this.panels.length) return;
    this.flipIndex = i;
    this.draw();
  }

  // One transform for every canvas: the image point (cx, cy) at the canvas centre, `zoom` times the base scale.
  scale() {
    return this.baseScale * this.zoom;
  }
  draw() {
    const shown = new Set(this.visiblePanels());
    const s = this.scale();
    for (const p of this.panels) {
      p.div.classList.toggle("hidden", !shown.has(p));
      const ctx = p.canvas.getContext("2d");
      ctx.setTransform(1, 0, 0, 1, 0, 0);
      ctx.clearRect(0, 0, p.canvas.width, p.canvas.height);
      ctx.imageSmoothingEnabled = false;
      ctx.setTransform(s, 0, 0, s, p.canvas.width / 2 - this.cx * s, p.canvas.height / 2 - this.cy * s);
      ctx.drawImage(p.offscreen, 0, 0);
    }
    for (const f of this.listeners) f();
  }

  // The image pixel under a canvas position (CSS pixels from the canvas's corner), or null outside the image.
  pixelAt(canvas, x, y) {
    const r = canvas.getBoundingClientRect();
    const px = x * canvas.width / r.width, py = y * canvas.height / r.height;
    const s = this.scale();
    const ix = Math.floor((px - canvas.width / 2) / s + this.cx), iy = Math.floor((py - canvas.height / 2) / s + this.cy);
    return ix >= 0 && iy >= 0 && ix < this.width && iy < this.height ? [ix, iy] : null;
  }
  // Every panel's values at pixel (x, y): RGB for images, the relative error for error maps.
  valuesAt(x, y) {
    const i = y * this.width + x, out = {};
    for (const p of this.panels)
      out[p.key] = p.kind === "hdr" ? [p.values[3 * i], p.values[3 * i + 1], p.values[3 * i + 2]] : p.values[i];
    return out;
  }

  attach(canvas) {
    let drag = null;
    canvas.addEventListener("mousemove", ev => {
      if (drag) {
        const s = this.scale() * canvas.getBoundingClientRect().width / canvas.width;
        this.cx = drag.cx - (ev.clientX - drag.x) / s;
        this.cy = drag.cy - (ev.clientY - drag.y) / s;
        this.draw();
      }
      const px = this.pixelAt(canvas, ev.offsetX, ev.offsetY);
      this.onPixel(px);
    });
    canvas.addEventListener("mousedown", ev => {
      drag = {x: ev.clientX, y: ev.clientY, cx: this.cx, cy: this.cy};
      ev.preventDefault();
    });
    window.addEventListener("mouseup", () => { drag = null; });
    canvas.addEventListener("dblclick", () => { this.resetView(); this.draw(); });
    canvas.addEventListener("wheel", ev => {
      ev.preventDefault();
      // Zoom about the cursor: the image point under it stays under it.
      const before = this.pointAt(canvas, ev.offsetX, ev.offsetY);
      this.zoom = Math.min(256, Math.max(0.25, this.zoom * Math.pow(1.25, ev.deltaY < 0 ? 1 : -1)));
      const after = this.pointAt(canvas, ev.offsetX, ev.offsetY);
      this.cx += before[0] - after[0];
      this.cy += before[1] - after[1];
      this.draw();
    }, {passive: false});
  }
  pointAt(canvas, x, y) {
    const r = canvas.getBoundingClientRect();
    const s = this.scale();
    return [(x * canvas.width / r.width - canvas.width / 2) / s + this.cx,
            (y * canvas.height / r.height - canvas.height / 2) / s + this.cy];
  }
  onPixel(px) {
    this.cursor = px;
    for (const f of this.listeners) f();
  }
}
