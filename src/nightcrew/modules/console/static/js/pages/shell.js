// The Shell: type ``module.method(args)``, Tab completes modules, methods and parameter values,
// Up/Down walk the history (kept in this browser), results and remote errors are shown clearly.

import * as api from "../api.js";
import { h, show } from "../dom.js";
import { complete, signature } from "../shellcomplete.js";
import { state } from "../store.js";

const HISTORY_KEY = "nightcrew.shell.history";

export function shellPage(container) {
  const history = JSON.parse(localStorage.getItem(HISTORY_KEY) || "[]");
  let position = history.length;
  const output = h("ol#shell-output", { "aria-live": "polite" });
  const input = h("input#shell-input", { autocomplete: "off", spellcheck: false, placeholder: "camera.set_exposure_time(2.5)   (Tab completes)", "aria-label": "shell command" });
  const hint = h("div#shell-hint.hint");
  const suggestions = h("ul#shell-suggestions");
  const catalogue = () => Object.fromEntries([...state.modules.values()].map((m) => [m.name, m.methods || {}]));

  function suggest(apply) {
    const result = complete(input.value, input.selectionStart, catalogue());
    hint.textContent = result.hint || "";
    suggestions.replaceChildren(...result.items.slice(0, 30).map((item) =>
      h("li", { onclick: () => insert(result, item) }, h("code", item.label), h("span.detail", item.detail))));
    if (apply && result.items.length) {
      const common = commonPrefix(result.items.map((i) => i.insert));
      insert(result, result.items.length === 1 ? result.items[0] : { insert: common });
    }
  }
  function insert(result, item) {
    const before = input.value.slice(0, result.from);
    const after = input.value.slice(input.selectionStart);
    input.value = before + item.insert + after;
    const caret = before.length + item.insert.length;
    input.setSelectionRange(caret, caret);
    input.focus();
    suggest(false);
  }
  async function run() {
    const line = input.value.trim();
    if (!line) return;
    if (history.at(-1) !== line) history.push(line);
    localStorage.setItem(HISTORY_KEY, JSON.stringify(history.slice(-200)));
    position = history.length;
    input.value = "";
    suggestions.replaceChildren();
    hint.textContent = "";
    const result = h("div.result.pending", "…");
    const entry = h("li", h("code.line", `> ${line}`), result);
    output.append(entry);
    entry.scrollIntoView({ block: "end" });
    try {
      const reply = await api.post("/api/shell", { line });
      result.className = "result ok";
      result.textContent = reply.result === null ? "done (no result)" : show(reply.result, 8);
    } catch (exc) {
      result.className = "result error";
      result.replaceChildren(h("strong.error-class", exc.errorClass), exc.module ? ` from ${exc.module}` : "", `: ${exc.message}`);
    }
    entry.scrollIntoView({ block: "end" });
  }
  input.addEventListener("keydown", (event) => {
    if (event.key === "Tab") {
      event.preventDefault();
      suggest(true);
    } else if (event.key === "Enter") {
      event.preventDefault();
      run();
    } else if (event.key === "ArrowUp" && position > 0) {
      event.preventDefault();
      input.value = history[--position];
    } else if (event.key === "ArrowDown") {
      event.preventDefault();
      position = Math.min(history.length, position + 1);
      input.value = history[position] ?? "";
    }
  });
  input.addEventListener("input", () => suggest(false));
  const methodsHelp = h("details.help", h("summary", "What can I call?"),
    h("ul", [...state.modules.values()].map((m) => h("li", h("strong", m.name), ": ",
      Object.entries(m.methods || {}).sort().map(([n, meth]) => h("code", { title: meth.doc }, `${n}${signature(meth)}`)).flatMap((c) => [c, " "])))));
  container.append(h("section.shell",
    h("h2", "Shell"),
    h("p.hint", state.role === "viewer" ? "As a viewer you may call read methods only (get_…, is_…, list_…, …_status)." : "Arguments are positional Python literals: 2.5, 'object', True, [1, 2]."),
    output,
    h("form.shell-line", { onsubmit: (e) => { e.preventDefault(); run(); } }, h("span.prompt", ">"), input, h("button#shell-run", { type: "submit" }, "Run")),
    hint, suggestions, methodsHelp));
  input.focus();
}

function commonPrefix(words) {
  if (!words.length) return "";
  let prefix = words[0];
  for (const w of words) while (!w.startsWith(prefix)) prefix = prefix.slice(0, -1);
  return prefix;
}
