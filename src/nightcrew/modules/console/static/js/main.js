// The console's entry point: login, the frame (header, navigation, page, log pane) and the router.

import * as api from "./api.js";
import { h, replace } from "./dom.js";
import * as live from "./live.js";
import { isOperator, state, watchModules } from "./store.js";
import { loginPage } from "./pages/login.js";
import { logPane } from "./pages/log.js";
import { modulePage } from "./pages/module.js";
import { shellPage } from "./pages/shell.js";
import { eventsPage } from "./pages/events.js";
import { statusPage } from "./pages/status.js";
import { tasksPage } from "./pages/tasks.js";

let cleanup = () => {};
let frame = null;

async function boot() {
  try {
    state.config = await api.get("/api/config");
  } catch (exc) {
    document.body.replaceChildren(h("p.error", `The console cannot load its configuration: ${exc.message}`));
    return;
  }
  document.title = `${state.config.title || "nightcrew"} console`;
  api.whenLoggedOut(showLogin);
  try {
    started(await api.get("/api/session"));
  } catch {
    showLogin();
  }
}

function showLogin() {
  live.disconnect();
  cleanup();
  cleanup = () => {};
  for (const dispose of frame?.disposers || []) dispose();
  frame = null;
  document.body.replaceChildren(loginPage(state.config.title || "nightcrew", started));
}

function started(session) {
  api.setCsrfToken(session.csrf_token);
  state.user = session.user;
  state.role = session.role;
  document.body.dataset.role = session.role;
  buildFrame();
  live.connect(showLogin);
  route();
}

/** Which special pages the config shows, in menu order. */
function specialPages() {
  const c = state.config;
  return [
    c.show_tasks && ["tasks", "Tasks", tasksPage],
    c.show_shell !== false && ["shell", "Shell", shellPage],
    c.show_events !== false && ["events", "Events", eventsPage],
    c.show_status !== false && ["status", "Status", statusPage],
  ].filter(Boolean);
}

/** Whether a module gets a page: show_modules true (all), false (none) or a list of names. */
function showsModule(name) {
  const shown = state.config.show_modules;
  if (Array.isArray(shown)) return shown.includes(name);
  return shown !== false;
}

function buildFrame() {
  const moduleList = h("ul#module-list", { "aria-label": "modules" });
  const nav = h("nav#nav",
    state.config.show_modules === false ? null : h("h2", "Modules"),
    moduleList,
    h("h2", "Console"),
    h("ul#special-list", specialPages().map(([id, title]) => h("li", h(`a#nav-${id}`, { href: `#/${id}` }, title)))),
  );
  const logout = h("button#logout", {
    onclick: async () => {
      try {
        await api.post("/api/logout");
      } finally {
        showLogin();
      }
    },
  }, "Log out");
  frame = {
    page: h("main#page"),
    moduleList,
    disposers: [],
  };
  document.body.replaceChildren(
    h("header#top",
      h("button#menu-toggle", { "aria-label": "menu", onclick: () => document.body.classList.toggle("nav-open") }, "☰"),
      h("h1", state.config.title || "nightcrew"),
      h("span#live-dot", { title: "live connection" }),
      h("span.spacer"),
      h("span#whoami", `${state.user} (${state.role})`),
      logout),
    h("div#body", nav, frame.page),
    logPane(frame.disposers),
  );
  frame.disposers.push(watchModules(renderModuleList));
  renderModuleList();
  window.onhashchange = route;
}

function renderModuleList() {
  if (!frame) return;
  const current = location.hash;
  replace(frame.moduleList, [...state.modules.values()].filter((m) => showsModule(m.name)).map((m) =>
    h("li", { dataset: { module: m.name, state: m.state } },
      h("a", { href: `#/modules/${m.name}`, class: current === `#/modules/${m.name}` ? "current" : "" },
        h("span.state-dot", { title: m.state }), m.label || m.name))));
}

function route() {
  if (!frame) return;
  cleanup();
  cleanup = () => {};
  document.body.classList.remove("nav-open");
  const [, kind, name] = location.hash.match(/^#\/([^/]*)\/?(.*)$/) || [];
  const special = specialPages().find(([id]) => id === kind);
  frame.page.replaceChildren();
  for (const a of document.querySelectorAll("#nav a")) a.classList.toggle("current", a.getAttribute("href") === location.hash);
  if (special) {
    cleanup = special[2](frame.page) || cleanup;
  } else if (kind === "modules" && name && showsModule(decodeURIComponent(name))) {
    cleanup = modulePage(frame.page, decodeURIComponent(name)) || cleanup;
  } else {
    const first = [...state.modules.keys()].find(showsModule);
    frame.page.append(h("section.welcome",
      h("h2", "Welcome"),
      h("p", isOperator() ? "You may operate the observatory." : "You are a viewer: you see everything and call nothing."),
      h("p", first ? "Choose a module on the left." : "No module pages are shown here."),
    ));
  }
}

boot();
