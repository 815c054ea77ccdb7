// Observing procedures: focus series (the V-curve as it is measured), guiding (RMS over time and
// the offsets it sends), flat fields and acquisition.

import { h, show } from "../dom.js";
import { card, messageLine, readout } from "./context.js";
import { linePlot } from "./plots.js";

const num = (id, label, val) => h("label", label, h("input", { id, type: "number", step: "any", value: val }));
const value = (id) => Number(document.getElementById(id).value);

export function focusSeriesCard(ctx) {
  const message = messageLine();
  const [stateEl, setState] = readout("Series", "fs-state");
  const vcurve = linePlot("V-curve", ["width [px]"], { xTime: false, points: true, height: 200, yLabel: "width [px]" });
  ctx.cleanup(() => vcurve.destroy());
  ctx.poll([["auto_focus_status"]], (v) => {
    const s = v.auto_focus_status;
    if (!s) return;
    const parts = [s.running ? `running, ${s.done ?? 0} of ${s.count ?? "?"}` : "idle"];
    if (s.focus !== undefined) parts.push(`best ${show(s.focus, 6)} ± ${show(s.error, 2)} mm`);
    if (s.failed) parts.push(`failed: ${s.failed}`);
    setState(parts.join("; "));
    const m = [...(s.measurements || [])].filter(([, w]) => w !== null).sort((a, b) => a[0] - b[0]);
    vcurve.setData([m.map(([x]) => x), m.map(([, w]) => w)]);
  });
  return card("Focus series",
    h("div.readouts", stateEl),
    h("div.row", num("fs-count", "Frames ", 7), num("fs-step", "Step [mm] ", 0.05), num("fs-exptime", "Exposure [s] ", 3),
      ctx.action("Start", "auto_focus", () => [value("fs-count"), value("fs-step"), value("fs-exptime")], { message, id: "fs-start" }),
      ctx.action("Abort", "abort", () => [], { message })),
    message, vcurve.element);
}

export function guidingCard(ctx) {
  const message = messageLine();
  const [loopEl, setLoop] = readout("Loop", "guide-loop");
  const [rmsEl, setRms] = readout("RMS [″]", "guide-rms");
  const rmsPlot = linePlot("Guiding RMS", ["RMS [″]"], { height: 150 });
  const offsetPlot = linePlot("Offsets sent", ["ΔRA [″]", "ΔDec [″]"], { height: 150 });
  ctx.cleanup(() => rmsPlot.destroy());
  ctx.cleanup(() => offsetPlot.destroy());
  const rms = [[], []];
  const offsets = [[], [], []];
  ctx.poll([["get_loop_state"], ["get_config_value", ["rms"]]], (v) => {
    setLoop(show(v.get_loop_state));
    const r = v['get_config_value["rms"]'];
    setRms(show(r, 3));
    if (typeof r === "number") {
      rms[0].push(Date.now() / 1000);
      rms[1].push(r);
      if (rms[0].length > 3600) rms.forEach((a) => a.shift());
      rmsPlot.setData(rms);
    }
  });
  ctx.onEvent("OffsetsRaDecEvent", (f, msg) => {
    offsets[0].push(Date.parse(msg.time) / 1000);
    offsets[1].push(f.dra * 3600);
    offsets[2].push(f.ddec * 3600);
    offsetPlot.setData(offsets);
  });
  return card("Guiding",
    h("div.readouts", loopEl, rmsEl),
    h("div.buttons", ctx.action("Start", "start", () => [], { message, id: "guide-start" }), ctx.action("Stop", "stop", () => [], { message, id: "guide-stop" })),
    message, rmsPlot.element, offsetPlot.element);
}

export function flatsCard(ctx) {
  const message = messageLine();
  return card("Flat fields",
    h("div.row", num("flats-count", "Frames ", 5),
      ctx.action("Take flats", "flat_field", () => [value("flats-count")], { message, id: "flats-start", then: (r) => (message.textContent = `${r[0]} flats, ${show(r[1], 4)} s in all`) }),
      ctx.action("Abort", "abort", () => [], { message })),
    message);
}

export function acquisitionCard(ctx) {
  const message = messageLine();
  const [runEl, setRun] = readout("Running", "acq-running");
  ctx.poll([["is_running"]], (v) => setRun(v.is_running ? "yes" : "no"));
  return card("Acquisition",
    h("div.readouts", runEl),
    h("div.buttons",
      ctx.action("Acquire target", "acquire_target", () => [], { message, id: "acq-start", then: (r) => (message.textContent = `acquired: ${show(r)}`) }),
      ctx.action("Abort", "abort", () => [], { message })),
    message);
}
