// Every method the module's interfaces offer, each with a form for its parameters: the page's
// catch-all, so nothing an interface offers is out of reach even without a dedicated widget.

import * as api from "../api.js";
import { h, show } from "../dom.js";

/** An input for one parameter: a select for choices and booleans, a text field otherwise. */
export function paramInput(param, idPrefix = "") {
  const id = `${idPrefix}${param.name}`;
  let input;
  if (param.choices) {
    input = h("select", { id, name: param.name },
      param.required ? null : h("option", { value: "" }, "(default)"),
      param.choices.map((c) => h("option", { value: c }, c)));
  } else if (param.type === "bool") {
    input = h("select", { id, name: param.name }, h("option", { value: "true" }, "True"), h("option", { value: "false" }, "False"));
    if (param.default === false) input.value = "false";
  } else {
    input = h("input", { id, name: param.name, placeholder: param.required ? param.type : `${param.type} = ${show(param.default)}` });
  }
  return input;
}

/** A parameter's value from its input: JSON where it parses ("2.5", "[1, 2]", "null"), else text. */
export function paramValue(param, input) {
  const text = input.value.trim();
  if (text === "" && !param.required) return undefined;
  if (param.choices) return text;
  if (param.type === "bool") return text === "true";
  if (param.type === "str" || param.type === "str | None") return text;
  try {
    return JSON.parse(text);
  } catch {
    return text;
  }
}

export function methodsCard(ctx) {
  const names = Object.keys(ctx.module.methods || {}).sort();
  return h("details.card.methods", { dataset: { widget: "methods" } },
    h("summary", h("strong", "Methods"), ` — all ${names.length} of ${ctx.module.interfaces.length} interfaces, each with a form`),
    names.map((name) => methodRow(ctx, name, ctx.module.methods[name])));
}

function methodRow(ctx, name, method) {
  const inputs = method.params.map((p) => [p, paramInput(p, `m-${name}-`)]);
  const output = h("output.result");
  const button = h("button", { type: "submit" }, "Call");
  button.disabled = !ctx.can(name);
  if (button.disabled) button.title = "viewers may not call this";
  const form = h("form.method", {
    dataset: { method: name },
    onsubmit: async (event) => {
      event.preventDefault();
      const args = {};
      for (const [p, input] of inputs) {
        const value = paramValue(p, input);
        if (value !== undefined) args[p.name] = value;
      }
      output.className = "result";
      output.textContent = "…";
      try {
        const result = await api.call(ctx.name, name, args);
        output.textContent = `→ ${show(result)}`;
      } catch (exc) {
        output.className = "result error";
        output.textContent = exc.describe();
      }
    },
  },
  inputs.map(([p, input]) => h("label", p.name, input)),
  button, output);
  return h("details.method",
    h("summary", h("code", name), h("span.iface", method.interface), h("span.doc", method.doc)),
    form);
}
