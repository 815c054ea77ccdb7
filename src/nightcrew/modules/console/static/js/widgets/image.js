// The last frame of a camera: a PNG the console renders from it (stretch and percentiles chosen
// here), zoom and pan with Panzoom (wheel, drag, pinch), and the frame's FITS header. The overview
// is at most 1024 px; zoomed in, the part in view is fetched again at the frame's own resolution.

import * as api from "../api.js";
import { h, replace, show } from "../dom.js";
import Panzoom from "../../vendor/panzoom/panzoom.es.js";
import { card } from "./context.js";

const OVERVIEW = 1024; // longest side of the whole-frame PNG

export function imageCard(ctx) {
  const base = `/api/images/${encodeURIComponent(ctx.name)}/latest`;
  const img = h("img#last-image", { alt: "last frame", draggable: false });
  const detail = h("img#image-detail", { alt: "", draggable: false, hidden: true });
  const stage = h("div.image-stage", img, detail);
  const info = h("p#image-info.hint", "no frame yet");
  const stretch = h("select#image-stretch", { "aria-label": "stretch", onchange: load }, ["linear", "asinh", "log"].map((s) => h("option", s)));
  const low = h("input#image-low", { type: "number", value: 1, step: 0.5, min: 0, max: 100, "aria-label": "low percentile", onchange: load });
  const high = h("input#image-high", { type: "number", value: 99.5, step: 0.1, min: 0, max: 100, "aria-label": "high percentile", onchange: load });
  const headerTable = h("table#image-header.header");
  const headerBox = h("details.header-box", h("summary", "FITS header"), headerTable);
  let currentId = null;
  let frameSize = null; // [width, height] of the whole frame
  let detailTimer = null;
  let loading = false;
  let again = false;

  // Panzoom measures the element, so it starts once the image is on the page.
  let panzoom = null;
  function startPanzoom() {
    if (panzoom || !img.isConnected) return;
    panzoom = Panzoom(img, { maxScale: 32, minScale: 0.5, canvas: true });
    stage.addEventListener("wheel", (e) => panzoom.zoomWithWheel(e));
    img.addEventListener("panzoomchange", () => {
      detail.hidden = true; // stale as soon as the view moves
      clearTimeout(detailTimer);
      detailTimer = setTimeout(loadDetail, 300);
    });
  }

  /** The part of the frame in view, at full resolution, laid over the zoomed overview. */
  async function loadDetail() {
    if (!frameSize || currentId === null) return;
    const view = stage.getBoundingClientRect();
    const shown = img.getBoundingClientRect();
    const overview = frameSize[0] * Math.min(1, OVERVIEW / Math.max(...frameSize)); // its width in px
    // Worth it only where the overview is blown up and the frame has more pixels than it.
    if (frameSize[0] <= overview || shown.width * devicePixelRatio <= 1.05 * overview) return;
    const scale = frameSize[0] / shown.width; // frame pixels per screen pixel
    const left = Math.max(view.left, shown.left);
    const top = Math.max(view.top, shown.top);
    const right = Math.min(view.right, shown.right);
    const bottom = Math.min(view.bottom, shown.bottom);
    if (right - left < 4 || bottom - top < 4) return;
    const region = {
      left: Math.floor((left - shown.left) * scale),
      top: Math.floor((top - shown.top) * scale),
      width: Math.ceil((right - left) * scale),
      height: Math.ceil((bottom - top) * scale),
    };
    const size = Math.min(4096, Math.max(16, Math.ceil(Math.max(right - left, bottom - top) * devicePixelRatio)));
    const params = new URLSearchParams({ stretch: stretch.value, low: low.value, high: high.value, max_size: size, id: currentId, ...region });
    const next = new Image();
    next.src = `${base}.png?${params}`;
    try {
      await next.decode();
    } catch {
      return;
    }
    if (stage.getBoundingClientRect().width !== view.width || img.getBoundingClientRect().left !== shown.left) return; // moved meanwhile
    detail.src = next.src;
    Object.assign(detail.style, { left: `${left - view.left}px`, top: `${top - view.top}px`, width: `${right - left}px`, height: `${bottom - top}px` });
    detail.dataset.region = [region.left, region.top, region.width, region.height].join(",");
    detail.hidden = false;
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
    const params = new URLSearchParams({ stretch: stretch.value, low: low.value, high: high.value, max_size: OVERVIEW, id });
    const next = new Image();
    next.src = `${base}.png?${params}`;
    try {
      await next.decode();
      img.src = next.src;
      img.dataset.imageId = id;
      img.dataset.shownAt = String(Date.now()); // epoch ms: the benchmark compares it with the event
      startPanzoom();
      detail.hidden = true;
      loadDetail();
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
      frameSize = [meta.width, meta.height];
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
  ctx.cleanup(() => {
    clearTimeout(detailTimer);
    panzoom?.destroy();
  });
  loadHeader().then(load);
  return card("Last image",
    h("div.controls", h("label", "Stretch ", stretch), h("label", "Low % ", low), h("label", "High % ", high), reset),
    stage, info, headerBox);
}
