// Moving devices: the motion status with init/park/stop (every IMotion), roof and dome, focuser
// and filter wheel.

import { h, show } from "../dom.js";
import { card, messageLine, readout } from "./context.js";

const input = (id, attrs = {}) => h("input", { id, type: "number", step: "any", ...attrs });
const value = (id) => Number(document.getElementById(id).value);

export function motionCard(ctx) {
  const message = messageLine();
  const [statusEl, setStatus] = readout("Motion", "motion-status");
  const [readyEl, setReady] = readout("Ready", "motion-ready");
  ctx.poll([["get_motion_status"], ["is_ready"]], (v) => {
    setStatus(show(v.get_motion_status));
    setReady(v.is_ready === undefined ? "—" : v.is_ready ? "yes" : "no");
  });
  return card("Motion",
    h("div.readouts", statusEl, readyEl),
    h("div.buttons",
      ctx.action("Initialise", "init", () => [], { message, id: "motion-init" }),
      ctx.action("Park", "park", () => [], { message, id: "motion-park" }),
      ctx.action("Stop", "stop_motion", () => [], { message, id: "motion-stop" })),
    message);
}

export function roofCard(ctx) {
  const message = messageLine();
  const parts = [
    h("div.buttons",
      ctx.action("Open", "open_roof", () => [], { message, id: "roof-open" }),
      ctx.action("Close", "close_roof", () => [], { message, id: "roof-close" })),
  ];
  if (ctx.offers("IDome")) {
    const [azEl, setAz] = readout("Slit azimuth", "dome-az");
    ctx.poll([["get_azimuth"]], (v) => setAz(`${show(v.get_azimuth, 5)}°`));
    parts.push(h("div.readouts", azEl), h("div.row", h("label", "Azimuth [°] ", input("dome-move-az")),
      ctx.action("Turn", "move_azimuth", () => [value("dome-move-az")], { message, id: "dome-move" })));
  }
  return card(ctx.offers("IDome") ? "Dome" : "Roof", parts, message);
}

export function focuserCard(ctx) {
  const message = messageLine();
  const [focusEl, setFocus] = readout("Focus [mm]", "focus-value");
  const [offsetEl, setOffset] = readout("Offset [mm]", "focus-offset");
  ctx.poll([["get_focus"], ["get_focus_offset"]], (v) => {
    setFocus(show(v.get_focus, 6));
    setOffset(show(v.get_focus_offset, 6));
  });
  return card("Focuser",
    h("div.readouts", focusEl, offsetEl),
    h("div.row", h("label", "Focus [mm] ", input("focus-set")), ctx.action("Set focus", "set_focus", () => [value("focus-set")], { message, id: "focus-set-button" })),
    h("div.row", h("label", "Offset [mm] ", input("focus-offset-set")), ctx.action("Set offset", "set_focus_offset", () => [value("focus-offset-set")], { message })),
    message);
}

export function filtersCard(ctx) {
  const message = messageLine();
  const [filterEl, setFilter] = readout("Filter", "filter-current");
  const select = h("select#filter-select", { "aria-label": "filter" });
  let listed = false;
  ctx.poll([["get_filter"], ["list_filters"]], (v) => {
    setFilter(show(v.get_filter));
    if (!listed && v.list_filters) {
      select.replaceChildren(...v.list_filters.map((f) => h("option", f)));
      select.value = v.get_filter;
      listed = true;
    }
  });
  return card("Filter wheel",
    h("div.readouts", filterEl),
    h("div.row", select, ctx.action("Change", "set_filter", () => [select.value], { message, id: "filter-set" })),
    message);
}
