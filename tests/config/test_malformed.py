"""Malformed configurations: each must fail with ONE error naming file, line, key and the problem."""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from pathlib import Path

import pytest

from nightcrew.config import load_and_build, load_config, validate_config
from nightcrew.errors import ConfigError

S = "tests.config.sample_classes"


@dataclass(frozen=True)
class Case:
    """``files["main.yaml"]`` is loaded; the error must be at ``file``:``line`` for ``key``."""

    id: str
    files: dict[str, str]
    file: str
    line: int | None
    key: str | None
    message: str  # a regular expression the message must match
    environ: dict[str, str] = field(default_factory=dict)


def main(text: str, others: dict[str, str] | None = None) -> dict[str, str]:
    return {"main.yaml": text, **(others or {})}


CASES = [
    Case(
        "module not importable",
        main("class: tests.config.nope.Thing\nvalue: 1\n"),
        "main.yaml",
        1,
        "class",
        "cannot import 'tests.config.nope': No module named 'tests.config.nope'",
    ),
    Case(
        "module importing a missing dependency",
        main("class: tests.config.broken_module.Unreachable\n"),
        "main.yaml",
        1,
        "class",
        "cannot import 'tests.config.broken_module': No module named 'nightcrew_no_such_dependency'",
    ),
    Case(
        "hinted key still checked when another hint cannot be evaluated",
        main("class: tests.config.hidden_hints.HalfHinted\nwhere: anything\ncount: many\n"),
        "main.yaml",
        3,
        "count",
        "expected int, got str 'many'",
    ),
    Case(
        "class missing in module",
        main(f"class: {S}.Thingy\nvalue: 1\n"),
        "main.yaml",
        1,
        "class",
        f"'{S}' has no attribute 'Thingy' \\(did you mean 'Thing'\\?\\)",
    ),
    Case(
        "not a class",
        main("class: os.path.join\n"),
        "main.yaml",
        1,
        "class",
        "'os.path.join' is not a class but a function",
    ),
    Case(
        "class not dotted",
        main("class: Thing\nvalue: 1\n"),
        "main.yaml",
        1,
        "class",
        "'Thing' is not a dotted class path",
    ),
    Case(
        "class key missing",
        main("# a thing\nvalue: 1\n"),
        "main.yaml",
        2,
        "class",
        "missing key 'class'",
    ),
    Case(
        "unknown key with suggestion",
        main(f"class: {S}.Leaf\nmessage: hi\nintervall: 5\n"),
        "main.yaml",
        3,
        "intervall",
        f"unknown key 'intervall' for {S}.Leaf \\(did you mean 'interval'\\?\\)",
    ),
    Case(
        "unknown key from the end of the kwargs chain",
        main(f"class: {S}.Leaf\nmessage: hi\ntimeuot: 3\n"),
        "main.yaml",
        3,
        "timeuot",
        "unknown key 'timeuot' .*did you mean 'timeout'",
    ),
    Case(
        "str for float",
        main(f"class: {S}.Leaf\nmessage: hi\ninterval: ten\n"),
        "main.yaml",
        3,
        "interval",
        "expected float, got str 'ten'",
    ),
    Case(
        "bool for int",
        main(f"class: {S}.Kitchen\ncount: true\n"),
        "main.yaml",
        2,
        "count",
        "expected int, got bool True",
    ),
    Case(
        "required key missing",
        main(f"class: {S}.Leaf\ninterval: 5\n"),
        "main.yaml",
        1,
        "message",
        f"missing required key 'message' for {S}.Leaf",
    ),
    Case(
        "YAML syntax error",
        main(f"class: {S}.Leaf\nmessage: [unclosed\ninterval: 5\n"),
        "main.yaml",
        3,
        None,
        "invalid YAML: .*expected ',' or ']'",
    ),
    Case(
        "YAML tab indentation",
        main(f"class: {S}.Leaf\n\tmessage: hi\n"),
        "main.yaml",
        2,
        None,
        "invalid YAML: found character '\\\\t'",
    ),
    Case(
        "include missing",
        main(f"class: {S}.Middle\nthing: !include nothere.yaml\n"),
        "main.yaml",
        2,
        "thing",
        "cannot include 'nothere.yaml': file nothere.yaml not found",
    ),
    Case(
        "include cycle",
        main(
            f"class: {S}.Middle\nthing: !include a.yaml\n",
            {"a.yaml": "class: x.Y\nvalue: !include main.yaml\n"},
        ),
        "a.yaml",
        2,
        "thing.value",
        "include cycle: main.yaml -> a.yaml -> main.yaml",
    ),
    Case(
        "environment variable unset",
        main(f"class: {S}.Leaf\nmessage: hi\nname: ${{CAMERA_PASSWORD}}\n"),
        "main.yaml",
        3,
        "name",
        "environment variable CAMERA_PASSWORD is not set",
    ),
    Case(
        "unterminated placeholder",
        main(f"class: {S}.Leaf\nmessage: ${{GREETING\n"),
        "main.yaml",
        2,
        "message",
        "unterminated placeholder",
    ),
    Case(
        "nested unknown key",
        main(f"class: {S}.Middle\nthing:\n  class: {S}.Thing\n  valeu: 1\n"),
        "main.yaml",
        4,
        "thing.valeu",
        "unknown key 'valeu' .*did you mean 'value'",
    ),
    Case(
        "wrong type inside an included file",
        main(
            f"class: {S}.Middle\nthing: !include thing.yaml\n",
            {"thing.yaml": f"class: {S}.Thing\nvalue: many\n"},
        ),
        "thing.yaml",
        2,
        "thing.value",
        "expected int, got str 'many'",
    ),
    Case(
        "wrong key in a merged base",
        main(
            f"<<: !include base.yaml\nclass: {S}.Leaf\nmessage: hi\n",
            {"base.yaml": "name: x\nintervall: 5\n"},
        ),
        "base.yaml",
        2,
        "intervall",
        "unknown key 'intervall'",
    ),
    Case(
        "list item missing required key",
        main(f"class: {S}.Kitchen\nthings:\n  - class: {S}.Thing\n    value: 1\n  - class: {S}.Thing\n"),
        "main.yaml",
        5,
        "things[1].value",
        "missing required key 'value'",
    ),
    Case(
        "list item without class",
        main(f"class: {S}.Kitchen\nthings:\n  - value: 1\n"),
        "main.yaml",
        3,
        "things[0].class",
        "missing key 'class' \\(the dotted path of the Thing to build\\)",
    ),
    Case(
        "dict value of wrong type",
        main(f"class: {S}.Kitchen\nlimits:\n  min: 0\n  max: high\n"),
        "main.yaml",
        4,
        "limits.max",
        "expected float, got str 'high'",
    ),
    Case(
        "literal not allowed",
        main(f"class: {S}.Kitchen\nspeed: medium\n"),
        "main.yaml",
        2,
        "speed",
        "expected one of 'low', 'high', got str 'medium'",
    ),
    Case(
        "enum value unknown",
        main(f"class: {S}.Kitchen\nmode: turbo\n"),
        "main.yaml",
        2,
        "mode",
        "expected one of 'fast', 'slow', got str 'turbo'",
    ),
    Case(
        "optional of wrong type",
        main(f"class: {S}.Kitchen\ntimeout: soon\n"),
        "main.yaml",
        2,
        "timeout",
        "expected float \\| None, got str 'soon'",
    ),
    Case(
        "tuple of wrong length",
        main(f"class: {S}.Kitchen\nposition: [1, 2, 3]\n"),
        "main.yaml",
        2,
        "position",
        "expected tuple\\[float, float\\] \\(2 items\\), got a list of 3",
    ),
    Case(
        "int for an interface parameter",
        main(f"class: {S}.Kitchen\ncamera: 5\n"),
        "main.yaml",
        2,
        "camera",
        "expected str \\(a module name\\) \\| ICamLike, got int 5",
    ),
    Case(
        "object not implementing the interface",
        main(f"class: {S}.Kitchen\ncamera:\n  class: {S}.Thing\n  value: 1\n"),
        "main.yaml",
        3,
        "camera.class",
        f"{S}.Thing does not implement ICamLike",
    ),
    Case(
        "nested object of the wrong class",
        main(f"class: {S}.Middle\nthing:\n  class: {S}.Other\n"),
        "main.yaml",
        3,
        "thing.class",
        f"{S}.Other does not derive from Thing",
    ),
    Case(
        "abstract class",
        main(f"class: {S}.Middle\nthing: {{class: {S}.AbstractThing, value: 1}}\n"),
        "main.yaml",
        2,
        "thing.class",
        "is abstract and cannot be built \\(abstract: run\\)",
    ),
    Case(
        "duplicate key",
        main(f"class: {S}.Leaf\nmessage: hi\ninterval: 5\nmessage: ho\n"),
        "main.yaml",
        4,
        "message",
        "duplicate key 'message' \\(first written on line 2\\)",
    ),
    Case(
        "merge of a list",
        main(f"class: {S}.Leaf\n<<: !include list.yaml\n", {"list.yaml": "- a\n- b\n"}),
        "main.yaml",
        2,
        "<<",
        "'<<' merges a mapping .*got a list",
    ),
    Case(
        "unknown tag",
        main(f"class: {S}.Leaf\nmessage: !secret pw\n"),
        "main.yaml",
        2,
        "message",
        "unsupported tag !secret",
    ),
    Case(
        "top level is a list",
        main(f"- class: {S}.Leaf\n"),
        "main.yaml",
        1,
        None,
        "expected a mapping with a 'class' key at the top level, got a list",
    ),
    Case(
        "empty file",
        main(""),
        "main.yaml",
        1,
        None,
        "got an empty file",
    ),
    Case(
        "placeholder resolving to the wrong type",
        main(f"class: {S}.Leaf\nmessage: hi\ninterval: ${{INTERVAL:-soon}}\n"),
        "main.yaml",
        3,
        "interval",
        "expected float, got str 'soon'",
    ),
    Case(
        "unknown key in the included file of an included file",
        main(
            f"class: {S}.Kitchen\nnamed:\n  main: !include sub/thing.yaml\n",
            {"sub/thing.yaml": f"class: {S}.SpecialThing\nvalue: 1\nfactor: 2\nfactr: 3\n"},
        ),
        "sub/thing.yaml",
        4,
        "named.main.factr",
        "unknown key 'factr' .*did you mean 'factor'",
    ),
]


def write_files(root: Path, files: dict[str, str]) -> None:
    for name, text in files.items():
        path = root / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text)


@pytest.mark.parametrize("case", CASES, ids=[case.id for case in CASES])
def test_malformed_config_names_file_line_and_key(
    case: Case, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    write_files(tmp_path, case.files)
    monkeypatch.chdir(tmp_path)
    with pytest.raises(ConfigError, match=case.message) as info:
        load_and_build("main.yaml", environ=case.environ)
    error = info.value
    assert (error.file, error.line, error.key) == (case.file, case.line, case.key)
    text = str(error)
    assert text.startswith(f"{case.file}:{case.line}: ")
    if case.key:
        assert f"key '{case.key}': " in text
    assert "\n" not in text


def test_there_are_at_least_twenty_distinct_cases() -> None:
    assert len({case.id for case in CASES}) == len(CASES) >= 20


def test_constructor_error_is_reported_with_location(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    write_files(tmp_path, main(f"class: {S}.Kitchen\nthings:\n  - class: {S}.Picky\n    value: -1\n"))
    monkeypatch.chdir(tmp_path)
    # Validation cannot know that -1 is refused; the constructor's error still names the place.
    validate_config(load_config("main.yaml"))
    message = re.escape(f"building {S}.Picky failed: ValueError: value must not be negative")
    with pytest.raises(ConfigError, match=message) as info:
        load_and_build("main.yaml")
    assert (info.value.file, info.value.line, info.value.key) == ("main.yaml", 3, "things[0]")


def test_constructor_config_error_points_at_the_key_it_names(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    write_files(
        tmp_path, main(f"class: {S}.Kitchen\nthings:\n  - class: {S}.Picky\n    limit: 5\n    value: 7\n")
    )
    monkeypatch.chdir(tmp_path)
    with pytest.raises(
        ConfigError, match=r"^main\.yaml:5: key 'things\[0\]\.value': value must be <= 5, got 7$"
    ):
        load_and_build("main.yaml")


def test_validate_reports_the_first_problem_in_file_order(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    write_files(tmp_path, main(f"class: {S}.Kitchen\ncount: x\nratio: y\n"))
    monkeypatch.chdir(tmp_path)
    with pytest.raises(ConfigError, match="expected int") as info:
        validate_config(load_config("main.yaml"))
    assert info.value.key == "count"


def test_missing_top_level_file() -> None:
    with pytest.raises(ConfigError, match="file not found") as info:
        load_config("/nonexistent/nightcrew.yaml")
    assert info.value.file == "/nonexistent/nightcrew.yaml"


def test_scalar_for_an_object_parameter() -> None:
    config = {"class": f"{S}.Kitchen", "things": [5]}
    message = re.escape("expected a Thing description (a mapping with 'class'), got int 5")
    with pytest.raises(ConfigError, match=message) as info:
        validate_config(config)
    assert info.value.key == "things[0]"
