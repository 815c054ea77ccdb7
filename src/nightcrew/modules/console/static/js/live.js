// The WebSocket to /api/ws: dispatches messages by type, reconnects with back-off when it drops,
// and shows a banner while it is away and when it is back.

import { h } from "./dom.js";

const listeners = new Map(); // type → Set(callback)
let socket = null;
let wanted = false;
let attempts = 0;
let retryTimer = null;
let banner = null;
let onSessionEnded = () => {};

/** Call ``callback(message)`` for every message of ``type``; returns a function that unsubscribes. */
export function on(type, callback) {
  if (!listeners.has(type)) listeners.set(type, new Set());
  listeners.get(type).add(callback);
  return () => listeners.get(type)?.delete(callback);
}

function dispatch(message) {
  for (const callback of listeners.get(message.type) || []) {
    try {
      callback(message);
    } catch (exc) {
      console.error(`console: handler of ${message.type} failed`, exc);
    }
  }
}

/** Open the socket and keep it open until ``disconnect``; ``sessionEnded`` runs on close code 4401. */
export function connect(sessionEnded) {
  onSessionEnded = sessionEnded;
  wanted = true;
  open();
}

export function disconnect() {
  wanted = false;
  clearTimeout(retryTimer);
  if (socket) socket.close(1000);
  socket = null;
  showBanner(null);
}

/** Whether the socket is open now (tests and the status line read this). */
export function isConnected() {
  return socket?.readyState === WebSocket.OPEN;
}

function open() {
  const url = `${location.protocol === "https:" ? "wss" : "ws"}://${location.host}/api/ws`;
  const ws = new WebSocket(url);
  socket = ws;
  ws.onopen = () => {
    if (attempts > 0) showBanner("reconnected", "The live connection is back; the pages are up to date again.");
    attempts = 0;
    document.body.dataset.live = "open";
  };
  ws.onmessage = (msg) => {
    let message;
    try {
      message = JSON.parse(msg.data);
    } catch {
      return;
    }
    dispatch(message);
  };
  ws.onclose = (event) => {
    if (socket !== ws) return;
    socket = null;
    document.body.dataset.live = "closed";
    if (!wanted) return;
    if (event.code === 4401) {
      wanted = false;
      onSessionEnded();
      return;
    }
    attempts++;
    const delay = Math.min(10000, 500 * 2 ** Math.min(attempts - 1, 5));
    showBanner("lost", `Live connection lost — reconnecting (attempt ${attempts})…`);
    retryTimer = setTimeout(open, delay);
  };
}

function showBanner(kind, text) {
  if (!banner) banner = h("div#live-banner", { role: "status", "aria-live": "polite" });
  if (!banner.isConnected) document.body.append(banner); // the frame replaces the body's children
  clearTimeout(banner.hideTimer);
  banner.className = kind ? `banner-${kind}` : "";
  banner.hidden = !kind;
  banner.textContent = text || "";
  if (kind === "reconnected") banner.hideTimer = setTimeout(() => (banner.hidden = true), 4000);
}
