// Camera controls, each shown only when the camera offers its interface: exposure time, image
// type, binning, window, gain, cooling; expose/abort and the progress of the running exposure.

import { call, read } from "../api.js";
import { h, show } from "../dom.js";
import { card, messageLine, readout } from "./context.js";

export function cameraCard(ctx) {
  const message = messageLine();
  const rows = [];
  const exptime = h("input#cam-exptime", { type: "number", min: 0, step: "any", value: 1 });
  if (ctx.offers("IExposureTime")) rows.push(h("label", "Exposure time [s] ", exptime));
  const imageType = h("select#cam-imagetype", (ctx.module.methods.set_image_type?.params[0]?.choices || []).map((c) => h("option", c)));
  if (ctx.offers("IImageType")) rows.push(h("label", "Image type ", imageType));
  const binning = h("select#cam-binning");
  if (ctx.offers("IBinning")) rows.push(h("label", "Binning ", binning));
  const win = ["left", "top", "width", "height"].map((k) => h("input", { id: `cam-window-${k}`, type: "number", min: 0, placeholder: k, "aria-label": `window ${k}` }));
  if (ctx.offers("IWindow")) rows.push(h("div.window", "Window ", win, ctx.action("Full frame", "get_full_frame", () => [], { message, then: (w) => fillWindow(w) })));
  const gain = h("input#cam-gain", { type: "number", step: "any" });
  if (ctx.offers("IGain")) rows.push(h("label", "Gain ", gain));

  function fillWindow(w) {
    if (!w) return;
    for (const [i, k] of ["left", "top", "width", "height"].entries()) win[i].value = w[k];
  }

  // Settings go to the camera first (only those it offers), then one frame is taken.
  async function settle() {
    const calls = [];
    if (ctx.offers("IExposureTime")) calls.push(["set_exposure_time", [Number(exptime.value)]]);
    if (ctx.offers("IImageType")) calls.push(["set_image_type", [imageType.value]]);
    if (ctx.offers("IBinning") && binning.value) calls.push(["set_binning", binning.value.split("x").map(Number)]);
    if (ctx.offers("IWindow") && win.every((i) => i.value !== "")) calls.push(["set_window", win.map((i) => Number(i.value))]);
    if (ctx.offers("IGain") && gain.value !== "") calls.push(["set_gain", [Number(gain.value)]]);
    for (const [method, args] of calls) await call(ctx.name, method, args);
    return [];
  }
  const expose = ctx.action("Expose", "grab_data", settle, { message, id: "cam-expose", then: (path) => (message.textContent = `frame written: ${path}`) });
  const abort = ctx.action("Abort", "abort", () => [], { message, id: "cam-abort" });

  const [statusEl, setStatus] = readout("Status", "cam-status");
  const [leftEl, setLeft] = readout("Time left [s]", "cam-left");
  const progress = h("progress#cam-progress", { max: 100, value: 0 });
  const [coolEl, setCool] = readout("Cooling", "cam-cooling");
  ctx.poll([["get_exposure_status"], ["get_exposure_progress"], ["get_exposure_time_left"], ["get_cooling"]], (v) => {
    setStatus(show(v.get_exposure_status));
    progress.value = v.get_exposure_progress ?? 0;
    setLeft(show(v.get_exposure_time_left, 3));
    const c = v.get_cooling;
    if (c) setCool(`${c.enabled ? "on" : "off"}, setpoint ${show(c.setpoint)} °C, power ${show(c.power, 3)} %`);
  });
  initial(ctx, { exptime, imageType, binning, gain, fillWindow });
  return card("Camera",
    h("div.form-grid", rows),
    h("div.buttons", expose, abort),
    h("div.readouts", statusEl, leftEl, ctx.offers("ICooling") ? coolEl : null),
    progress, message);
}

/** Fill the controls once with the camera's current settings. */
async function initial(ctx, { exptime, imageType, binning, gain, fillWindow }) {
  const methods = [["get_exposure_time"], ["get_image_type"], ["list_binnings"], ["get_binning"], ["get_window"], ["get_gain"]].filter(([m]) => ctx.has(m));
  let results;
  try {
    results = await read(methods.map(([method]) => ({ module: ctx.name, method, args: [] })));
  } catch {
    return;
  }
  const v = Object.fromEntries(methods.map(([m], i) => [m, results[i]?.result]));
  if (v.get_exposure_time !== undefined) exptime.value = v.get_exposure_time;
  if (v.get_image_type) imageType.value = v.get_image_type;
  if (v.list_binnings) {
    binning.replaceChildren(...v.list_binnings.map((b) => h("option", `${b.x}x${b.y}`)));
    if (v.get_binning) binning.value = `${v.get_binning.x}x${v.get_binning.y}`;
  }
  if (v.get_window) fillWindow(v.get_window);
  if (v.get_gain !== undefined) gain.value = v.get_gain;
}
