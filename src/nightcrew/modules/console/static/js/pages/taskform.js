// Adding a task: a form for the common case (one target, one exposure series, one window), its
// bounds and defaults taken from the request format's JSON Schema, and a box for a whole request
// group in YAML or JSON (as in a file for `nightcrew tasks add`). The server validates either with
// the same model; each problem it names is shown at its field.

import * as api from "../api.js";
import { h, replace } from "../dom.js";
import { isOperator } from "../store.js";

const R = "requests[0]";
const C = `${R}.configurations[0]`;
const I = `${C}.instrument_configs[0]`;
// [id, label, path in the request group, [schema definition, property]]
const FIELDS = [
  ["name", "Name", "name", ["RequestGroup", "name"]],
  ["proposal", "Proposal", "proposal", ["RequestGroup", "proposal"]],
  ["priority", "Priority", "priority", ["RequestGroup", "priority"]],
  ["telescope-class", "Telescope class", `${R}.location.telescope_class`, ["Location", "telescope_class"]],
  ["window-start", "Window from (UTC)", `${R}.windows[0].start`, ["Window", "start"]],
  ["window-end", "to (UTC)", `${R}.windows[0].end`, ["Window", "end"]],
  ["target", "Target", `${C}.target.name`, ["Target", "name"]],
  ["ra", "RA [°]", `${C}.target.ra`, ["Target", "ra"]],
  ["dec", "Dec [°]", `${C}.target.dec`, ["Target", "dec"]],
  ["exposure-time", "Exposure [s]", `${I}.exposure_time`, ["InstrumentConfig", "exposure_time"]],
  ["exposure-count", "Exposures", `${I}.exposure_count`, ["InstrumentConfig", "exposure_count"]],
  ["filter", "Filter", `${I}.optical_elements.filter`, null],
  ["max-airmass", "Max airmass", `${C}.constraints.max_airmass`, ["Constraints", "max_airmass"]],
  ["min-lunar-distance", "Min Moon distance [°]", `${C}.constraints.min_lunar_distance`, ["Constraints", "min_lunar_distance"]],
];

/** The property's schema, the nullable branch unwrapped; whether the definition requires it. */
function propertyOf(schema, [definition, property]) {
  const def = schema.$defs?.[definition] || (schema.title === definition ? schema : {});
  let prop = def.properties?.[property] || {};
  if (prop.anyOf) prop = prop.anyOf.find((branch) => branch.type !== "null") || prop;
  return [prop, (def.required || []).includes(property)];
}

function inputFor(id, schema, where) {
  if (!where) return h("input", { id: `task-${id}`, type: "text", placeholder: "optional" });
  const [prop, required] = propertyOf(schema, where);
  const attrs = { id: `task-${id}`, required, title: prop.description || prop.title || "" };
  if (prop.type === "number" || prop.type === "integer") {
    Object.assign(attrs, { type: "number", step: prop.type === "integer" ? 1 : "any", min: prop.minimum, max: prop.maximum });
    if (prop.exclusiveMinimum !== undefined) attrs.dataset = { exclusiveMinimum: prop.exclusiveMinimum };
  } else if (prop.format === "date-time") {
    attrs.type = "datetime-local";
  } else {
    Object.assign(attrs, { type: "text", minlength: prop.minLength, maxlength: prop.maxLength });
  }
  const input = h("input", attrs);
  if (prop.default !== undefined && prop.default !== null) input.value = prop.default;
  return input;
}

/** Set ``path`` (``requests[0].windows[0].start``) in ``target`` to ``value``. */
function setPath(target, path, value) {
  const keys = path.match(/[^.[\]]+/g).map((k) => (/^\d+$/.test(k) ? Number(k) : k));
  let node = target;
  keys.slice(0, -1).forEach((key, i) => {
    node[key] ??= typeof keys[i + 1] === "number" ? [] : {};
    node = node[key];
  });
  node[keys.at(-1)] = value;
}

const utcInput = (date) => date.toISOString().slice(0, 16);

/** The form; ``added(body)`` is called after the server stored a group. Returns {element, prefill}. */
export function taskForm(added) {
  const fields = h("div#task-fields.form-grid");
  const problems = h("ul#task-problems.problems");
  const message = h("p#task-message.message", { role: "status" });
  const raw = h("textarea#task-raw-text", { rows: 12, spellcheck: false, placeholder: "name: M31\nproposal: ...\nrequests: ..." });
  const inputs = new Map(); // path → input
  let schema = null;
  let wanted = null; // what prefill() was given, applied once the fields exist

  function show(error) {
    message.className = "message error";
    message.textContent = error.describe ? error.describe() : error.message;
    const unplaced = [];
    for (const problem of error.problems || []) {
      const input = inputs.get(problem.path);
      if (input) mark(input, problem.message);
      else unplaced.push(problem);
    }
    replace(problems, unplaced.map((p) => h("li", { dataset: { path: p.path } }, p.path ? `${p.path}: ${p.message}` : p.message)));
  }
  function mark(input, text) {
    input.setAttribute("aria-invalid", "true");
    input.closest("label").querySelector(".field-error").textContent = text;
  }
  function clear() {
    replace(problems);
    message.className = "message";
    message.textContent = "";
    for (const input of inputs.values()) {
      input.removeAttribute("aria-invalid");
      input.closest("label").querySelector(".field-error").textContent = "";
    }
  }
  /** The group the form describes; with ``check``, null (the fields marked) when a field breaks the schema. */
  function group(check = true) {
    const result = {};
    let valid = true;
    for (const [path, input] of inputs) {
      const floor = input.dataset.exclusiveMinimum;
      input.setCustomValidity(floor !== undefined && input.value !== "" && !(Number(input.value) > Number(floor)) ? `must be > ${floor}` : "");
      if (check && !input.checkValidity()) {
        mark(input, input.validationMessage);
        valid = false;
      }
      if (input.value === "") continue;
      const value = input.type === "number" ? Number(input.value) : input.type === "datetime-local" ? `${input.value}:00Z` : input.value;
      setPath(result, path, value);
    }
    setPath(result, `${C}.type`, "EXPOSE");
    return valid ? result : null;
  }
  async function submit(send) {
    clear();
    try {
      const body = await send();
      if (!body) return;
      const ids = body.tasks.map((t) => t.id).join(", ");
      message.textContent = `added “${body.tasks[0].name}”: task ${ids}`;
      added(body);
    } catch (exc) {
      show(exc);
    }
  }

  const form = h("form#task-form", {
    novalidate: true,
    onsubmit: (event) => {
      event.preventDefault();
      submit(async () => {
        const data = group();
        if (!data) throw new Error("the form has fields out of bounds (marked)");
        return api.post("/api/tasks", data);
      });
    },
  }, fields, h("button#task-add", { type: "submit", disabled: !isOperator() }, "Add task"));
  const rawBox = h("details#task-raw",
    h("summary", "A whole request group in YAML or JSON (several requests, configurations, windows)"),
    raw,
    h("div.buttons",
      h("button#task-raw-add", { type: "button", disabled: !isOperator(), onclick: () => submit(() => api.postText("/api/tasks", raw.value, "application/yaml")) }, "Add from text"),
      h("button#task-raw-from-form", { type: "button", onclick: () => (raw.value = JSON.stringify(group(false), null, 2)) }, "Start from the form")));

  api.get("/api/tasks/schema").then((loaded) => {
    schema = loaded;
    replace(fields, FIELDS.map(([id, label, path, where]) => {
      const input = inputFor(id, schema, where);
      input.disabled = !isOperator();
      inputs.set(path, input);
      return h("label", { dataset: { path } }, label, input, h("small.field-error"));
    }));
    applyPrefill();
  }).catch((exc) => show(exc));

  const element = h("details.card#task-add-card", { open: isOperator() },
    h("summary", isOperator() ? "Add a task" : "Add a task (operators only)"),
    h("p.hint", "One target, one exposure series, one window; the defaults and bounds are the request format's. The Moon distance and airmass limits keep a target out of the plan: check them."),
    form, rawBox, problems, message);
  function applyPrefill() {
    if (!wanted || !inputs.size) return;
    const set = (path, value) => {
      const input = inputs.get(path);
      if (input && !input.value && value) input.value = value;
    };
    const start = new Date(wanted.now);
    set(`${R}.windows[0].start`, utcInput(start));
    set(`${R}.windows[0].end`, utcInput(new Date(start.getTime() + 12 * 3600 * 1000)));
    set(`${R}.location.telescope_class`, wanted.telescopeClass);
  }
  /** Fill the empty window (12 h from ``now``, clock time) and telescope class (the newest task's). */
  function prefill(now, telescopeClass) {
    wanted = { now, telescopeClass };
    applyPrefill();
  }
  return { element, prefill };
}
