// A nightcrew client over XMPP (docs/protocol.md): login, the room, discovery, calls, events.
// Hand-written and small; what the methods, parameters and events are comes from the generated
// files (clients/js/generated), never from here.
import { client as xmppClient, xml, jid as parseJid } from "@xmpp/client";

import {
  ERRORS,
  InterfaceError,
  InvalidArgumentError,
  RemoteError,
  RemoteTimeoutError,
  XmppAuthError,
} from "../generated/errors.js";
import { EVENT_SCHEMAS } from "../generated/events.js";
import { DEFAULT_TIMEOUT, INTERFACES } from "../generated/index.js";
import { decodeEvent } from "./decode.js";
import { combinedInterface } from "./remote.js";
import { schemaProblem } from "./schema.js";
import { methodCall, methodResponse, parseResponse } from "./xmlrpc.js";

const NS_RPC = "jabber:iq:rpc";
const NS_DISCO = "http://jabber.org/protocol/disco#info";
const NS_MUC = "http://jabber.org/protocol/muc";
const NS_MUC_USER = "http://jabber.org/protocol/muc#user";
const NS_TIMEOUT = "urn:nightcrew:rpc:timeout";
const NS_EVENT = "urn:nightcrew:event";
const NS_MODULE = "urn:nightcrew:module";
const INTERFACE_FEATURE = "urn:nightcrew:interface:";
/** Wall seconds added to every deadline for the network (as nightcrew's own XMPP comm does). */
const NETWORK_GRACE = 1.0;
const LOOPBACK = new Set(["127.0.0.1", "::1", "localhost"]);

/**
 * @typedef {object} ClientOptions
 * @property {string} jid           the client's account, `name@domain`; the name is its module name
 * @property {string} password
 * @property {string} [server]      `host:port` (default: the JID's domain, port 5222)
 * @property {string} [room]        the observatory's room: a name on `conference.<domain>`, or a JID
 * @property {string} [resource]
 * @property {(message: string) => void} [warn]  where skipped events and such are reported
 */

export class NightcrewClient {
  /** @param {ClientOptions} options */
  constructor({ jid, password, server, room = "nightcrew", resource = "nightcrew", warn }) {
    const { local, domain } = parseJid(jid);
    if (!local) throw new InvalidArgumentError(`jid ${JSON.stringify(jid)} has no name (name@domain)`);
    this.name = local;
    this.domain = domain;
    this._password = password;
    this._server = server ?? `${domain}:5222`;
    this._room = room.includes("@") ? room : `${room}@conference.${domain}`;
    this._resource = resource;
    this._warn = warn ?? ((message) => console.warn(`nightcrew-client: ${message}`));
    /** @type {Map<string, {jid: string, state: string}>} occupants of the room, by module name */
    this._occupants = new Map();
    /** @type {Map<string, object>} calls in flight, by iq id */
    this._pending = new Map();
    /** @type {Map<string, Set<Function>>} event handlers, by event name */
    this._handlers = new Map();
    /** @type {Set<Function>} waiters woken by every change of the room */
    this._roomWaiters = new Set();
    /** @type {Map<string, number>} clock speed of each module, asked once */
    this._speeds = new Map();
    this._idPrefix = `js-${Math.random().toString(16).slice(2, 10)}`;
    this._counter = 0;
    this._xmpp = null;
    /** @type {RemoteError|null} why the room refused us, if it did */
    this._joinError = null;
  }

  /** Names of the modules in the room now (this client excluded), sorted. */
  get modules() {
    return [...this._occupants.keys()].filter((name) => name !== this.name).sort();
  }

  /**
   * Log in (SCRAM only; TLS whenever offered and always off loopback) and join the room.
   * @param {number} [timeoutSeconds] wall seconds for the login and the join
   */
  async connect(timeoutSeconds = 30) {
    const [host, port = "5222"] = this._server.split(/:(?=\d+$)/);
    const secureRequired = !LOOPBACK.has(host);
    const xmpp = xmppClient({
      service: `xmpp://${host}:${port}`,
      domain: this.domain,
      resource: this._resource,
      // Each step of the login (stream open, STARTTLS, SASL, bind) may take this long; the
      // library's own 2 s fail on a busy machine.
      timeout: timeoutSeconds * 1000,
      credentials: async (authenticate, mechanisms, _fast, entity) => {
        const scram = mechanisms.find((mechanism) => mechanism.startsWith("SCRAM-"));
        if (!scram) throw new XmppAuthError(`the server offers no SCRAM login (offers ${mechanisms.join(", ")})`);
        if (secureRequired && !entity.isSecure()) {
          throw new XmppAuthError(`refusing to log in to ${host} without TLS`);
        }
        await authenticate({ username: this.name, password: this._password }, scram);
      },
    });
    xmpp.reconnect.stop(); // a lost session fails its calls; the user makes a new client
    xmpp.on("error", (error) => this._warn(`XMPP: ${error.message}`));
    xmpp.on("stanza", (stanza) => this._onStanza(stanza));
    xmpp.on("offline", () => this._failAll(new RemoteError("the XMPP session ended")));
    this._serve(xmpp);
    this._xmpp = xmpp;
    try {
      await withDeadline(xmpp.start(), timeoutSeconds, `login to ${this._server}`);
    } catch (error) {
      if (error.condition === "not-authorized") {
        throw new XmppAuthError(`the server refused the login of ${this.name}@${this.domain}`);
      }
      throw error;
    }
    const inRoom = () => this._joinError || this._occupants.get(this.name)?.self;
    const joined = this._until(inRoom, timeoutSeconds, `join ${this._room}`);
    await xmpp.send(
      xml(
        "presence",
        { to: `${this._room}/${this.name}` },
        xml("x", { xmlns: NS_MUC }, xml("history", { maxstanzas: "0" })),
        xml("status", {}, "ready"),
        xml("module", { xmlns: NS_MODULE, state: "ready" }),
      ),
    );
    await joined;
    if (this._joinError) throw this._joinError;
  }

  /** Leave the room and log out; safe to call twice. */
  async close() {
    const xmpp = this._xmpp;
    this._xmpp = null;
    this._failAll(new RemoteError("the client was closed"));
    if (xmpp) await xmpp.stop();
  }

  /**
   * Wait until every named module is in the room and announces state `ready` (bounded).
   * @param {Array<string>} names
   * @param {number} timeoutSeconds wall seconds
   */
  async waitUntilReady(names, timeoutSeconds) {
    const ready = () => names.every((name) => this._occupants.get(name)?.state === "ready");
    await this._until(ready, timeoutSeconds, `modules ${names.join(", ")} ready`);
  }

  /**
   * The interfaces a module serves, name → version (its disco#info features).
   * @param {string} module
   * @returns {Promise<Object<string, number>>}
   */
  async interfaces(module) {
    const query = await this._session.iqCaller.get(xml("query", { xmlns: NS_DISCO }), this._jidOf(module));
    const served = {};
    for (const feature of query.getChildren("feature")) {
      const variable = feature.attrs.var ?? "";
      if (variable.startsWith(INTERFACE_FEATURE)) {
        const [name, version] = variable.slice(INTERFACE_FEATURE.length).split(":");
        served[name] = Number(version);
      }
    }
    return served;
  }

  /**
   * A proxy for `module`, checked to serve every interface named (generated classes), with the
   * methods of all of them and of every other interface the module serves that the catalogue
   * knows (as nightcrew's own proxies: a camera's proxy has `set_exposure_time` of IExposureTime
   * beside ICamera's). It is an instance of the first interface named.
   * @template {typeof import("./remote.js").RemoteInterface} T
   * @param {string} module
   * @param {T} Interface
   * @param {...typeof import("./remote.js").RemoteInterface} more further interfaces it must serve
   * @returns {Promise<InstanceType<T>>}
   * @throws {RemoteError} the module is not in the room
   * @throws {InterfaceError} it does not serve one of them (in the version the catalogue has)
   */
  async proxy(module, Interface, ...more) {
    if (typeof Interface !== "function") throw new TypeError("proxy(module, Interface, ...more): name an interface");
    const served = await this.interfaces(module);
    const named = [Interface, ...more];
    const missing = named.filter(({ spec }) => served[spec.name] !== spec.version);
    if (missing.length > 0) {
      const offers = Object.keys(served).sort().join(", ");
      const what = missing.map(({ spec: { name, version } }) =>
        name in served ? `${name} version ${version} (it has ${served[name]})` : name,
      );
      throw new InterfaceError(`module '${module}' does not offer ${what.join(", ")} (offers: ${offers})`);
    }
    const others = Object.entries(served)
      .map(([name, version]) => INTERFACES[name]?.spec.version === version && INTERFACES[name])
      .filter((Other) => Other && !named.includes(Other));
    const Proxy = combinedInterface([...named, ...others]);
    return new Proxy(this, module);
  }

  /**
   * The module's clock: `{time: Date, speed: clock seconds per wall second}` (`system.clock`).
   * @param {string} module
   */
  async clock(module) {
    const clock = await this.call(module, "system.clock", []);
    this._speeds.set(module, clock.speed);
    return clock;
  }

  /**
   * Call `method` of `module` with checked arguments (the generated methods do this; use them).
   *
   * Waits the default 10 clock seconds, or as long as the module announces (section 4), in the
   * module's clock seconds converted to wall time with its clock speed, plus a network grace.
   * @param {string} module
   * @param {string} method
   * @param {Array<*>} args
   * @param {{params?: Array<object>, schemas?: Object<string, object>}} [declaration]
   */
  async call(module, method, args, { params = [], schemas = {} } = {}) {
    const session = this._session;
    const speed = method.startsWith("system.") ? 1 : await this._speed(module);
    const to = this._jidOf(module);
    const id = `${this._idPrefix}-${++this._counter}`;
    const query = xml("query", { xmlns: NS_RPC }, methodCall(method, args, params, schemas));
    const reply = new Promise((resolve, reject) => {
      const call = { module, method, to, speed, resolve, reject, timer: null };
      this._pending.set(id, call);
      this._extend(id, DEFAULT_TIMEOUT);
    });
    await session.send(xml("iq", { type: "set", id, to }, query));
    return reply;
  }

  /**
   * Call `handler(event, sender)` for every event of `EventClass` (a generated class) from others.
   * @template {typeof import("./event.js").Event} E
   * @param {E} EventClass
   * @param {(event: InstanceType<E>, sender: string) => void} handler
   * @returns {() => void} removes the handler
   */
  on(EventClass, handler) {
    const name = EventClass.eventName;
    if (!this._handlers.has(name)) this._handlers.set(name, new Set());
    this._handlers.get(name).add(handler);
    return () => this._handlers.get(name).delete(handler);
  }

  /**
   * Send an event to every module in the room (checked against its schema first).
   * @param {import("./event.js").Event} event
   */
  async send(event) {
    const name = event.constructor.eventName;
    const problem = schemaProblem(event.toJSON(), { $ref: `#/$defs/${name}` }, EVENT_SCHEMAS);
    if (problem) throw new InvalidArgumentError(`${name}: ${problem}`);
    await this._session.send(
      xml(
        "message",
        { type: "groupchat", to: this._room },
        xml("event", { xmlns: NS_EVENT, name }, JSON.stringify(event)),
        xml("no-store", { xmlns: "urn:xmpp:hints" }),
      ),
    );
  }

  async _speed(module) {
    if (!this._speeds.has(module)) await this.clock(module);
    return this._speeds.get(module);
  }

  /** The XMPP session; RemoteError before connect() and after close(). */
  get _session() {
    if (!this._xmpp) throw new RemoteError("the client is not connected (connect() first)");
    return this._xmpp;
  }

  _jidOf(module) {
    const occupant = this._occupants.get(module);
    if (!occupant || module === this.name) {
      const online = this.modules.join(", ") || "none";
      throw new RemoteError(`module '${module}' is not online (online: ${online})`);
    }
    return occupant.jid;
  }

  /** (Re)arm the deadline of call `id`: `clockSeconds` on the callee's clock from now. */
  _extend(id, clockSeconds) {
    const call = this._pending.get(id);
    clearTimeout(call.timer);
    const wallMs = (clockSeconds / call.speed + NETWORK_GRACE) * 1000;
    call.timer = setTimeout(() => {
      this._pending.delete(id);
      const message = `${call.module}.${call.method}() did not answer within ${clockSeconds} clock seconds`;
      call.reject(new RemoteTimeoutError(message));
    }, wallMs);
  }

  _settle(id, settle) {
    const call = this._pending.get(id);
    if (!call) return;
    this._pending.delete(id);
    clearTimeout(call.timer);
    settle(call);
  }

  _failAll(error) {
    for (const id of [...this._pending.keys()]) this._settle(id, (call) => call.reject(error));
  }

  /** Resolve once `condition()` holds (checked on every change of the room), or fail after a time. */
  _until(condition, timeoutSeconds, what) {
    if (condition()) return Promise.resolve();
    return new Promise((resolve, reject) => {
      const waiter = () => {
        if (!condition()) return;
        this._roomWaiters.delete(waiter);
        clearTimeout(timer);
        resolve();
      };
      const timer = setTimeout(() => {
        this._roomWaiters.delete(waiter);
        reject(new RemoteTimeoutError(`could not ${what} within ${timeoutSeconds} s`));
      }, timeoutSeconds * 1000);
      this._roomWaiters.add(waiter);
    });
  }

  _onStanza(stanza) {
    if (stanza.is("presence")) this._onPresence(stanza);
    else if (stanza.is("message")) this._onMessage(stanza);
    else if (stanza.is("iq") && ["result", "error"].includes(stanza.attrs.type)) this._onReply(stanza);
  }

  _onPresence(presence) {
    const [room, nick] = (presence.attrs.from ?? "").split("/");
    if (room !== this._room || !nick) return;
    const user = presence.getChild("x", NS_MUC_USER);
    if (presence.attrs.type === "error") {
      const condition = presence.getChild("error")?.children.find((c) => typeof c !== "string")?.name;
      // `conflict`: a module of this name is already in the room (protocol.md, section 2).
      this._joinError = new RemoteError(`cannot join ${this._room} as ${nick}: ${condition ?? "error"}`);
    } else if (presence.attrs.type === "unavailable") {
      const jid = this._occupants.get(nick)?.jid;
      this._occupants.delete(nick);
      for (const [id, call] of this._pending) {
        if (call.to === jid) this._settle(id, () => call.reject(new RemoteError(`module '${nick}' went offline`)));
      }
    } else {
      const known = this._occupants.get(nick);
      const jid = user?.getChild("item")?.attrs.jid ?? known?.jid;
      const state = presence.getChild("module", NS_MODULE)?.attrs.state ?? known?.state ?? "unknown";
      const self = user?.getChildren("status").some((status) => status.attrs.code === "110") || known?.self;
      this._occupants.set(nick, { jid, state, self: Boolean(self) });
    }
    for (const waiter of [...this._roomWaiters]) waiter();
  }

  _onMessage(message) {
    const timeout = message.getChild("timeout", NS_TIMEOUT);
    if (timeout) {
      const call = this._pending.get(timeout.attrs.id);
      // Only the module called may announce its call's timeout.
      if (call && call.to === message.attrs.from) this._extend(timeout.attrs.id, Number(timeout.attrs.seconds));
      return;
    }
    const element = message.getChild("event", NS_EVENT);
    const [room, sender] = (message.attrs.from ?? "").split("/");
    if (!element || room !== this._room || sender === this.name) return;
    const name = element.attrs.name;
    const handlers = this._handlers.get(name);
    if (!handlers?.size) return;
    const { event, problem } = decodeEvent(name, element.getText());
    if (problem) {
      this._warn(`skipped ${name} from ${sender}: ${problem}`);
      return;
    }
    for (const handler of handlers) handler(event, sender);
  }

  _onReply(iq) {
    const id = iq.attrs.id;
    if (!this._pending.has(id)) return;
    this._settle(id, (call) => {
      if (iq.attrs.type === "error") {
        const condition = iq.getChild("error")?.children.find((c) => typeof c !== "string")?.name;
        return call.reject(new RemoteError(`${call.module}.${call.method}() failed: ${condition ?? "error"}`));
      }
      const response = iq.getChild("query", NS_RPC)?.getChild("methodResponse");
      if (!response) return call.reject(new RemoteError(`${call.module}.${call.method}(): no methodResponse`));
      const { result, fault } = parseResponse(response);
      if (!fault) return call.resolve(result);
      const ErrorClass = ERRORS[fault.errorClass] ?? RemoteError;
      return call.reject(new ErrorClass(fault.faultString));
    });
  }

  /** What every member of a nightcrew network answers: disco#info, and calls to IModule. */
  _serve(xmpp) {
    xmpp.iqCallee.get(NS_DISCO, "query", () =>
      xml(
        "query",
        { xmlns: NS_DISCO },
        xml("identity", { category: "client", type: "bot" }),
        ...[NS_RPC, NS_TIMEOUT, NS_EVENT, `${INTERFACE_FEATURE}IModule:1`, NS_DISCO].map((v) =>
          xml("feature", { var: v }),
        ),
      ),
    );
    const answers = {
      get_label: () => this.name,
      get_version: () => "nightcrew-client (JavaScript)",
      get_state: () => "ready",
      get_error_string: () => "",
      reset_error: () => true,
    };
    xmpp.iqCallee.set(NS_RPC, "query", (ctx) => {
      const name = ctx.element.getChild("methodCall")?.getChildText("methodName") ?? "";
      const answer = answers[name];
      const fault = answer
        ? null
        : { errorClass: "InterfaceError", message: `no method '${name}' (methods: ${Object.keys(answers).join(", ")})` };
      return xml("query", { xmlns: NS_RPC }, methodResponse(answer ? answer() : null, fault));
    });
  }
}

function withDeadline(promise, seconds, what) {
  let timer;
  const deadline = new Promise((_, reject) => {
    timer = setTimeout(() => reject(new RemoteTimeoutError(`could not ${what} within ${seconds} s`)), seconds * 1000);
  });
  return Promise.race([promise, deadline]).finally(() => clearTimeout(timer));
}
