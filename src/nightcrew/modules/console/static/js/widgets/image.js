// The last frame of a camera: a PNG the console renders from it (stretch and percentiles chosen
// here), zoom and pan with Panzoom (wheel, drag, pinch), and the frame's FITS header.

import * as api from "../api.js";
import { h, replace, show } from "../dom.js";
import Panzoom from "../../vendor/panzoom/panzoom.es.js";
import { card } from "./context.js";

export function imageCard(ctx) {
  const base = `/api/images/${encodeURIComponent(ctx.name)}/latest`;
  const img = h("img#last-image", { alt: "last frame", draggable: false });
  const stage = h("div.image-stage", img);
  const info = h("p#image-info.hint", "no frame yet");
  const stretch = h("select#image-stretch", { "aria-label": "stretch", onchange: load }, ["linear", "asinh", "log"].map((s) => h("option", s)));
  const low = h("input#image-low", { type: "number", value: 1, step: 0.5, min: 0, max: 100, "aria-label": "low percentile", onchange: load });
  const high = h("input#image-high", { type: "number", value: 99.5, step: 0.1, min: 0, max: 100, "aria-label": "high percentile", onchange: load });
  const headerTable = h("table#image-header.header");
  const headerBox = h("details.header-box", h("summary", "FITS header"), headerTable);
  let currentId = null;
  let loading = false;
  let again = false;

  // Panzoom measures the element, so it starts once the image is on the page.
  let panzoom = null;
  function startPanzoom() {
    if (panzoom || !img.isConnected) return;
    panzoom = Panzoom(img, { maxScale: 32, minScale: 0.5, canvas: true });
    stage.addEventListener("wheel", (e) => panzoom.zoomWithWheel(e));
  }
  const reset = h("button#image-fit", { onclick: () => panzoom?.reset() }, "Fit");

  async function load() {
    if (currentId === null) return;
    if (loading) {
      again = true; // a newer frame or stretch arrived while loading: load once more after this one
      return;
    }
    loading = true;
    const id = currentId;
    const params = new URLSearchParams({ stretch: stretch.value, low: low.value, high: high.value, max_size: 1024, id });
    const next = new Image();
    next.src = `${base}.png?${params}`;
    try {
      await next.decode();
      img.src = next.src;
      img.dataset.imageId = id;
      img.dataset.shownAt = String(Date.now()); // epoch ms: the benchmark compares it with the event
      startPanzoom();
    } catch {
      info.textContent = `frame ${id} could not be loaded`;
    }
    loading = false;
    if (again) {
      again = false;
      load();
    }
  }
  async function loadHeader() {
    try {
      const meta = await api.get(`${base}.json`);
      currentId = meta.id;
      info.textContent = `frame ${meta.id}: ${meta.filename} — ${meta.width} × ${meta.height} px, ${meta.time}`;
      replace(headerTable, meta.header.map((c) => h("tr", h("th", c.key), h("td", show(c.value, 8)), h("td.comment", c.comment || ""))));
    } catch (exc) {
      if (exc.status !== 404) info.textContent = exc.describe();
    }
  }
  ctx.on("image", (msg) => {
    if (msg.module !== ctx.name) return;
    currentId = msg.id;
    load();
    loadHeader();
  });
  ctx.cleanup(() => panzoom?.destroy());
  loadHeader().then(load);
  return card("Last image",
    h("div.controls", h("label", "Stretch ", stretch), h("label", "Low % ", low), h("label", "High % ", high), reset),
    stage, info, headerBox);
}
