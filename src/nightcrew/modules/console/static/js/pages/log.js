// The log pane under every page: every module's log records, filtered by minimum level and module.

import * as api from "../api.js";
import { clock, h, replace } from "../dom.js";
import { on } from "../live.js";
import { state, watchModules } from "../store.js";

const LEVELS = ["INFO", "WARNING", "ERROR", "CRITICAL"];
const KEEP = 1000;

/** The pane; the listeners it adds go into ``disposers`` (called when the frame is torn down). */
export function logPane(disposers) {
  const records = [];
  const level = h("select#log-level", { "aria-label": "minimum level", onchange: render }, LEVELS.map((l) => h("option", { value: l }, l)));
  const module = h("select#log-module", { "aria-label": "module", onchange: render }, h("option", { value: "" }, "all modules"));
  const list = h("ol#log-list");
  const count = h("span.count");
  const pane = h("section#log-pane",
    h("div.log-bar",
      h("button#log-toggle", { onclick: () => pane.classList.toggle("collapsed") }, "Log"),
      level, module, count),
    list);

  function passes(r) {
    return LEVELS.indexOf(r.level) >= LEVELS.indexOf(level.value) && (!module.value || r.module === module.value);
  }
  function row(r) {
    return h(`li.level-${r.level.toLowerCase()}`, h("time", clock(r.time)), h("span.lvl", r.level), h("span.mod", r.module), h("span.msg", r.message));
  }
  function render() {
    const shown = records.filter(passes).slice(-300);
    replace(list, shown.map(row));
    count.textContent = `${shown.length} shown`;
    list.scrollTop = list.scrollHeight;
  }
  function fillModules() {
    const names = new Set([...state.modules.keys(), ...records.map((r) => r.module)]);
    const chosen = module.value;
    replace(module, h("option", { value: "" }, "all modules"), [...names].sort().map((n) => h("option", { value: n }, n)));
    module.value = chosen;
  }
  disposers.push(on("log", (r) => {
    records.push(r);
    if (records.length > KEEP) records.splice(0, records.length - KEEP);
    if (!passes(r)) return;
    const atEnd = list.scrollTop + list.clientHeight >= list.scrollHeight - 4;
    list.append(row(r));
    while (list.childElementCount > 300) list.firstElementChild.remove();
    if (atEnd) list.scrollTop = list.scrollHeight;
    if (![...module.options].some((o) => o.value === r.module)) fillModules();
  }));
  disposers.push(on("hello", async () => {
    try {
      const data = await api.get("/api/log?limit=300");
      records.splice(0, records.length, ...data.records);
      fillModules();
      render();
    } catch {
      /* the pane stays as it was; the next records still arrive */
    }
  }));
  disposers.push(watchModules(fillModules));
  return pane;
}
