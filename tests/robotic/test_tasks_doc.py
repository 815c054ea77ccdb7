"""docs/tasks.md: its field tables equal the request model, and its commands run as written."""

from __future__ import annotations

import json
import re
import shlex
from pathlib import Path

import pytest
from pydantic import BaseModel

from nightcrew.cli.main import main
from nightcrew.robotic import tasks
from nightcrew.robotic.tasks import request_group_schema

ROOT = Path(__file__).parents[2]
DOC = (ROOT / "docs/tasks.md").read_text()
SITE_FILE = ROOT / "examples/sim/shared/site.yaml"


def sections() -> dict[str, dict[str, list[str]]]:
    """Model name → field → the cells of its row, from the doc's "### Name — path" tables."""
    found: dict[str, dict[str, list[str]]] = {}
    for heading, body in re.findall(r"^### (\w+) — [^\n]*\n(.*?)(?=^#|\Z)", DOC, flags=re.M | re.S):
        rows = [line for line in body.splitlines() if line.startswith("| `")]
        cells = [[cell.strip() for cell in row.strip("|").split("|")] for row in rows]
        found[heading] = {row[0].strip("`"): row for row in cells}
    return found


def expected_default(model: type[BaseModel], name: str) -> str:
    field = model.model_fields[name]
    if field.is_required():
        return "*required*"
    value = field.get_default(call_default_factory=True)
    if isinstance(value, BaseModel):
        return "*each field's default*"
    if isinstance(value, tuple):
        value = list(value)
    return f"`{json.dumps(getattr(value, 'value', value))}`"


def models() -> dict[str, type[BaseModel]]:
    schema = request_group_schema()
    names = ["RequestGroup", *(name for name, d in schema["$defs"].items() if "properties" in d)]
    return {name: getattr(tasks, name) for name in names}


def test_every_field_of_the_model_is_in_the_doc_with_its_default() -> None:
    documented = sections()
    assert set(documented) == set(models())
    for name, model in models().items():
        rows = documented[name]
        assert list(rows) == list(model.model_fields), f"{name}: fields differ from the model"
        for field, row in rows.items():
            assert row[3] == expected_default(model, field), f"{name}.{field}: default"
            assert row[4], f"{name}.{field}: no meaning given"


def test_every_choice_of_an_enumerated_field_is_listed() -> None:
    schema = request_group_schema()
    documented = sections()
    for name in models():
        properties = (schema if name == "RequestGroup" else schema["$defs"][name])["properties"]
        for field, spec in properties.items():
            ref = spec.get("$ref") or next((a.get("$ref") for a in spec.get("allOf", [])), None)
            choices = schema["$defs"][ref.rsplit("/", 1)[1]].get("enum", []) if ref else []
            for choice in choices:
                assert f"`{choice}`" in documented[name][field][1], f"{name}.{field}: {choice}"


def test_the_defaults_that_exclude_targets_are_called_out() -> None:
    for field in ("min_lunar_distance: 30", "max_airmass: 2.0", "max_sun_altitude: -12", "windows"):
        assert f"**`{field}" in DOC


def test_the_first_task_and_commands_run_as_written(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    monkeypatch.chdir(tmp_path)  # the observatory directory
    for name in ("NIGHTCREW_TASKS_DB", "NIGHTCREW_COMM", "NIGHTCREW_SITE"):
        monkeypatch.delenv(name, raising=False)
    (tmp_path / "site.yaml").write_text(SITE_FILE.read_text())
    yaml_block = re.search(r"```yaml\n(.*?)```", DOC, flags=re.S)
    assert yaml_block is not None
    (tmp_path / "m15.yaml").write_text(yaml_block.group(1))
    sh_block = re.search(r"```sh\n(.*?)```", DOC, flags=re.S)
    assert sh_block is not None
    outputs = []
    for line in sh_block.group(1).splitlines():
        words = shlex.split(line, comments=True)
        assert words[0] == "nightcrew"
        assert main(words[1:]) == 0, line
        outputs.append(capsys.readouterr().out)
    assert "constraints.min_lunar_distance: 30.0  (can keep a target out of the plan)" in outputs[0]
    assert (tmp_path / "tasks.sqlite").is_file()
    assert ": planned 2026-11-10 " in outputs[2]
    assert outputs[-1].startswith("task 1 (M15 globular cluster): CANCELED")
