// The base of the generated event classes: what travels is the event's own fields as a JSON object.

export class Event {
  /** The name the event travels under (the generated class sets it). */
  static eventName = "Event";

  /** The JSON object of the fields (dates as ISO 8601 strings, bytes as base64), as on the wire. */
  toJSON() {
    return Object.fromEntries(
      Object.entries(this)
        .filter(([, value]) => value !== undefined)
        .map(([name, value]) => [name, jsonValue(value)]),
    );
  }
}

function jsonValue(value) {
  if (value instanceof Date) return value.toISOString();
  if (value instanceof Uint8Array) return Buffer.from(value).toString("base64");
  return value;
}
