// The console's HTTP API (docs/console-api.md): JSON in and out, the CSRF token on every POST,
// and one error type carrying the server's {class, message, module}.

let csrfToken = "";

export class ApiError extends Error {
  constructor(status, body) {
    const error = body?.error || {};
    super(error.message || `HTTP ${status}`);
    this.status = status;
    this.errorClass = error.class || `HTTP ${status}`;
    this.module = error.module || null;
    this.problems = error.problems || []; // [{path, message}] of an invalid request group
  }
  /** "MoveError from telescope: ..." — what a person needs to see. */
  describe() {
    return `${this.errorClass}${this.module ? ` from ${this.module}` : ""}: ${this.message}`;
  }
}

export function setCsrfToken(token) {
  csrfToken = token || "";
}

async function request(method, path, body, contentType = "application/json") {
  const headers = { Accept: "application/json" };
  if (method !== "GET") {
    headers["Content-Type"] = contentType;
    headers["X-CSRF-Token"] = csrfToken;
  }
  const sent = body === undefined || contentType !== "application/json" ? body : JSON.stringify(body);
  let response;
  try {
    response = await fetch(path, { method, headers, body: sent, credentials: "same-origin" });
  } catch (exc) {
    throw new ApiError(0, { error: { class: "NetworkError", message: `the console cannot be reached (${exc.message})` } });
  }
  const text = await response.text();
  let data = null;
  try {
    data = text ? JSON.parse(text) : null;
  } catch {
    data = { error: { class: `HTTP ${response.status}`, message: text.slice(0, 200) } };
  }
  if (!response.ok) {
    const error = new ApiError(response.status, data);
    if (response.status === 401 && path !== "/api/login" && path !== "/api/session") onLoggedOut(error);
    throw error;
  }
  return data;
}

let onLoggedOut = () => {};
/** What to do when a request finds the session gone (the app shows the login page). */
export function whenLoggedOut(callback) {
  onLoggedOut = callback;
}

export const get = (path) => request("GET", path);
export const post = (path, body) => request("POST", path, body ?? {});
/** POST a text body as it is (e.g. YAML with ``application/yaml``). */
export const postText = (path, text, contentType) => request("POST", path, text, contentType);

/** Call ``module.method`` with positional (list) or named (object) arguments; returns the result. */
export async function call(module, method, args = []) {
  return (await post("/api/call", { module, method, args })).result;
}

/** Several read methods at once: [{module, method, args}] → [{result} | {error}]. */
export async function read(calls) {
  if (!calls.length) return [];
  return (await post("/api/read", { calls })).results;
}
