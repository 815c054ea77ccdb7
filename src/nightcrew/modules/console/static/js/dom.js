// Small DOM helpers: the console builds its pages from plain elements, without a framework.

/** Create an element: h("div.card#id", {onclick, title, ...}, child, "text", [more]). */
export function h(spec, attrs = {}, ...children) {
  const [, tag = "div", rest = ""] = spec.match(/^([a-z0-9-]*)(.*)$/i);
  const el = document.createElement(tag || "div");
  for (const part of rest.match(/[.#][^.#]+/g) || []) {
    if (part[0] === ".") el.classList.add(part.slice(1));
    else el.id = part.slice(1);
  }
  if (attrs === null || typeof attrs !== "object" || attrs instanceof Node || Array.isArray(attrs)) {
    children.unshift(attrs);
    attrs = {};
  }
  for (const [key, value] of Object.entries(attrs)) {
    if (value === undefined || value === null || value === false) continue;
    if (key.startsWith("on") && typeof value === "function") el.addEventListener(key.slice(2), value);
    else if (key === "dataset") Object.assign(el.dataset, value);
    else if (key === "style" && typeof value === "object") Object.assign(el.style, value);
    else if (key in el && typeof value !== "string") el[key] = value;
    else el.setAttribute(key, value === true ? "" : value);
  }
  append(el, children);
  return el;
}

function append(el, children) {
  for (const child of children.flat(Infinity)) {
    if (child === undefined || child === null || child === false) continue;
    el.append(child instanceof Node ? child : String(child));
  }
}

/** Replace all children of ``el``. */
export function replace(el, ...children) {
  el.replaceChildren();
  append(el, children);
  return el;
}

/** A value as people read it: numbers to a sensible precision, objects as compact JSON. */
export function show(value, digits = 4) {
  if (value === null || value === undefined) return "—";
  if (typeof value === "number") {
    if (!Number.isFinite(value)) return String(value);
    return Number.isInteger(value) ? String(value) : value.toPrecision(digits).replace(/\.?0+$/, "");
  }
  if (typeof value === "string") return value;
  return JSON.stringify(value);
}

/** Degrees as sexagesimal: hours for RA (``hours``), degrees otherwise. */
export function sexagesimal(degrees, hours = false) {
  if (degrees === null || degrees === undefined || !Number.isFinite(degrees)) return "—";
  const value = hours ? (((degrees % 360) + 360) % 360) / 15 : degrees;
  const sign = value < 0 ? "-" : hours ? "" : "+";
  // Round in the last shown digit first, so 59.999 s becomes the next minute, not "60.00".
  const digits = hours ? 2 : 1;
  const units = Math.round(Math.abs(value) * 3600 * 10 ** digits);
  const perMinute = 60 * 10 ** digits;
  const whole = Math.floor(units / (60 * perMinute));
  const minutes = Math.floor(units / perMinute) % 60;
  const seconds = (units % perMinute) / 10 ** digits;
  const pad = (n, w) => String(n).padStart(w, "0");
  const sec = seconds.toFixed(digits).padStart(digits + 3, "0");
  return `${sign}${pad(whole, 2)}${hours ? "h" : "°"}${pad(minutes, 2)}${hours ? "m" : "′"}${sec}${hours ? "s" : "″"}`;
}

/** Seconds as "1 d 02:03:04" / "02:03:04". */
export function duration(seconds) {
  if (!Number.isFinite(seconds)) return "—";
  const s = Math.max(0, Math.round(seconds));
  const d = Math.floor(s / 86400);
  const hms = [Math.floor(s / 3600) % 24, Math.floor(s / 60) % 60, s % 60]
    .map((n) => String(n).padStart(2, "0"))
    .join(":");
  return d ? `${d} d ${hms}` : hms;
}

/** A UTC time (ISO string or epoch seconds) as HH:MM:SS. */
export function clock(time) {
  if (time === null || time === undefined) return "—";
  const date = typeof time === "number" ? new Date(time * 1000) : new Date(time);
  return Number.isNaN(date.getTime()) ? String(time) : date.toISOString().slice(11, 19);
}
