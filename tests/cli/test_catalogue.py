"""`nightcrew catalogue`: the committed docs/catalogue.json is what the code generates, and says enough."""

from __future__ import annotations

import json
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from nightcrew.cli.catalogue import catalogue_text
from nightcrew.cli.main import main
from nightcrew.errors import __all__ as error_names
from nightcrew.events import __all__ as event_exports
from nightcrew.interfaces import __all__ as interface_exports

COMMITTED = Path(__file__).resolve().parents[2] / "docs" / "catalogue.json"


@pytest.fixture(scope="module")
def text() -> str:
    return catalogue_text()


@pytest.fixture(scope="module")
def catalogue(text: str) -> dict[str, Any]:
    parsed: dict[str, Any] = json.loads(text)
    return parsed


def test_committed_catalogue_is_current(text: str) -> None:
    # CI fails here when an interface, event or error changed without `make catalogue`.
    assert COMMITTED.read_text(encoding="utf-8") == text, (
        "docs/catalogue.json is stale: run `nightcrew catalogue --output docs/catalogue.json`"
    )


def test_generation_is_deterministic(text: str) -> None:
    assert catalogue_text() == text


def test_check_option_tells_a_stale_file(
    tmp_path: Path, text: str, capsys: pytest.CaptureFixture[str]
) -> None:
    current, stale = tmp_path / "current.json", tmp_path / "stale.json"
    assert main(["catalogue", "--output", str(current)]) == 0
    assert current.read_text(encoding="utf-8") == text
    assert main(["catalogue", "--check", str(current)]) == 0
    stale.write_text(text.replace('"move_radec"', '"move_to"'), encoding="utf-8")
    assert main(["catalogue", "--check", str(stale)]) == 1
    assert f"{stale} is stale" in capsys.readouterr().err


def test_everything_exported_is_catalogued(catalogue: dict[str, Any]) -> None:
    interfaces = {name for name in interface_exports if name.startswith("I") and name[1].isupper()}
    assert interfaces <= set(catalogue["interfaces"])
    events = {name for name in event_exports if name.endswith("Event") and name != "Event"}
    assert events == set(catalogue["events"]["x-events"])
    assert {name for name in error_names if name.endswith("Error")} <= set(catalogue["errors"])
    assert catalogue["errors"]["InterfaceError"]["extends"] == "NightcrewError"
    assert catalogue["errors"]["RemoteTimeoutError"]["extends"] == "RemoteError"
    assert catalogue["errors"]["NightcrewError"]["extends"] is None


def test_a_method_with_units_bounds_and_timeout(catalogue: dict[str, Any]) -> None:
    document = catalogue["interfaces"]["IPointingRaDec"]
    assert document["openrpc"].startswith("1.") and document["info"]["version"] == "1"
    move = next(m for m in document["methods"] if m["name"] == "move_radec")
    assert move["paramStructure"] == "by-position"
    assert move["params"] == [
        {
            "name": "ra",
            "required": True,
            "schema": {"type": "number", "minimum": 0.0, "exclusiveMaximum": 360.0, "x-unit": "deg"},
        },
        {
            "name": "dec",
            "required": True,
            "schema": {"type": "number", "minimum": -90.0, "maximum": 90.0, "x-unit": "deg"},
        },
    ]
    assert move["result"]["schema"] == {"type": "null"}
    assert move["x-timeout"] == {"seconds": 300.0, "announced": True}
    assert move["description"].startswith("Slew to right ascension")


def test_defaults_enums_and_composition(catalogue: dict[str, Any]) -> None:
    data = catalogue["interfaces"]["IData"]
    grab = data["methods"][0]
    assert grab["name"] == "grab_data" and grab["x-timeout"]["seconds"] == 3600.0
    broadcast, image_type = grab["params"]
    assert broadcast == {
        "name": "broadcast",
        "required": False,
        "schema": {"type": "boolean", "default": True},
    }
    assert image_type["schema"]["default"] is None
    assert data["components"]["schemas"]["ImageType"]["enum"][:2] == ["object", "bias"]
    assert catalogue["interfaces"]["ICamera"]["x-extends"] == ["IAbortable", "IData", "IExposure"]
    assert catalogue["interfaces"]["ICamera"]["methods"] == []  # all its methods come from what it extends


def test_event_fields(catalogue: dict[str, Any]) -> None:
    new_image = catalogue["events"]["$defs"]["NewImageEvent"]
    assert new_image["required"] == ["filename"]
    assert new_image["properties"]["filename"]["type"] == "string"
    assert new_image["properties"]["image_type"]["anyOf"][0] == {"$ref": "#/$defs/ImageType"}


def _refs(value: Any) -> Iterator[str]:
    if isinstance(value, dict):
        for key, item in value.items():
            if key == "$ref":
                yield item
            else:
                yield from _refs(item)
    elif isinstance(value, list):
        for item in value:
            yield from _refs(item)


def test_every_reference_resolves_inside_its_own_document(catalogue: dict[str, Any]) -> None:
    # Each interface document and the events document stand alone: a client may take any one.
    for name, document in catalogue["interfaces"].items():
        schemas = document["components"]["schemas"]
        for ref in _refs(document):
            assert ref.startswith("#/components/schemas/") and ref.rsplit("/", 1)[1] in schemas, (name, ref)
    events = catalogue["events"]
    for ref in _refs(events):
        assert ref.startswith("#/$defs/") and ref.rsplit("/", 1)[1] in events["$defs"], ref


def test_protocol_lists_every_event_and_error(catalogue: dict[str, Any]) -> None:
    protocol = (COMMITTED.parent / "protocol.md").read_text(encoding="utf-8")
    section = protocol.split("## 8. Every event and every error", 1)[1].split("\n## ", 1)[0]
    for name in [*catalogue["events"]["x-events"], *catalogue["errors"]]:
        assert f"| `{name}` |" in section, f"docs/protocol.md section 8 does not list {name}"
