// Completion for the Shell's lines, ``module.method(args)``: module names, then methods, then
// the next parameter with its allowed values. The server parses and runs the line (POST /api/shell).

/**
 * What to offer at the cursor: {from, items:[{label, insert, detail}]}.
 * ``catalogue`` maps module name → {method name → {params: [{name, type, required, default, choices}], doc}}
 * (the ``methods`` of GET /api/modules).
 */
export function complete(line, cursor, catalogue) {
  const head = line.slice(0, cursor);
  const call = head.match(/^\s*([A-Za-z_][\w-]*)\.([A-Za-z_]\w*)\s*\(([^)]*)$/);
  if (call) {
    // Arguments are positional: say which parameter comes next, and offer its allowed values.
    const method = catalogue[call[1]]?.[call[2]];
    if (!method) return { from: cursor, items: [] };
    const index = topLevelCommas(call[3]);
    const param = method.params[index];
    if (!param) return { from: cursor, items: [], hint: `${call[2]}${signature(method)}: no more parameters` };
    const word = call[3].slice(call[3].lastIndexOf(",") + 1).trimStart();
    const values = param.choices ? param.choices.map((c) => `'${c}'`) : param.type === "bool" ? ["True", "False"] : [];
    const items = values.filter((v) => v.startsWith(word)).map((v) => ({ label: v, insert: v, detail: param.name }));
    return { from: cursor - word.length, items, hint: `${param.name}: ${param.type}${param.required ? "" : ` = ${JSON.stringify(param.default)}`}` };
  }
  const dotted = head.match(/^\s*([A-Za-z_][\w-]*)\.([A-Za-z_]\w*)?$/);
  if (dotted) {
    const methods = catalogue[dotted[1]] || {};
    const word = dotted[2] || "";
    const items = Object.keys(methods)
      .filter((m) => m.startsWith(word))
      .sort()
      .map((m) => ({ label: m, insert: `${m}(`, detail: signature(methods[m]) }));
    return { from: cursor - word.length, items };
  }
  const bare = head.match(/^\s*([A-Za-z_][\w-]*)?$/);
  if (bare) {
    const word = bare[1] || "";
    const items = Object.keys(catalogue)
      .filter((m) => m.startsWith(word))
      .sort()
      .map((m) => ({ label: m, insert: `${m}.`, detail: "module" }));
    return { from: cursor - word.length, items };
  }
  return { from: cursor, items: [] };
}

/** How many commas outside brackets and quotes: the index of the argument being typed. */
function topLevelCommas(text) {
  let depth = 0;
  let quote = null;
  let count = 0;
  for (const ch of text) {
    if (quote) {
      if (ch === quote) quote = null;
    } else if (ch === "'" || ch === '"') quote = ch;
    else if ("[{(".includes(ch)) depth++;
    else if ("]})".includes(ch)) depth--;
    else if (ch === "," && depth === 0) count++;
  }
  return count;
}

/** "(count, step: float = 0.1)" for a method entry of the catalogue. */
export function signature(method) {
  const params = (method?.params || []).map((p) => `${p.name}: ${p.type}${p.required ? "" : ` = ${JSON.stringify(p.default)}`}`);
  return `(${params.join(", ")})`;
}
