// Status: every module's state, error string, version and uptime; reset an error.

import * as api from "../api.js";
import { duration, h, replace } from "../dom.js";
import { isOperator, state, watchModules } from "../store.js";

export function statusPage(container) {
  const body = h("tbody");
  const message = h("p#status-message.message", { role: "status" });
  function render() {
    replace(body, [...state.modules.values()].map((m) => {
      const reset = m.state === "error" ? h("button.reset", { dataset: { module: m.name } }, "Reset error") : "";
      if (reset) reset.disabled = !isOperator();
      if (reset) reset.onclick = async () => {
        message.className = "message";
        try {
          const ready = await api.call(m.name, "reset_error", []);
          message.textContent = `${m.name}: ${ready ? "error reset, ready again" : "still not ready"}`;
        } catch (exc) {
          message.className = "message error";
          message.textContent = exc.describe();
        }
      };
      return h("tr", { dataset: { module: m.name, state: m.state } },
        h("td", m.label && m.label !== m.name ? `${m.label} (${m.name})` : m.name),
        h("td.state", h("span.state", { dataset: { state: m.state } }, m.state)),
        h("td.error", m.error || ""),
        h("td", m.version || ""),
        h("td", duration((m.uptime_s ?? 0) + (performance.now() - m.receivedAt) / 1000)),
        h("td", reset));
    }));
  }
  // A module's uptime came with its entry; count on from there instead of asking again.
  const timer = setInterval(render, 5000);
  const unwatch = watchModules(render);
  container.append(h("section.status",
    h("h2", "Status"),
    h("table#status-table", h("thead", h("tr", ["module", "state", "error", "version", "uptime", ""].map((t) => h("th", t)))), body),
    message));
  render();
  return () => {
    clearInterval(timer);
    unwatch();
  };
}
