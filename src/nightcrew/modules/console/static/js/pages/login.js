// The login form: user and password; errors as the server words them (no hint which part was wrong).

import * as api from "../api.js";
import { h } from "../dom.js";

export function loginPage(title, loggedIn) {
  const user = h("input#login-user", { name: "user", autocomplete: "username", required: true, autofocus: true });
  const password = h("input#login-password", { name: "password", type: "password", autocomplete: "current-password", required: true });
  const message = h("p#login-error.error", { role: "alert" });
  const button = h("button#login-submit", { type: "submit" }, "Log in");
  const form = h("form#login", {
    onsubmit: async (event) => {
      event.preventDefault();
      message.textContent = "";
      button.disabled = true;
      try {
        loggedIn(await api.post("/api/login", { user: user.value, password: password.value }));
      } catch (exc) {
        message.textContent = exc.message;
        password.value = "";
        password.focus();
      } finally {
        button.disabled = false;
      }
    },
  },
  h("h1", title),
  h("label", "User", user),
  h("label", "Password", password),
  button,
  message);
  return h("div.login-page", form);
}
