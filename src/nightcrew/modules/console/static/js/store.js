// What the console knows of the observatory: the online modules (from hello, module_joined,
// module_left and module_state), the user's role and the config. Pages subscribe to changes.

import { on } from "./live.js";

export const state = {
  config: {},
  user: null,
  role: "viewer",
  modules: new Map(), // name → entry as in GET /api/modules
};

const watchers = new Set();

/** Call ``callback()`` when the set of modules or one's state changes; returns an unsubscribe. */
export function watchModules(callback) {
  watchers.add(callback);
  return () => watchers.delete(callback);
}

function changed() {
  for (const callback of watchers) callback();
}

// When an entry arrived, so that uptimes count on from its uptime_s without asking again.
const stamp = (m) => Object.assign(m, { receivedAt: performance.now() });

export function setModules(list) {
  state.modules = new Map(list.map((m) => [m.name, stamp(m)]));
  changed();
}

/** Whether the user may call ``method`` of ``module`` (viewers only read methods). */
export function mayCall(module, method) {
  if (state.role === "operator") return true;
  return Boolean(state.modules.get(module)?.methods?.[method]?.read);
}

export function isOperator() {
  return state.role === "operator";
}

/** Whether the module offers an interface. */
export function offers(module, iface) {
  return Boolean(module?.interfaces?.includes(iface));
}

on("hello", (msg) => {
  state.user = msg.user;
  state.role = msg.role;
  setModules(msg.modules);
});
on("module_joined", (msg) => {
  state.modules.set(msg.module.name, stamp(msg.module));
  state.modules = new Map([...state.modules].sort(([a], [b]) => a.localeCompare(b)));
  changed();
});
on("module_left", (msg) => {
  state.modules.delete(msg.name);
  changed();
});
on("module_state", (msg) => {
  const module = state.modules.get(msg.name);
  if (!module) return;
  module.state = msg.state;
  module.error = msg.error;
  changed();
});
