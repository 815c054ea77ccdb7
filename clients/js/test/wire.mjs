// The runtime's XML-RPC codec against another implementation (tests/clients/test_js_wire.py):
//   node wire.mjs encode   prints a <methodCall> of sample values, as the client would send it
//   node wire.mjs decode   reads a jabber:iq:rpc <query> on stdin, prints its call's params as tagged JSON
//   node wire.mjs events   reads [name, JSON text] pairs on stdin, prints what each decodes to
import parse from "@xmpp/xml/lib/parse.js";

import { decodeEvent } from "../src/decode.js";
import { decodeValue, methodCall } from "../src/xmlrpc.js";

function tagged(value) {
  if (value instanceof Date) return { date: value.toISOString() };
  if (value instanceof Uint8Array) return { base64: Buffer.from(value).toString("base64") };
  if (typeof value === "number" && !Number.isFinite(value)) return { number: String(value) };
  if (Array.isArray(value)) return value.map(tagged);
  if (value && typeof value === "object") {
    return { struct: Object.fromEntries(Object.entries(value).map(([k, v]) => [k, tagged(v)])) };
  }
  return value;
}

async function stdinText() {
  const chunks = [];
  for await (const chunk of process.stdin) chunks.push(chunk);
  return Buffer.concat(chunks).toString("utf-8");
}

if (process.argv[2] === "events") {
  const decoded = JSON.parse(await stdinText()).map(([name, text]) => {
    const { event, problem } = decodeEvent(name, text);
    return event ? { class: event.constructor.name, fields: tagged({ ...event }).struct } : { problem };
  });
  process.stdout.write(JSON.stringify(decoded));
} else if (process.argv[2] === "encode") {
  const values = [
    null,
    true,
    42,
    2 ** 40,
    1.5,
    10,
    Number.NaN,
    Number.NEGATIVE_INFINITY,
    "a <b> & 'c' \u00b0",
    new Date(Date.UTC(2026, 10, 10, 17, 50, 0, 250)),
    Uint8Array.from([0, 1, 254, 255]),
    [1, "two", [3.5]],
    { ra: 322.95, name: "M39", tags: [] },
  ];
  const params = values.map(() => ({ schema: {} }));
  params[5] = { schema: { type: "number" } }; // a whole number where the schema says `number`
  process.stdout.write(methodCall("sample", values, params).toString());
} else {
  const call = parse(await stdinText()).getChild("methodCall");
  const values = call.getChild("params").getChildren("param").map((p) => decodeValue(p.getChild("value")));
  process.stdout.write(JSON.stringify({ method: call.getChildText("methodName"), params: values.map(tagged) }));
}
