// XML-RPC values, calls and responses as docs/protocol.md (section 4) has them, on @xmpp/xml elements.
// Encoding is guided by the JSON Schema of the parameter (a `number` travels as <double> even when
// its value is whole); decoding needs no schema.
import { xml } from "@xmpp/client";

const INT32 = 2 ** 31;

/**
 * Follow a local `$ref` (`#/components/schemas/X` or `#/$defs/X`) into `schemas`.
 * @param {object|undefined} schema
 * @param {Object<string, object>} schemas
 * @returns {object}
 */
export function resolveRef(schema, schemas) {
  let resolved = schema ?? {};
  for (let depth = 0; resolved.$ref && depth < 16; depth++) {
    resolved = schemas[resolved.$ref.split("/").pop()] ?? {};
  }
  return resolved;
}

/** The branch of an `anyOf` that fits a JavaScript value (by JSON type), else the schema itself. */
function branchFor(value, schema, schemas) {
  const resolved = resolveRef(schema, schemas);
  if (!resolved.anyOf) return resolved;
  const kind = value === null ? "null" : Array.isArray(value) ? "array" : typeof value;
  for (const option of resolved.anyOf.map((s) => resolveRef(s, schemas))) {
    const type = option.type ?? (option.enum ? typeof option.enum[0] : undefined);
    if (type === kind || (kind === "number" && type === "integer") || (kind === "object" && type === "string")) {
      return option;
    }
  }
  return resolved;
}

/**
 * One JavaScript value as an XML-RPC `<value>`.
 * @param {*} value
 * @param {object} [schema] JSON Schema of the value (guides number and date encoding)
 * @param {Object<string, object>} [schemas] the components its `$ref`s point into
 */
export function encodeValue(value, schema = {}, schemas = {}) {
  const fitting = branchFor(value, schema, schemas);
  if (value === null || value === undefined) return xml("value", {}, xml("nil"));
  if (typeof value === "boolean") return xml("value", {}, xml("boolean", {}, value ? "1" : "0"));
  if (typeof value === "number") return xml("value", {}, encodeNumber(value, fitting.type));
  if (typeof value === "string") return xml("value", {}, xml("string", {}, value));
  if (value instanceof Date) return xml("value", {}, xml("dateTime.iso8601", {}, wireDate(value)));
  if (value instanceof Uint8Array) {
    return xml("value", {}, xml("base64", {}, Buffer.from(value).toString("base64")));
  }
  if (Array.isArray(value)) {
    const items = value.map((item, index) =>
      encodeValue(item, fitting.prefixItems?.[index] ?? fitting.items, schemas),
    );
    return xml("value", {}, xml("array", {}, xml("data", {}, ...items)));
  }
  const members = Object.entries(value).map(([name, item]) => {
    const itemSchema = fitting.properties?.[name] ?? fitting.additionalProperties;
    return xml("member", {}, xml("name", {}, name), encodeValue(item, itemSchema, schemas));
  });
  return xml("value", {}, xml("struct", {}, ...members));
}

function encodeNumber(value, type) {
  if (!Number.isFinite(value)) {
    return xml("double", {}, Number.isNaN(value) ? "nan" : value > 0 ? "inf" : "-inf");
  }
  if (type === "number" || !Number.isInteger(value)) return xml("double", {}, String(value));
  return xml(Math.abs(value) < INT32 ? "int" : "i8", {}, String(value));
}

/** `YYYYMMDDTHH:MM:SS[.ffffff]`, UTC, as nightcrew writes date/times. */
function wireDate(date) {
  const iso = date.toISOString(); // 2026-11-10T17:50:00.123Z
  const millis = iso.slice(20, 23);
  const base = iso.slice(0, 10).replaceAll("-", "") + "T" + iso.slice(11, 19);
  return millis === "000" ? base : `${base}.${millis}000`;
}

/** A `<dateTime.iso8601>` text (basic or extended, optional fraction and zone; no zone = UTC). */
export function parseWireDate(text) {
  const match = /^(\d{4})-?(\d{2})-?(\d{2})T(\d{2}):?(\d{2}):?(\d{2})(\.\d+)?(Z|[+-]\d{2}:?\d{2})?$/.exec(text.trim());
  if (!match) throw new SyntaxError(`not an ISO 8601 date/time: ${JSON.stringify(text)}`);
  const [, y, mo, d, h, mi, s, fraction = "", zone = "Z"] = match;
  const offset = zone === "Z" ? "Z" : `${zone.slice(0, 3)}:${zone.slice(-2)}`;
  return new Date(`${y}-${mo}-${d}T${h}:${mi}:${s}${fraction.slice(0, 4)}${offset}`);
}

/**
 * An XML-RPC `<value>` element as a JavaScript value.
 * @param {import("@xmpp/xml").Element} value
 */
export function decodeValue(value) {
  const typed = value.children.find((child) => typeof child !== "string");
  if (!typed) return value.getText(); // a bare <value>text</value> is a string
  const text = typed.getText();
  switch (typed.name) {
    case "nil":
      return null;
    case "boolean":
      return text.trim() === "1";
    case "int":
    case "i4":
    case "i8":
      return Number.parseInt(text, 10);
    case "double":
      return decodeDouble(text.trim());
    case "string":
      return text;
    case "base64":
      return Buffer.from(text, "base64");
    case "dateTime.iso8601":
      return parseWireDate(text);
    case "array":
      return (typed.getChild("data")?.getChildren("value") ?? []).map(decodeValue);
    case "struct":
      return Object.fromEntries(
        typed.getChildren("member").map((m) => [m.getChildText("name"), decodeValue(m.getChild("value"))]),
      );
    default:
      throw new SyntaxError(`unknown XML-RPC type <${typed.name}>`);
  }
}

function decodeDouble(text) {
  if (text === "nan") return Number.NaN;
  if (text === "inf") return Number.POSITIVE_INFINITY;
  if (text === "-inf") return Number.NEGATIVE_INFINITY;
  return Number.parseFloat(text);
}

/**
 * A `<methodCall>`; `params` are the parameters' catalogue entries (their schemas guide encoding).
 * @param {string} method
 * @param {Array<*>} args
 * @param {Array<{schema: object}>} [params]
 * @param {Object<string, object>} [schemas]
 */
export function methodCall(method, args, params = [], schemas = {}) {
  const encoded = args.map((arg, i) => xml("param", {}, encodeValue(arg, params[i]?.schema, schemas)));
  return xml("methodCall", {}, xml("methodName", {}, method), xml("params", {}, ...encoded));
}

/**
 * A `<methodResponse>`: `{result}` or `{fault: {faultCode, faultString, errorClass?}}`.
 * @param {import("@xmpp/xml").Element} response
 */
export function parseResponse(response) {
  const fault = response.getChild("fault");
  if (fault) return { fault: decodeValue(fault.getChild("value")) };
  const param = response.getChild("params")?.getChild("param");
  if (!param) throw new SyntaxError("a methodResponse without fault or param");
  return { result: decodeValue(param.getChild("value")) };
}

/** A `<methodResponse>` carrying `result`, or a fault of `errorClass`. */
export function methodResponse(result, fault) {
  if (fault) {
    const struct = { faultCode: 1, faultString: fault.message, errorClass: fault.errorClass };
    return xml("methodResponse", {}, xml("fault", {}, encodeValue(struct)));
  }
  return xml("methodResponse", {}, xml("params", {}, xml("param", {}, encodeValue(result))));
}
