// Incoming events: the JSON text of an `<event>` as an instance of its generated class, checked
// against the catalogue's schema (unknown fields are ignored, as protocol.md section 5 asks).
import { EVENTS, EVENT_SCHEMAS } from "../generated/events.js";
import { isDateTime, schemaProblem } from "./schema.js";
import { parseWireDate } from "./xmlrpc.js";

/**
 * The event `name` carried as `text`: `{event}`, or `{problem}` saying why it cannot be used.
 * @param {string} name
 * @param {string} text
 * @returns {{event: import("./event.js").Event} | {problem: string}}
 */
export function decodeEvent(name, text) {
  if (!Object.hasOwn(EVENTS, name)) return { problem: "an event the catalogue does not have" };
  let fields;
  try {
    fields = JSON.parse(text);
  } catch (error) {
    return { problem: `not JSON (${error.message})` };
  }
  const problem = schemaProblem(fields, { $ref: `#/$defs/${name}` }, EVENT_SCHEMAS);
  if (problem) return { problem };
  for (const [field, schema] of Object.entries(EVENT_SCHEMAS[name].properties ?? {})) {
    if (isDateTime(schema) && typeof fields[field] === "string") {
      fields[field] = parseWireDate(fields[field]);
    }
  }
  return { event: new EVENTS[name](fields) };
}
