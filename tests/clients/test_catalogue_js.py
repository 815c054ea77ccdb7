"""``nightcrew catalogue --js``: the JavaScript client's generated files, from the catalogue only."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pytest

from nightcrew.cli.catalogue import catalogue_text
from nightcrew.cli.catalogue_js import js_client_files, js_type
from nightcrew.cli.main import main

from .node import CLIENT

GENERATED = CLIENT / "generated"


def test_committed_client_is_current() -> None:
    # CI fails here when an interface, event or error changed without `make catalogue`.
    expected = js_client_files(json.loads(catalogue_text()))
    on_disk = {path.relative_to(GENERATED).as_posix() for path in GENERATED.rglob("*.js")}
    assert on_disk == set(expected), "clients/js/generated is stale: run `make catalogue`"
    for relative, text in expected.items():
        assert (GENERATED / relative).read_text(encoding="utf-8") == text, (
            f"clients/js/generated/{relative} is stale: run `make catalogue`"
        )


def test_cli_writes_the_client_and_drops_files_of_removed_interfaces(tmp_path: Path) -> None:
    (tmp_path / "interfaces").mkdir()
    (tmp_path / "interfaces" / "IGone.js").write_text("// an interface removed from the code\n")
    assert main(["catalogue", "--js", str(tmp_path)]) == 0
    assert not (tmp_path / "interfaces" / "IGone.js").exists()
    assert (tmp_path / "events.js").read_text() == (GENERATED / "events.js").read_text()
    assert (tmp_path / "interfaces" / "ICamera.js").read_text() == (
        GENERATED / "interfaces" / "ICamera.js"
    ).read_text()


@pytest.mark.parametrize(
    ("schema", "expected"),
    [
        ({"type": "number", "minimum": 0.0}, "number"),
        ({"type": "integer"}, "number"),
        ({"anyOf": [{"$ref": "#/components/schemas/ImageType"}, {"type": "null"}]}, "ImageType|null"),
        ({"enum": ["idle", "error"], "type": "string"}, '"idle"|"error"'),
        ({"type": "string", "format": "date-time"}, "Date|string"),
        ({"type": "array", "prefixItems": [{"type": "number"}, {"type": "number"}]}, "[number, number]"),
        ({"type": "array", "items": {"type": "string"}}, "Array<string>"),
        ({"type": "object", "additionalProperties": {"type": "boolean"}}, "Object<string, boolean>"),
        (
            {"type": "object", "properties": {"x": {"type": "integer"}, "y": {}}, "required": ["x"]},
            "{x: number, y?: *}",
        ),
    ],
)
def test_jsdoc_types_from_json_schema(schema: dict[str, Any], expected: str) -> None:
    assert js_type(schema) == expected


def _catalogue(errors: dict[str, Any]) -> dict[str, Any]:
    """A catalogue of two made-up interfaces (one extends the other), no events, ``errors``."""
    method = {
        "name": "set_thing",
        "description": "Set the thing.",
        "params": [
            {"name": "default", "required": True, "schema": {"type": "number", "x-unit": "deg"}},
            {"name": "fast", "required": False, "schema": {"type": "boolean", "default": False}},
        ],
        "result": {"name": "result", "schema": {"type": "null"}},
        "x-timeout": {"seconds": None, "announced": True, "computed_from": ["default", "fast"]},
    }
    base = {"info": {"version": "2", "description": "A base."}, "methods": [method], "x-extends": []}
    child = {"info": {"version": "1", "description": "A child."}, "methods": [], "x-extends": ["IBase"]}
    for document in (base, child):
        document["components"] = {"schemas": {}}
    return {
        "default_timeout": 10.0,
        "interfaces": {"IBase": base, "IChild": child},
        "events": {"x-events": [], "$defs": {}},
        "errors": errors,
    }


def test_reserved_words_inherited_methods_and_computed_timeouts() -> None:
    files = js_client_files(_catalogue({"NightcrewError": {"extends": None, "description": "Base."}}))
    child = files["interfaces/IChild.js"]
    assert 'import { IBase } from "./IBase.js";' in child
    assert "  set_thing(default_, fast) {" in child  # `default` is reserved in JavaScript
    assert "@param {number} default_ [deg]" in child and "@param {boolean} [fast] default false" in child
    assert "Timeout: announced by the module for each call" in child
    assert "IChild.bases = [IBase];" in child
    assert '"version": 2' in files["interfaces/IBase.js"]


def test_error_classes_come_parents_first_and_a_missing_parent_is_named() -> None:
    errors = {
        "AError": {"extends": "ZError", "description": "A."},
        "ZError": {"extends": "NightcrewError", "description": "Z."},
        "NightcrewError": {"extends": None, "description": "Base."},
    }
    text = js_client_files(_catalogue(errors))["errors.js"]
    order = [text.index(f"export class {name} ") for name in ("NightcrewError", "ZError", "AError")]
    assert order == sorted(order)
    assert "export class AError extends ZError {" in text
    with pytest.raises(ValueError, match="error classes with unknown parents: AError"):
        js_client_files(_catalogue({"AError": {"extends": "Missing", "description": "A."}}))
