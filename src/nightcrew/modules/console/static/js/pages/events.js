// Events: the live list (filtered by type and sender), and a form to send an event with its fields.

import * as api from "../api.js";
import { clock, h, replace, show } from "../dom.js";
import { on } from "../live.js";
import { isOperator } from "../store.js";
import { paramInput, paramValue } from "../widgets/methods.js";

const KEEP = 2000;
const SHOW = 300;

export function eventsPage(container) {
  const events = [];
  let total = 0; // received since the page opened (the list keeps the last KEEP)
  const typeFilter = h("select#events-type", { "aria-label": "event type", onchange: render }, h("option", { value: "" }, "all types"));
  const senderFilter = h("select#events-sender", { "aria-label": "sender", onchange: render }, h("option", { value: "" }, "all senders"));
  const list = h("ol#events-list");
  const counter = h("span#events-count.count");
  const types = new Set();
  const senders = new Set();

  const passes = (e) => (!typeFilter.value || e.event === typeFilter.value) && (!senderFilter.value || e.sender === senderFilter.value);
  const row = (e) => h("li", { dataset: { event: e.event, sender: e.sender } },
    h("time", clock(e.time)), h("span.type", e.event), h("span.sender", e.sender),
    h("span.fields", Object.entries(e.fields).map(([k, v]) => `${k}=${show(v)}`).join("  ")));
  function render() {
    const shown = events.filter(passes).slice(-SHOW).reverse();
    replace(list, shown.map(row));
    counter.textContent = `${total} received live, ${shown.length} shown`;
    pending.length = 0;
  }
  function options(select, values, label) {
    const chosen = select.value;
    replace(select, h("option", { value: "" }, label), [...values].sort().map((v) => h("option", { value: v }, v)));
    select.value = chosen;
  }
  function add(e) {
    total++;
    events.push(e);
    if (events.length > KEEP) events.splice(0, events.length - KEEP);
    if (!types.has(e.event)) {
      types.add(e.event);
      options(typeFilter, types, "all types");
    }
    if (!senders.has(e.sender)) {
      senders.add(e.sender);
      options(senderFilter, senders, "all senders");
    }
  }
  // Many events a second: new rows go on top once per frame; only a filter change redraws all.
  const pending = [];
  let scheduled = false;
  function flush() {
    scheduled = false;
    const rows = pending.splice(0).filter(passes).slice(-SHOW).reverse().map(row);
    list.prepend(...rows);
    while (list.childElementCount > SHOW) list.lastElementChild.remove();
    counter.textContent = `${total} received live, ${list.childElementCount} shown`;
  }
  // The console dropped messages for this browser (it fell behind): say so, plainly.
  const dropped = h("span#events-dropped.error");
  const stopDropped = on("dropped", (msg) => (dropped.textContent = `${msg.count} live messages were dropped: this browser fell behind`));
  const stopEvents = on("event", (e) => {
    add(e);
    pending.push(e);
    if (scheduled) return;
    scheduled = true;
    requestAnimationFrame(flush);
  });
  api.get(`/api/events/recent?limit=${SHOW}`).then((r) => {
    events.unshift(...r.events.filter((e) => !events.some((x) => x.time === e.time && x.event === e.event && x.sender === e.sender)));
    for (const e of r.events) {
      types.add(e.event);
      senders.add(e.sender);
    }
    options(typeFilter, types, "all types");
    options(senderFilter, senders, "all senders");
    render();
  }).catch(() => {});

  container.append(h("section.events",
    h("h2", "Events"),
    h("div.controls", typeFilter, senderFilter, counter, dropped),
    sendForm(),
    list));
  return () => {
    stopEvents();
    stopDropped();
  };
}

function sendForm() {
  const type = h("select#send-type", { "aria-label": "event to send" });
  const fields = h("div#send-fields.form-grid");
  const message = h("p#send-message.message", { role: "status" });
  const button = h("button#send-event", { type: "submit" }, "Send");
  let described = {};
  let inputs = [];
  function showFields() {
    const fieldsOf = described[type.value]?.fields || [];
    inputs = fieldsOf.map((f) => [f, paramInput(f, "send-field-")]);
    replace(fields, inputs.map(([f, input]) => h("label", `${f.name} `, input)));
  }
  type.onchange = showFields;
  api.get("/api/events/types").then((r) => {
    described = r.types;
    replace(type, Object.keys(described).sort().map((t) => h("option", { value: t }, t)));
    // Not BadWeatherEvent (first by name): a careless Send would close the roof.
    if ("TestEvent" in described) type.value = "TestEvent";
    showFields();
  }).catch(() => {});
  button.disabled = !isOperator();
  const form = h("form#send-form", {
    onsubmit: async (event) => {
      event.preventDefault();
      const values = {};
      for (const [f, input] of inputs) {
        const v = paramValue(f, input);
        if (v !== undefined) values[f.name] = v;
      }
      message.className = "message";
      try {
        await api.post("/api/events", { type: type.value, fields: values });
        message.textContent = `${type.value} sent`;
      } catch (exc) {
        message.className = "message error";
        message.textContent = exc.describe();
      }
    },
  }, h("label", "Send ", type), fields, button, message);
  return h("details.send", { open: isOperator() }, h("summary", isOperator() ? "Send an event" : "Send an event (operators only)"), form);
}
