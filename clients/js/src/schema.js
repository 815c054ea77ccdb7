// Client-side checks against the catalogue's JSON Schemas (with Ajv, a well-kept validator of
// JSON Schema 2020-12, the dialect the catalogue uses): a call with a wrong argument fails here,
// before anything is sent, with the message shape a nightcrew module uses for the same refusal.
import Ajv2020Module from "ajv/dist/2020.js";
import addFormatsModule from "ajv-formats";

import { InvalidArgumentError } from "../generated/errors.js";
import { resolveRef } from "./xmlrpc.js";

// Both are CommonJS modules; their default export sits one level down under ESM.
const Ajv2020 = Ajv2020Module.default ?? Ajv2020Module;
const addFormats = addFormatsModule.default ?? addFormatsModule;

// strict: false lets the catalogue's own `x-` keywords (x-unit, x-persistent) through unchecked.
// verbose: errors carry the schema that failed, to say what was expected.
const ajv = new Ajv2020({ strict: false, allErrors: false, verbose: true });
addFormats(ajv, ["date-time"]);

/** @type {WeakMap<object, Function>} compiled validators, by the catalogue's schema object */
const compiled = new WeakMap();

function validator(schema, schemas) {
  let validate = compiled.get(schema);
  if (!validate) {
    // Refs point into the document's components; Ajv resolves them in the root's $defs.
    const text = JSON.stringify(schema).replaceAll('"#/components/schemas/', '"#/$defs/');
    validate = ajv.compile({ ...JSON.parse(text), $defs: schemas });
    compiled.set(schema, validate);
  }
  return validate;
}

/** The JSON view of a value, as the schema describes it (dates as strings, bytes as base64). */
function jsonView(value) {
  if (value instanceof Date) return Number.isNaN(value.getTime()) ? "invalid date" : value.toISOString();
  if (value instanceof Uint8Array) return Buffer.from(value).toString("base64");
  if (Array.isArray(value)) return value.map(jsonView);
  if (value && typeof value === "object") {
    return Object.fromEntries(Object.entries(value).map(([k, v]) => [k, jsonView(v)]));
  }
  return value;
}

/** A short description of what a schema accepts: `number`, `"object"|"bias"|null`, ... */
export function describeSchema(schema, schemas) {
  const resolved = resolveRef(schema, schemas);
  if (resolved.enum) return resolved.enum.map((v) => JSON.stringify(v)).join("|");
  if (resolved.anyOf) return resolved.anyOf.map((s) => describeSchema(s, schemas)).join("|");
  if (resolved.type === "array" && resolved.prefixItems) {
    return `[${resolved.prefixItems.map((s) => describeSchema(s, schemas)).join(", ")}]`;
  }
  if (resolved.type === "string" && resolved.format === "date-time") return "date-time";
  return resolved.type ?? "any value";
}

function show(value) {
  if (value === undefined) return "undefined";
  if (value instanceof Date) return `Date ${jsonView(value)}`;
  const type = value === null ? "null" : Array.isArray(value) ? "array" : typeof value;
  if (type === "number") return `number ${value}`; // JSON would write NaN and Infinity as null
  const text = JSON.stringify(jsonView(value)) ?? String(value);
  return `${type} ${text.length > 60 ? `${text.slice(0, 57)}...` : text}`;
}

const TYPE_KEYWORDS = new Set(["type", "enum", "anyOf", "oneOf", "const", "format"]);

/** The part of `value` at a JSON Pointer (`/image_type`, `/0/x`). */
function valueAt(value, pointer) {
  const steps = pointer.split("/").slice(1).map((step) => step.replaceAll("~1", "/").replaceAll("~0", "~"));
  return steps.reduce((part, step) => part?.[step], value);
}

/** `true` for a date-time string schema, also as a branch of `anyOf` (an optional date). */
export function isDateTime(schema) {
  return schema.format === "date-time" || Boolean(schema.anyOf?.some((option) => isDateTime(option)));
}

/**
 * Why `value` does not fit `schema`, or null when it does.
 * @returns {string|null}
 */
export function schemaProblem(value, schema, schemas) {
  const validate = validator(schema, schemas);
  if (validate(jsonView(value))) return null;
  // Ajv reports the innermost failure first; for `anyOf` the summary of the same place comes last.
  const first = validate.errors[0];
  const last = validate.errors[validate.errors.length - 1];
  const error = last.instancePath === first.instancePath ? last : first;
  const where = error.instancePath ? `at ${error.instancePath}: ` : "";
  const got = show(valueAt(value, error.instancePath));
  if (TYPE_KEYWORDS.has(error.keyword)) {
    return `${where}expected ${describeSchema(error.parentSchema, schemas)}, got ${got}`;
  }
  if (error.keyword === "required") return `${where}${error.message}`;
  return `${where}${error.message} (got ${got})`;
}

/**
 * The arguments to send for a call, checked against the method's parameters.
 *
 * Trailing arguments left out (or `undefined`) are left out on the wire (the module takes their
 * defaults); one left out before a given one takes the catalogue's default.
 * @param {string} method
 * @param {Array<{name: string, required: boolean, schema: object}>} params
 * @param {Object<string, object>} schemas
 * @param {Array<*>} args
 * @returns {Array<*>}
 * @throws {InvalidArgumentError}
 */
export function checkArguments(method, params, schemas, args) {
  let count = args.length;
  while (count > 0 && args[count - 1] === undefined) count--;
  if (count > params.length) {
    throw new InvalidArgumentError(`${method}(): takes ${params.length} arguments, got ${count}`);
  }
  const checked = [];
  for (const [index, param] of params.entries()) {
    let value = args[index];
    if (value === undefined) {
      if (param.required) throw new InvalidArgumentError(`${method}(): missing argument '${param.name}'`);
      if (index >= count) break;
      value = param.schema.default;
    }
    const problem = schemaProblem(value, param.schema, schemas);
    if (problem) throw new InvalidArgumentError(`${method}(): argument '${param.name}': ${problem}`);
    checked.push(value);
  }
  return checked;
}
