// What a widget on a module page gets: calls that report their errors, a shared poller of read
// methods (one /api/read per second for the whole page), live subscriptions and clean-up.

import * as api from "../api.js";
import { h } from "../dom.js";
import { on } from "../live.js";
import { mayCall, offers } from "../store.js";

export const POLL_MS = 1000;

export function makeContext(module) {
  const disposers = [];
  const reads = []; // {calls: [{module, method, args}], callback}
  let timer = null;
  let stopped = false;

  async function pollOnce() {
    const calls = reads.flatMap((r) => r.calls);
    if (!calls.length || stopped) return;
    let results;
    try {
      results = await api.read(calls);
    } catch {
      return; // offline or logged out: the banner and the module list say so
    }
    let i = 0;
    for (const r of reads) {
      const part = results.slice(i, i + r.calls.length);
      i += r.calls.length;
      try {
        r.callback(part.map((x) => ("result" in x ? x.result : undefined)), part);
      } catch (exc) {
        console.error("console: widget update failed", exc);
      }
    }
  }
  async function loop() {
    await pollOnce();
    if (!stopped) timer = setTimeout(loop, POLL_MS);
  }

  const ctx = {
    module,
    name: module.name,
    offers: (iface) => offers(module, iface),
    has: (method) => Boolean(module.methods?.[method]),
    can: (method) => mayCall(module.name, method),
    /** Poll read methods [[method, args], ...] of this module; ``callback(values, raw)``. */
    poll(methods, callback) {
      const calls = methods.filter(([m]) => ctx.has(m)).map(([method, args = []]) => ({ module: module.name, method, args }));
      if (calls.length) reads.push({ calls, callback: (values, raw) => {
        const byName = {};
        calls.forEach((c, k) => (byName[c.method + (c.args.length ? JSON.stringify(c.args) : "")] = values[k]));
        callback(byName, raw);
      } });
    },
    /** Poll now (after an action) instead of waiting for the next tick. */
    refresh: () => pollOnce(),
    /** Subscribe to a WebSocket message type for as long as the page is open. */
    on(type, callback) {
      disposers.push(on(type, callback));
    },
    /** Events of one type (optionally from one sender) while the page is open. */
    onEvent(eventType, callback, sender = null) {
      disposers.push(on("event", (msg) => {
        if (msg.event === eventType && (!sender || msg.sender === sender)) callback(msg.fields, msg);
      }));
    },
    cleanup: (fn) => disposers.push(fn),
    /**
     * A button that calls ``method`` with ``args()`` and shows the outcome in ``message``;
     * disabled when the user may not call it (a viewer) or the module lacks the method.
     */
    action(label, method, args = () => [], { message = null, then = null, id = null } = {}) {
      const button = h("button", { id, dataset: { method } }, label);
      button.disabled = !ctx.has(method) || !ctx.can(method);
      if (!ctx.can(method)) button.title = "viewers may not call this";
      button.onclick = async () => {
        if (message) message.textContent = `${method}…`;
        button.classList.add("busy");
        try {
          const result = await api.call(module.name, method, await args());
          if (message) message.textContent = `${method}: done`;
          if (then) then(result);
        } catch (exc) {
          if (message) {
            message.textContent = exc.describe ? exc.describe() : String(exc);
            message.classList.add("error");
            setTimeout(() => message.classList.remove("error"), 8000);
          }
        } finally {
          button.classList.remove("busy");
          pollOnce();
        }
      };
      return button;
    },
    start() {
      loop();
    },
    dispose() {
      stopped = true;
      clearTimeout(timer);
      for (const fn of disposers) fn();
    },
  };
  return ctx;
}

/** A labelled read-out whose value a poll sets: returns [element, set(value)]. */
export function readout(label, id = null) {
  const value = h("output", { id }, "—");
  return [h("div.readout", h("span.label", label), value), (text) => (value.textContent = text)];
}

/** A titled card for a widget. */
export function card(title, ...children) {
  return h("section.card", { dataset: { widget: title.toLowerCase() } }, h("h3", title), ...children);
}

/** A message line under a card's buttons. */
export function messageLine() {
  return h("p.message", { role: "status" });
}
