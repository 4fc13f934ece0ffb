// The capture inspector's page script, embedded in every page it writes
// (reports/inspect_page.h): the page opens offline, from any folder, with no
// file beside it.
#include "reports/inspect_page.h"

namespace gi {

const char* const kInspectScript = R"JS(
"use strict";
// The capture inspector's page script (reports/inspect_page.h). Data sits in
// the page: #meta (JSON) and one <script type="text/plain" id="blob-N"> per
// array, base64 of zlib-deflated little-endian bytes, inflated on first use
// with the browser's DecompressionStream('deflate'), so a page opens offline
// and only what is looked at is inflated.
const META = JSON.parse(document.getElementById("meta").textContent);
const chunks = new Map();
// One deflated chunk (a <script type="text/plain" id="blob-N">), inflated
// once, and its byte planes put back into words of `shuffle` bytes (a word
// of 4 bytes or a whole element; 1: as written. The writer groups like bytes
// together where deflate then finds more: reports/inspect_page.cpp).
function chunk(id, shuffle) {
  if (!chunks.has(id)) chunks.set(id, (async () => {
    const bin = atob(document.getElementById("blob-" + id).textContent);
    const bytes = new Uint8Array(bin.length);
    for (let i = 0; i < bin.length; ++i) bytes[i] = bin.charCodeAt(i);
    const stream = new Blob([bytes]).stream().pipeThrough(new DecompressionStream("deflate"));
    const planes = new Uint8Array(await new Response(stream).arrayBuffer());
    if (!(shuffle > 1)) return planes;
    const out = new Uint8Array(planes.length), words = Math.floor(planes.length / shuffle);
    for (let b = 0; b < shuffle; ++b) {
      const from = b * words;
      for (let w = 0; w < words; ++w) out[w * shuffle + b] = planes[from + w];
    }
    out.set(planes.subarray(words * shuffle), words * shuffle);
    return out;
  })());
  return chunks.get(id);
}
// A whole array ({chunks, chunk_bytes, bytes}) as one DataView.
const wholes = new Map();
function blob(desc) {
  const key = desc.chunks[0];
  if (!wholes.has(key)) wholes.set(key, (async () => {
    const parts = await Promise.all(desc.chunks.map((id, i) => chunk(id, desc.shuffle[i])));
    if (parts.length === 1) return new DataView(parts[0].buffer);
    const all = new Uint8Array(desc.bytes);
    parts.forEach((p, i) => all.set(p, i * desc.chunk_bytes));
    return new DataView(all.buffer);
  })());
  return wholes.get(key);
}
// The chunk that holds byte `offset` of an array, and the offset in it
// (chunks hold whole elements, so an element never straddles two).
async function at(desc, offset) {
  const i = Math.floor(offset / desc.chunk_bytes);
  const c = await chunk(desc.chunks[i], desc.shuffle[i]);
  return {dv: new DataView(c.buffer), base: offset - i * desc.chunk_bytes};
}
const SIZE = {"<f4": 4, "<u4": 4, "<i4": 4, "<u8": 8, "<f8": 8, "|u1": 1};
function read(dv, off, dtype) {
  switch (dtype) {
    case "<f4": return dv.getFloat32(off, true);
    case "<u4": return dv.getUint32(off, true);
    case "<i4": return dv.getInt32(off, true);
    case "<u8": return Number(dv.getBigUint64(off, true));
    case "<f8": return dv.getFloat64(off, true);
    default: return dv.getUint8(off);
  }
}
// Sources: every layer and every buffer, each a grid of elements (rows of
// fields). A source whose elements are the image's pixels (per chain) is
// shown at the image's size; any other as a square of its elements in order.
const W = META.width, H = META.height;
const sources = [];
for (const l of META.layers)
  sources.push({name: l.name, group: l.group || "layer", blob: l.blob, rowBytes: 12, chains: 1, image: true,
                width: W, height: H, elements: W * H, note: l.note || "",
                fields: [{name: "rgb", offset: 0, dtype: "<f4", count: 3, labels: "R G B"}]});
for (const b of META.buffers) {
  const s = {name: b.name, group: b.group || "buffer", blob: b.blob, layout: b.layout || "", note: b.note || ""};
  const size = SIZE[b.dtype];
  s.rowWords = b.row_words; s.rowBytes = b.row_words * size; s.elementsAll = b.elements;
  s.fields = b.fields || [{name: "value", offset: 0, dtype: b.dtype, count: b.row_words, labels: ""}];
  if (b.pixels) { s.image = true; s.chains = b.pixels.chains; s.width = W; s.height = H; s.elements = W * H; }
  else {
    s.image = false; s.chains = 1; s.elements = b.elements;
    s.width = Math.max(1, Math.ceil(Math.sqrt(b.elements))); s.height = Math.max(1, Math.ceil(b.elements / s.width));
  }
  sources.push(s);
}
const byName = new Map(sources.map(s => [s.name, s]));
function labelsOf(f) { return f.labels ? f.labels.split(" ") : []; }
// A field's components of one element; `row` = await at(s.blob, element * s.rowBytes).
function fieldValues(row, f) {
  const out = [];
  const base = row.base + f.offset, sz = SIZE[f.dtype];
  for (let c = 0; c < f.count; ++c) out.push(read(row.dv, base + c * sz, f.dtype));
  return out;
}
// Numbers for a person (6 significant digits); the exact value travels in data-values.
function show(v, dtype) {
  if (dtype !== "<f4" && dtype !== "<f8") return String(v);
  if (!isFinite(v)) return String(v);
  return v === 0 ? "0" : (Math.abs(v) >= 1e5 || Math.abs(v) < 1e-4 ? v.toExponential(5) : String(+v.toPrecision(6)));
}
function el(tag, attrs, ...kids) {
  const e = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs || {})) e.setAttribute(k, v);
  for (const k of kids) e.append(k);
  return e;
}
// Colour maps: Turbo (Mikhailov 2019, polynomial fit) for false colour;
// a hash for identifiers (light id, cell key); tone map: exposure, clamp, sRGB.
function turbo(t) {
  t = Math.min(1, Math.max(0, t));
  const r = 0.13572138 + t * (4.61539260 + t * (-42.66032258 + t * (132.13108234 + t * (-152.94239396 + t * 59.28637943))));
  const g = 0.09140261 + t * (2.19418839 + t * (4.84296658 + t * (-14.18503333 + t * (4.27729857 + t * 2.82956604))));
  const b = 0.10667330 + t * (12.64194608 + t * (-60.58204836 + t * (110.36276771 + t * (-89.90310912 + t * 27.34824973))));
  return [r * 255, g * 255, b * 255];
}
function idColour(v) {
  let h = (v >>> 0) ^ 0x9e3779b9; h = Math.imul(h ^ (h >>> 16), 0x85ebca6b); h = Math.imul(h ^ (h >>> 13), 0xc2b2ae35);
  h ^= h >>> 16;
  return [64 + (h & 191), 64 + ((h >>> 8) & 191), 64 + ((h >>> 16) & 191)];
}
function srgb(x) { x = Math.min(1, Math.max(0, x)); return 255 * (x <= 0.0031308 ? 12.92 * x : 1.055 * Math.pow(x, 1 / 2.4) - 0.055); }
// Draws source s (chain, field, component or "rgb", mode) into a canvas.
async function draw(canvas, s, v) {
  const dv = await blob(s.blob);
  const f = s.fields[v.field] || s.fields[0];
  const w = s.width, h = s.height, n = s.elements;
  canvas.width = w; canvas.height = h;
  const ctx = canvas.getContext("2d");
  const img = ctx.createImageData(w, h);
  const px = img.data;
  const sz = SIZE[f.dtype];
  const first = v.chain * (s.image ? s.elements : 0);
  const rgb = v.comp === "rgb" && f.count >= 3;
  const comp = rgb ? 0 : Math.min(Number(v.comp) || 0, f.count - 1);
  let lo = Infinity, hi = -Infinity;
  const vals = rgb ? null : new Float64Array(n);
  if (!rgb) {
    for (let i = 0; i < n; ++i) {
      const x = read(dv, (first + i) * s.rowBytes + f.offset + comp * sz, f.dtype);
      vals[i] = x;
      if (isFinite(x)) { if (x < lo) lo = x; if (x > hi) hi = x; }
    }
    if (v.lo !== undefined && v.lo !== "") lo = Number(v.lo);
    if (v.hi !== undefined && v.hi !== "") hi = Number(v.hi);
  }
  const scale = Math.pow(2, Number(v.exposure) || 0);
  for (let i = 0; i < w * h; ++i) {
    let c = [40, 40, 40];
    if (i < n) {
      if (rgb) {
        const o = (first + i) * s.rowBytes + f.offset;
        const r = read(dv, o, f.dtype), g = read(dv, o + sz, f.dtype), b = read(dv, o + 2 * sz, f.dtype);
        c = isFinite(r + g + b) ? [srgb(r * scale), srgb(g * scale), srgb(b * scale)] : [255, 0, 255];
      } else {
        const x = vals[i];
        if (!isFinite(x)) c = [255, 0, 255];
        else if (v.mode === "id") c = idColour(x);
        else if (v.mode === "tone") { const t = srgb(x * scale); c = [t, t, t]; }
        else c = turbo(hi > lo ? (x - lo) / (hi - lo) : 0.5);
      }
    }
    px[4 * i] = c[0]; px[4 * i + 1] = c[1]; px[4 * i + 2] = c[2]; px[4 * i + 3] = 255;
  }
  ctx.putImageData(img, 0, 0);
  canvas.dataset.drawn = "1";
  return {lo, hi};
}
// The view: a source, its chain, field, component, mode, exposure, range.
const state = {source: sources[0] ? sources[0].name : "", chain: 0, field: 0, comp: "rgb", mode: "false",
               exposure: 0, lo: "", hi: ""};
// Identifiers (a light id, a cell key) read best as distinct colours.
function idField(f) { return /(^|[._])(light_id|triangle_id|key|slot|checksum|seed)$/.test(f.name); }
function defaultsFor(s) {
  // A derived cell opens on its life: the world cache projected onto the image.
  const life = s.group === "derived" ? s.fields.findIndex(f => f.name === "life") : -1;
  state.field = life >= 0 ? life : 0; state.chain = 0; state.lo = ""; state.hi = "";
  const f = s.fields[state.field];
  state.comp = f.count >= 3 ? "rgb" : "0";
  state.mode = s.group === "layer" ? "tone" : idField(f) ? "id" : "false";
}
const main = document.getElementById("view");
const controls = document.getElementById("controls");
function option(value, text, selected) { const o = el("option", {value}, text); if (selected) o.selected = true; return o; }
function buildControls() {
  const s = byName.get(state.source);
  controls.replaceChildren();
  const src = el("select", {id: "c-source"});
  for (const t of sources) src.append(option(t.name, t.group + ": " + t.name, t.name === state.source));
  src.onchange = () => { state.source = src.value; defaultsFor(byName.get(src.value)); buildControls(); redraw(); };
  controls.append("source ", src);
  if (s.chains > 1) {
    const ch = el("select", {id: "c-chain"});
    for (let c = 0; c < s.chains; ++c) ch.append(option(c, "chain " + c, c === state.chain));
    ch.onchange = () => { state.chain = Number(ch.value); redraw(); };
    controls.append(" ", ch);
  }
  const fs = el("select", {id: "c-field"});
  s.fields.forEach((f, i) => fs.append(option(i, f.name, i === state.field)));
  fs.onchange = () => { state.field = Number(fs.value); const f = s.fields[state.field];
                        state.comp = f.count >= 3 ? "rgb" : "0"; state.lo = state.hi = "";
                        if (s.group !== "layer") state.mode = idField(f) ? "id" : "false"; buildControls(); redraw(); };
  controls.append(" field ", fs);
  const f = s.fields[state.field];
  const cs = el("select", {id: "c-comp"});
  if (f.count >= 3) cs.append(option("rgb", "rgb (first three)", state.comp === "rgb"));
  const labels = labelsOf(f);
  for (let c = 0; c < f.count; ++c) cs.append(option(String(c), "[" + c + "]" + (labels[c] ? " " + labels[c] : ""), state.comp === String(c)));
  cs.onchange = () => { state.comp = cs.value; state.lo = state.hi = ""; redraw(); };
  controls.append(" ", cs);
  const ms = el("select", {id: "c-mode"});
  for (const [m, t] of [["false", "false colour"], ["tone", "tone-mapped"], ["id", "identifier colours"]])
    ms.append(option(m, t, state.mode === m));
  ms.onchange = () => { state.mode = ms.value; redraw(); };
  controls.append(" ", ms);
  const ex = el("input", {id: "c-exposure", type: "range", min: -12, max: 12, step: 0.5, value: state.exposure});
  ex.oninput = () => { state.exposure = Number(ex.value); redraw(); };
  controls.append(" exposure ", ex);
  const lo = el("input", {id: "c-lo", size: 8, value: state.lo}), hi = el("input", {id: "c-hi", size: 8, value: state.hi});
  lo.onchange = () => { state.lo = lo.value; redraw(); };
  hi.onchange = () => { state.hi = hi.value; redraw(); };
  controls.append(" range ", lo, " – ", hi);
  document.getElementById("layout-note").textContent = (s.layout ? "layout: " + s.layout + ". " : "") + s.note;
}
let drawing = Promise.resolve();
function redraw() {
  const s = byName.get(state.source);
  drawing = drawing.then(async () => {
    const r = await draw(main, s, state);
    document.getElementById("range-note").textContent =
      state.comp === "rgb" ? "" : "false colour over [" + show(r.lo, "<f4") + ", " + show(r.hi, "<f4") + "]";
    await outline();
    mark();
  });
  return drawing;
}
// The picked pixel, ringed in cyan over the view (the canvas is at the
// image's resolution: the ring is the eight pixels around it).
function mark() {
  const s = byName.get(state.source);
  if (!s || !s.image || !state.picked) return;
  const [x, y] = state.picked;
  const ctx = main.getContext("2d");
  ctx.strokeStyle = "#2ff"; ctx.lineWidth = 1;
  ctx.strokeRect(x - 0.5, y - 0.5, 2, 2);
  document.body.dataset.picked = x + "," + y;
}
// The region a check judged, outlined over the view when the view is of the
// image's pixels: #region=x0,y0,x1,y1 (inclusive pixels), else the region the
// page was written with (META.region, the nightly's failing check) and, where
// the check gave its mask, the mask itself: the pixels outside it dimmed.
let regionMask = null;
async function outline() {
  const s = byName.get(state.source);
  if (!s || !s.image) return;
  const r = hashParams.get("region") ? hashParams.get("region").split(",").map(Number) : META.region;
  const ctx = main.getContext("2d");
  // The report's link names the page's own region in the fragment: the mask
  // is the region's unless the fragment asks for another.
  const asked = hashParams.get("region");
  if (META.region_mask && (!asked || (META.region && asked === META.region.join(",")))) {
    if (!regionMask) regionMask = await blob(META.region_mask);
    const img = ctx.getImageData(0, 0, W, H);
    let border = 0;
    const inside = (x, y) => x >= 0 && y >= 0 && x < W && y < H && regionMask.getUint8(y * W + x) !== 0;
    // The pixels outside the mask are dimmed rather than the border drawn:
    // a region of scattered pixels (a shadow threshold on a noisy reference)
    // is mostly border, and drawing it would hide the pixels it is about.
    for (let y = 0; y < H; ++y)
      for (let x = 0; x < W; ++x) {
        if (!inside(x, y)) {
          const i = 4 * (y * W + x);
          for (let c = 0; c < 3; ++c) img.data[i + c] = Math.round(img.data[i + c] * 0.3);
        } else if (!(inside(x - 1, y) && inside(x + 1, y) && inside(x, y - 1) && inside(x, y + 1))) {
          ++border;
        }
      }
    ctx.putImageData(img, 0, 0);
    document.body.dataset.regionMask = String(border);
  }
  if (!r || r.length !== 4) return;
  const [x0, y0, x1, y1] = r;
  ctx.strokeStyle = "#ff2"; ctx.lineWidth = 1;
  ctx.strokeRect(x0 + 0.5, y0 + 0.5, x1 - x0, y1 - y0);
  document.body.dataset.region = r.join(",");
}
// A pixel's values in every image-shaped source, decoded by its fields.
async function pick(x, y) {
  state.picked = [x, y];
  redraw();
  const table = el("table", {id: "pixel-table"});
  table.append(el("tr", {}, el("th", {}, "source"), el("th", {}, "chain"), el("th", {}, "field"), el("th", {}, "value")));
  const p = y * W + x;
  for (const s of sources) {
    if (!s.image) continue;
    for (let c = 0; c < s.chains; ++c) {
      const e = c * s.elements + p;
      const row = await at(s.blob, e * s.rowBytes);
      for (const f of s.fields) {
        if (f.name.startsWith("pad")) continue;
        const vals = fieldValues(row, f);
        const labels = labelsOf(f);
        const text = vals.map((v, i) => (labels[i] && labels[i] !== "-" ? labels[i] + " " : "") + show(v, f.dtype)).join(", ");
        table.append(el("tr", {"data-source": s.name, "data-chain": c, "data-field": f.name, "data-values": vals.join(" ")},
                        el("td", {}, s.name), el("td", {}, String(c)), el("td", {}, f.name), el("td", {}, text)));
      }
      for (const line of explain(s, row))
        table.append(el("tr", {"class": "explain", "data-source": s.name, "data-chain": c},
                        el("td", {}, ""), el("td", {}, ""), el("td", {}, "→"), el("td", {}, line)));
    }
  }
  const panel = document.getElementById("pixel");
  panel.replaceChildren(el("h2", {}, "Pixel " + x + ", " + y), table);
  document.body.dataset.pixel = x + "," + y;
}
// What a decoded element points at: a DI reservoir's light, a cache cell's state.
function explain(s, row) {
  const out = [];
  const name = (s.layout || "").split(" ")[0];
  if (name === "DiReservoir" && META.lights) {
    const f = s.fields.find(f => f.name === "light.light_id"), v = s.fields.find(f => f.name === "light.valid");
    if (f && v && fieldValues(row, v)[0]) {
      const id = fieldValues(row, f)[0], l = META.lights[id];
      out.push(l ? "light " + id + ": " + l.kind + " \u201c" + l.name + "\u201d" + (l.triangles ? " (" + l.triangles + " triangles)" : "")
                 : "light " + id + ": not in the scene at this frame");
    } else if (f) out.push("empty reservoir (no light)");
  }
  if (s.group === "derived" && s.note) out.push(s.note);
  return out;
}
function diffSection() {
  const a = META.against;
  if (!a) return;
  const sec = document.getElementById("diff");
  sec.append(el("h2", {}, (a.baseline ? "Against the baseline " : "Against ") + a.dir));
  const verdict = el("p", {id: "diff-verdict", "data-identical": a.identical ? "1" : "0"},
                     a.identical ? (a.baseline ? "identical: every buffer's hash equals the baseline's" +
                                                 (a.entries.some(d => d.kind === "layer") ? ", and the output its final image" : "")
                                               : "identical: every buffer and every layer is equal bit for bit")
                                 : "different: " + a.entries.filter(d => d.status !== "equal").map(d => d.name).join(", "));
  sec.append(verdict);
  for (const n of a.notes || []) sec.append(el("p", {"class": "note diff-note"}, n));
  const t = el("table", {id: "diff-table"});
  t.append(el("tr", {}, ...["kind", "name", "status", "differing", "of", "first differing element", "here", "there"].map(h => el("th", {}, h))));
  for (const d of a.entries) {
    const hash = d.by === "hash";
    const first = d.status === "different" && !hash ? "[" + d.first_index.join(", ") + "] word " + d.first_word + (d.first_field ? " (" + d.first_field + ")" : "")
                : hash && d.status === "different" ? "by hash (the baseline keeps no elements)" : "";
    const row = el("tr", {"data-name": d.name, "data-status": d.status},
                   ...[d.kind, d.name, d.status, d.status === "different" && !hash ? String(d.differing) : "", String(d.elements), first,
                       d.status === "different" ? String(d.here) : "", d.status === "different" ? String(d.there) : ""].map(c => el("td", {}, c)));
    t.append(row);
  }
  sec.append(t);
  for (const d of a.entries) {
    if (d.status !== "different" || d.mask_blob === undefined) continue;
    const s = byName.get(d.name);
    const c = el("canvas", {"class": "diff", title: d.name});
    sec.append(el("figure", {}, c, el("figcaption", {}, d.name + ": " + d.differing + " differing (white)")));
    const w = s && s.image ? W : Math.max(1, Math.ceil(Math.sqrt(d.elements)));
    blob(d.mask_blob).then(dv => {
      const h = Math.max(1, Math.ceil(d.elements / w));
      c.width = w; c.height = h;
      const ctx = c.getContext("2d"), img = ctx.createImageData(w, h);
      for (let i = 0; i < w * h; ++i) { const m = i < d.elements && dv.getUint8(i); img.data.set(m ? [255, 255, 255, 255] : [30, 30, 60, 255], 4 * i); }
      ctx.putImageData(img, 0, 0);
      c.dataset.drawn = "1";
    });
  }
}
// Every source as a thumbnail, drawn as it scrolls into view (#all: at once,
// which is what the browser test asks for).
async function gallery() {
  const g = document.getElementById("gallery");
  const jobs = [];
  const all = hashParams.has("all");
  const observer = all ? null : new IntersectionObserver(entries => {
    for (const e of entries) if (e.isIntersecting) { observer.unobserve(e.target); e.target.drawJob(); }
  });
  for (const s of sources) {
    const c = el("canvas", {"class": "thumb", "data-source": s.name});
    const fig = el("figure", {}, c, el("figcaption", {}, s.name));
    fig.onclick = () => { state.source = s.name; defaultsFor(s); buildControls(); redraw(); };
    g.append(fig);
    const v = {chain: 0, field: 0, comp: s.fields[0].count >= 3 ? "rgb" : "0", mode: s.group === "layer" ? "tone" : "false", exposure: 0};
    c.drawJob = () => draw(c, s, v).catch(err => { document.body.dataset.imageErrors = (Number(document.body.dataset.imageErrors || 0) + 1);
                                                     console.error("inspect: " + s.name + " did not decode: " + err); });
    if (all) jobs.push(c.drawJob()); else observer.observe(c);
  }
  await Promise.all(jobs);
  if (all) document.body.dataset.drawn = String(document.querySelectorAll("canvas.thumb[data-drawn]").length) + "/" + sources.length;
}
const hashParams = new URLSearchParams(location.hash.slice(1));
main.addEventListener("click", ev => {
  const s = byName.get(state.source);
  const r = main.getBoundingClientRect();
  const x = Math.floor((ev.clientX - r.left) * main.width / r.width), y = Math.floor((ev.clientY - r.top) * main.height / r.height);
  if (s.image) pick(x, y); else pickElement(s, y * s.width + x);
});
async function pickElement(s, e) {
  if (e >= s.elements) return;
  const row = await at(s.blob, e * s.rowBytes);
  const t = el("table", {id: "element-table"});
  for (const f of s.fields) {
    const vals = fieldValues(row, f);
    t.append(el("tr", {"data-field": f.name, "data-values": vals.join(" ")}, el("td", {}, f.name), el("td", {}, vals.map(v => show(v, f.dtype)).join(", "))));
  }
  document.getElementById("pixel").replaceChildren(el("h2", {}, s.name + " element " + e), t);
}
// The output and the Embree reference side by side, tone-mapped at the view's exposure.
async function beside() {
  const sec = document.getElementById("beside");
  if (!sec) return;
  for (const name of ["output", "reference/output"]) {
    const s = byName.get(name);
    if (!s) continue;
    const c = el("canvas", {"class": "diff", "data-source": name});
    sec.append(el("figure", {}, c, el("figcaption", {}, name + (s.note ? ": " + s.note : ""))));
    await draw(c, s, {chain: 0, field: 0, comp: "rgb", mode: "tone", exposure: state.exposure});
  }
}
(async () => {
  try {
    if (hashParams.has("source") && byName.has(hashParams.get("source"))) state.source = hashParams.get("source");
    if (byName.has(state.source)) { defaultsFor(byName.get(state.source)); buildControls(); await redraw(); }
    // How long the page took to show its first view (the figure docs/commands/inspect.md quotes).
    document.body.dataset.viewMs = String(Math.round(performance.now()));
    diffSection();
    await beside();
    await gallery();
    if (hashParams.has("pixel")) {
      const [x, y] = hashParams.get("pixel").split(",").map(Number);
      await pick(x, y);
    }
    document.body.dataset.readyMs = String(Math.round(performance.now()));
    document.getElementById("status").textContent = "first view in " + document.body.dataset.viewMs + " ms, ready in " +
        document.body.dataset.readyMs + " ms" + (hashParams.has("pixel") ? " (pixel " + hashParams.get("pixel") + " decoded)" : "");
    document.body.dataset.ready = "1";
  } catch (err) {
    console.error("inspect: " + err + "\n" + (err.stack || ""));
  }
})();
)JS";

}  // namespace gi
