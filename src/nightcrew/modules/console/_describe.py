"""Interfaces, methods and events described as JSON for the pages, and values turned into JSON.

The pages build themselves from these descriptions (a camera without IWindow has no
``set_window`` here, so no window controls) and the shell completes from them. They are a view of
the catalogue (:mod:`nightcrew.comm.catalogue`), which describes methods and events once: types
are written back from its JSON Schemas as a person writes them (``ImageType | None``).
"""

from __future__ import annotations

import base64
import dataclasses
from collections.abc import Iterable, Mapping
from datetime import datetime
from functools import cache
from typing import Any

from nightcrew.comm.catalogue import event_schemas, methods_document
from nightcrew.comm.codec import encode
from nightcrew.events.base import Event, event_by_name, event_names
from nightcrew.interfaces.base import Interface, interface_methods
from nightcrew.modules.console._auth import is_read_method

__all__ = ["describe_event_types", "describe_methods", "to_json"]

#: JSON Schema types by the Python names the pages show.
_TYPE_NAMES = {"integer": "int", "number": "float", "string": "str", "boolean": "bool", "null": "None"}
_FORMAT_NAMES = {
    "date-time": "datetime",
    "date": "date",
    "time": "time",
    "binary": "bytes",
    "base64url": "bytes",
}


def to_json(value: Any) -> Any:
    """``value`` (anything the codec can send) as plain JSON: datetimes ISO, bytes base64."""
    return _wire_to_json(encode(value))


def _wire_to_json(value: Any) -> Any:
    if isinstance(value, datetime):
        return value.isoformat()
    if isinstance(value, bytes):
        return base64.b64encode(value).decode()
    if isinstance(value, list):
        return [_wire_to_json(v) for v in value]
    if isinstance(value, dict):
        return {k: _wire_to_json(v) for k, v in value.items()}
    if isinstance(value, float) and value != value:  # NaN is no JSON
        return None
    return value


def _schema_text(schema: Mapping[str, Any]) -> str:
    """A catalogue schema as a person writes its type: ``float``, ``ImageType | None``, ``list[str]``."""
    if "$ref" in schema:
        return str(schema["$ref"]).rsplit("/", 1)[-1]
    if "anyOf" in schema:
        return " | ".join(_schema_text(option) for option in schema["anyOf"])
    kind = schema.get("type")
    if kind == "array":
        if "prefixItems" in schema:
            return f"tuple[{', '.join(_schema_text(item) for item in schema['prefixItems'])}]"
        return f"list[{_schema_text(schema['items'])}]" if "items" in schema else "list"
    if kind == "object" and "additionalProperties" in schema:
        values = schema["additionalProperties"]
        return f"dict[str, {_schema_text(values if isinstance(values, Mapping) else {})}]"
    if not isinstance(kind, str):
        return "Any"
    return _FORMAT_NAMES.get(str(schema.get("format")), _TYPE_NAMES.get(kind, "Any"))


def _choices(schema: Mapping[str, Any], definitions: Mapping[str, Any]) -> list[Any] | None:
    """The values of the first enum in ``schema`` (followed through references), if any."""
    if "enum" in schema:
        return list(schema["enum"])
    if "$ref" in schema:
        return _choices(definitions.get(str(schema["$ref"]).rsplit("/", 1)[-1], {}), definitions)
    for option in schema.get("anyOf", ()):
        found = _choices(option, definitions)
        if found is not None:
            return found
    return None


def _parameter(
    name: str, schema: Mapping[str, Any], required: bool, definitions: Mapping[str, Any]
) -> dict[str, Any]:
    """One parameter (of a method or an event) as the pages see it."""
    return {
        "name": name,
        "type": _schema_text(schema),
        "required": required,
        "default": None if required else schema.get("default"),
        "choices": _choices(schema, definitions),
    }


def describe_methods(interfaces: Iterable[type[Interface]]) -> dict[str, dict[str, Any]]:
    """Method name → interface, doc, parameters, return type, whether a viewer may call it."""
    return dict(_describe_methods(tuple(interfaces)))


@cache
def _describe_methods(interfaces: tuple[type[Interface], ...]) -> dict[str, dict[str, Any]]:
    document = methods_document("console", 1, interface_methods(interfaces), "")
    definitions = document["components"]["schemas"]
    return {
        method["name"]: {
            "interface": method["x-interface"],
            "doc": method["description"],
            "params": [
                _parameter(p["name"], p["schema"], p["required"], definitions) for p in method["params"]
            ],
            "returns": _schema_text(method["result"]["schema"]),
            "read": is_read_method(method["name"]),
        }
        for method in document["methods"]
    }


def describe_event_types() -> dict[str, dict[str, Any]]:
    """Every event type this process knows, with its fields."""
    known = ((name, event_by_name(name)) for name in event_names())
    return dict(
        _describe_events(tuple((name, event_type) for name, event_type in known if event_type is not None))
    )


@cache
def _describe_events(known: tuple[tuple[str, type[Event]], ...]) -> dict[str, dict[str, Any]]:
    definitions = event_schemas(event_type for _, event_type in known)["$defs"]
    described = {}
    for name, event_type in known:
        schema = definitions[event_type.__name__]
        required = set(schema.get("required", ()))
        fields = [
            _parameter(field_name, field, field_name in required, definitions)
            for field_name, field in schema.get("properties", {}).items()
        ]
        for field in dataclasses.fields(event_type):  # the schema has no default made by a factory
            if field.default_factory is not dataclasses.MISSING:
                described_field = next(f for f in fields if f["name"] == field.name)
                described_field["default"] = to_json(field.default_factory())
        described[name] = {"doc": schema.get("description", ""), "fields": fields}
    return described
