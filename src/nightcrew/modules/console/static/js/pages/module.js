// A module's page, built from what its interfaces offer: a card per widget that applies, the
// observatory's own widget if the config names one, and every method as a form.

import { h, replace } from "../dom.js";
import { state, watchModules } from "../store.js";
import { makeContext } from "../widgets/context.js";
import { methodsCard } from "../widgets/methods.js";
import { WIDGETS } from "../widgets/registry.js";

export function modulePage(container, name) {
  let ctx = null;
  let shownFor = null; // the module entry the cards were built for

  function build() {
    const module = state.modules.get(name);
    if (module === shownFor) return updateHeader(module);
    if (ctx) ctx.dispose();
    ctx = null;
    shownFor = module;
    if (!module) {
      replace(container, h("section.gone#module-gone",
        h("h2", name),
        h("p", `${name} is not online (it stopped or left). This page comes back when it returns.`)));
      return;
    }
    ctx = makeContext(module);
    const custom = state.config.widgets?.[name];
    replace(container,
      h("div.module-head",
        h("h2", module.label || name, h("small", ` ${name}`)),
        h("span#module-state.state", { dataset: { state: module.state } }, module.state),
        h("span#module-error.error", module.error || "")),
      h("p.interfaces", module.interfaces.join(" · ")),
      h("div.cards", WIDGETS.filter((w) => w.applies(ctx)).map((w) => w.build(ctx))),
      custom ? h("section.card.custom-widget",
        h("h3", custom.title || "Observatory widget"),
        h("iframe", { src: custom.url, title: custom.title || name, sandbox: "allow-scripts allow-same-origin allow-forms" })) : null,
      methodsCard(ctx));
    ctx.start();
  }
  function updateHeader(module) {
    const stateEl = container.querySelector("#module-state");
    if (!stateEl || !module) return;
    stateEl.textContent = module.state;
    stateEl.dataset.state = module.state;
    container.querySelector("#module-error").textContent = module.error || "";
  }
  const unwatch = watchModules(() => {
    const module = state.modules.get(name);
    // a new entry object (module_joined) rebuilds, a state change only updates the header
    if (module !== shownFor) build();
    else updateHeader(module);
  });
  build();
  return () => {
    unwatch();
    if (ctx) ctx.dispose();
  };
}
