"""The JavaScript client's generated part, written from the catalogue (``nightcrew catalogue --js DIR``).

One ES module per interface (a class with one method per catalogue method: its parameter names and
order, JSDoc types from the JSON Schemas, the announced timeout in its doc, the method's schemas as
data for the runtime's client-side checks), one module of event classes, one of error classes, and
an index. Nothing here knows a method, event or error by name: all of it comes from the catalogue
dict, so the generated client can only say what the catalogue says. The hand-written runtime the
files import (XMPP, XML-RPC, schema checks) is in ``clients/js/src``.

Pure and deterministic: the same catalogue gives the same files (a committed copy is compared in CI).
"""

from __future__ import annotations

import json
from typing import Any

__all__ = ["GENERATED_HEADER", "js_client_files", "js_type"]

GENERATED_HEADER = (
    "// Generated from the nightcrew catalogue by `nightcrew catalogue --js clients/js/generated`.\n"
    "// Do not edit: change the Python interface, event or error and generate again.\n"
)
#: Words JavaScript reserves; a parameter of that name is written with a trailing underscore.
_RESERVED = frozenset({
    "arguments", "await", "break", "case", "catch", "class", "const", "continue", "debugger",
    "default", "delete", "do", "else", "enum", "eval", "export", "extends", "false", "finally",
    "for", "function", "if", "implements", "import", "in", "instanceof", "interface", "let", "new",
    "null", "package", "private", "protected", "public", "return", "static", "super", "switch",
    "this", "throw", "true", "try", "typeof", "var", "void", "while", "with", "yield",
})  # fmt: skip
_INTERFACE_REF = "#/components/schemas/"
_EVENT_REF = "#/$defs/"


def js_type(schema: dict[str, Any], ref_prefix: str = _INTERFACE_REF) -> str:
    """The JSDoc type of a JSON Schema (refs by their component name, which the files define)."""
    if "$ref" in schema:
        return str(schema["$ref"]).removeprefix(ref_prefix)
    if "enum" in schema:
        return "|".join(json.dumps(value) for value in schema["enum"])
    if "anyOf" in schema:
        return "|".join(js_type(option, ref_prefix) for option in schema["anyOf"])
    kind = schema.get("type")
    if kind in ("number", "integer"):
        return "number"
    if kind == "string":
        return "Date|string" if schema.get("format") == "date-time" else "string"
    if kind in ("boolean", "null"):
        return str(kind)
    if kind == "array":
        if "prefixItems" in schema:
            return "[" + ", ".join(js_type(item, ref_prefix) for item in schema["prefixItems"]) + "]"
        return f"Array<{js_type(schema.get('items', {}), ref_prefix)}>"
    if kind == "object":
        if "properties" in schema:
            return "{" + ", ".join(_property(name, schema, ref_prefix) for name in schema["properties"]) + "}"
        values = schema.get("additionalProperties")
        return f"Object<string, {js_type(values, ref_prefix)}>" if isinstance(values, dict) else "object"
    return "*"


def _property(name: str, schema: dict[str, Any], ref_prefix: str) -> str:
    optional = "" if name in schema.get("required", []) else "?"
    return f"{name}{optional}: {js_type(schema['properties'][name], ref_prefix)}"


def _comment(text: str, indent: str = "") -> list[str]:
    """A JSDoc comment block (``*/`` inside the text cannot end it early)."""
    lines = text.replace("*/", "*\\/").strip().splitlines() or [""]
    return [f"{indent}/**", *(f"{indent} * {line}".rstrip() for line in lines), f"{indent} */"]


def _constraints(schema: dict[str, Any]) -> str:
    words = [f"[{schema['x-unit']}]"] if "x-unit" in schema else []
    bounds = ("minimum", "exclusiveMinimum", "maximum", "exclusiveMaximum")
    words += [f"{key} {schema[key]}" for key in bounds if key in schema]
    if "default" in schema:
        words.append(f"default {json.dumps(schema['default'])}")
    return " ".join(words)


def _timeout_text(timeout: dict[str, Any]) -> str:
    if not timeout["announced"]:
        return f"Timeout: {timeout['seconds']:g} clock seconds (the default, not announced)."
    if timeout["seconds"] is None:
        return "Timeout: announced by the module for each call (computed from the arguments)."
    return f"Timeout: announced, {timeout['seconds']:g} clock seconds."


def _identifier(name: str) -> str:
    return f"{name}_" if name in _RESERVED else name


def _method_lines(method: dict[str, Any]) -> list[str]:
    doc = [method["description"] or method["name"], "", _timeout_text(method["x-timeout"])]
    for param in method["params"]:
        identifier = _identifier(param["name"])
        name = identifier if param["required"] else f"[{identifier}]"
        doc.append(f"@param {{{js_type(param['schema'])}}} {name} {_constraints(param['schema'])}".rstrip())
    doc.append(f"@returns {{Promise<{js_type(method['result']['schema'])}>}}")
    names = ", ".join(_identifier(param["name"]) for param in method["params"])
    return [
        *_comment("\n".join(doc), "  "),
        f"  {method['name']}({names}) {{",
        f"    return this._invoke({json.dumps(method['name'])}, arguments);",
        "  }",
    ]


def _all_methods(name: str, interfaces: dict[str, Any]) -> dict[str, dict[str, Any]]:
    """Every method ``name`` offers, its own and those of the interfaces it extends, by name."""
    methods: dict[str, dict[str, Any]] = {}
    for base in interfaces[name]["x-extends"]:
        methods.update(_all_methods(base, interfaces))
    methods.update({method["name"]: method for method in interfaces[name]["methods"]})
    return methods


def _all_components(name: str, interfaces: dict[str, Any]) -> dict[str, Any]:
    """The schemas the methods of ``name`` use, its own and those of the interfaces it extends."""
    components: dict[str, Any] = {}
    for base in interfaces[name]["x-extends"]:
        components.update(_all_components(base, interfaces))
    components.update(interfaces[name]["components"]["schemas"])
    return components


def _interface_file(name: str, interfaces: dict[str, Any]) -> str:
    document = interfaces[name]
    bases = document["x-extends"]
    lines = [GENERATED_HEADER.rstrip("\n"), 'import { RemoteInterface } from "../../src/remote.js";']
    lines += [f'import {{ {base} }} from "./{base}.js";' for base in bases]
    lines.append("")
    for component, schema in sorted(_all_components(name, interfaces).items()):
        lines += _comment(
            f"{schema.get('description', component)}\n@typedef {{{js_type(schema)}}} {component}"
        )
    methods = _all_methods(name, interfaces)
    description = document["info"]["description"]
    if bases:
        description += "\n\nExtends " + ", ".join(bases) + " (their methods are here too)."
    lines += _comment(description)
    lines.append(f"export class {name} extends RemoteInterface {{")
    for method_name in sorted(methods):
        lines += _method_lines(methods[method_name])
    lines.append("}")
    spec = {
        "name": name,
        "version": int(document["info"]["version"]),
        "methods": {method["name"]: _method_spec(method) for method in document["methods"]},
        "schemas": document["components"]["schemas"],
    }
    lines.append(f"{name}.spec = {_literal(spec)};")
    lines.append(f"{name}.bases = [{', '.join(bases)}];")
    return "\n".join(lines) + "\n"


def _method_spec(method: dict[str, Any]) -> dict[str, Any]:
    """What the runtime needs of a method: parameters with schemas, result schema, timeout."""
    return {
        "params": method["params"],
        "result": method["result"]["schema"],
        "timeout": method["x-timeout"],
    }


def _literal(value: Any) -> str:
    return json.dumps(value, indent=2, sort_keys=True, ensure_ascii=False)


def _events_file(events: dict[str, Any]) -> str:
    definitions = events["$defs"]
    lines = [GENERATED_HEADER.rstrip("\n"), 'import { Event } from "../src/event.js";', ""]
    for name in sorted(set(definitions) - set(events["x-events"])):
        schema = definitions[name]
        lines += _comment(
            f"{schema.get('description', name)}\n@typedef {{{js_type(schema, _EVENT_REF)}}} {name}"
        )
    for name in events["x-events"]:
        schema = definitions[name]
        properties = schema.get("properties", {})
        fields = js_type(
            {"type": "object", "properties": properties, "required": schema.get("required", [])}, _EVENT_REF
        )
        lines += _comment(schema.get("description", name))
        lines.append(f"export class {name} extends Event {{")
        lines.append(f"  static eventName = {json.dumps(name)};")
        lines += _comment(f"@param {{{fields}}} [fields]", "  ")
        lines += ["  constructor(fields = {}) {", "    super();"]
        for field, field_schema in properties.items():
            default = _literal(field_schema["default"]) if "default" in field_schema else "undefined"
            lines.append(f"    /** @type {{{js_type(field_schema, _EVENT_REF)}}} */")
            lines.append(f"    this.{field} = fields.{field} ?? {default};")
        lines += ["  }", "}", ""]
    lines.append("/** Every event class, by the name it travels under. */")
    lines.append("export const EVENTS = {" + ", ".join(events["x-events"]) + "};")
    lines.append("")
    lines.append(
        "/** JSON Schema of every event and of the types they use (`$defs`, as in the catalogue). */"
    )
    lines.append(f"export const EVENT_SCHEMAS = {_literal(definitions)};")
    return "\n".join(lines) + "\n"


def _errors_file(errors: dict[str, Any]) -> str:
    lines = [GENERATED_HEADER.rstrip("\n")]
    written: list[str] = []
    pending = sorted(errors)
    while pending:  # parents first: a class can only extend one already defined
        ready = [name for name in pending if errors[name]["extends"] in (None, *written)]
        if not ready:
            raise ValueError(f"error classes with unknown parents: {', '.join(pending)}")
        for name in ready:
            parent = errors[name]["extends"] or "Error"
            lines += ["", *_comment(errors[name]["description"]), f"export class {name} extends {parent} {{"]
            if parent == "Error":
                lines += [
                    "  /** @param {string} message */",
                    "  constructor(message) {",
                    "    super(message);",
                    "    this.name = new.target.name;",
                    "  }",
                ]
            lines.append("}")
            written.append(name)
        pending = [name for name in pending if name not in ready]
    lines += ["", "/** Every error class, by the name a fault's `errorClass` carries. */"]
    lines.append("export const ERRORS = {" + ", ".join(sorted(errors)) + "};")
    return "\n".join(lines) + "\n"


def _index_file(interfaces: dict[str, Any], default_timeout: float) -> str:
    names = sorted(interfaces)
    lines = [GENERATED_HEADER.rstrip("\n")]
    lines += [f'import {{ {name} }} from "./interfaces/{name}.js";' for name in names]
    lines += ['export * from "./events.js";', 'export * from "./errors.js";', ""]
    lines.append(f"export {{ {', '.join(names)} }};")
    lines.append("/** Every interface class, by the name in its disco#info feature. */")
    lines.append(f"export const INTERFACES = {{ {', '.join(names)} }};")
    lines.append("/** Calls without an announcement may take this many clock seconds. */")
    lines.append(f"export const DEFAULT_TIMEOUT = {default_timeout!r};")
    return "\n".join(lines) + "\n"


def js_client_files(catalogue: dict[str, Any]) -> dict[str, str]:
    """Relative path → text of every generated file of the JavaScript client."""
    interfaces: dict[str, Any] = catalogue["interfaces"]
    files = {f"interfaces/{name}.js": _interface_file(name, interfaces) for name in sorted(interfaces)}
    files["events.js"] = _events_file(catalogue["events"])
    files["errors.js"] = _errors_file(catalogue["errors"])
    files["index.js"] = _index_file(interfaces, float(catalogue["default_timeout"]))
    return files
