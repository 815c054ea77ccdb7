"""Valid configurations: loading (includes, merges, placeholders) and building (nested objects)."""

from __future__ import annotations

from typing import Any

import pytest

from nightcrew.config import (
    ConfigNode,
    Location,
    build_object,
    load_and_build,
    load_config,
    to_plain,
    validate_config,
)
from nightcrew.errors import ConfigError
from tests.config.conftest import WriteFiles
from tests.config.sample_classes import Kitchen, Leaf, LocalCam, Middle, Mode, SpecialThing, Thing

S = "tests.config.sample_classes"


def test_builds_with_keys_of_the_whole_kwargs_chain(write: WriteFiles) -> None:
    path = write({"leaf.yaml": f"class: {S}.Leaf\nmessage: hi\ninterval: 5\nlabel: L\nname: n\ntimeout: 2\n"})
    leaf = load_and_build(path)
    assert isinstance(leaf, Leaf)
    assert (leaf.message, leaf.label, leaf.name) == ("hi", "L", "n")
    # int given for float parameters arrives as float.
    assert leaf.interval == 5.0 and isinstance(leaf.interval, float)
    assert leaf.timeout == 2.0 and isinstance(leaf.timeout, float)


def test_builds_nested_objects_lists_and_dicts_of_them(write: WriteFiles) -> None:
    path = write(
        {
            "kitchen.yaml": f"""\
class: {S}.Kitchen
thing: {{class: {S}.SpecialThing, value: 1, factor: 2}}
things:
  - {{class: {S}.Thing, value: 2}}
  - {{class: {S}.Thing, value: 3, label: three}}
named:
  a: {{class: {S}.Thing, value: 4}}
camera: {{class: {S}.LocalCam, exposure: 3}}
"""
        }
    )
    kitchen = load_and_build(path)
    assert isinstance(kitchen.thing, SpecialThing)
    assert (kitchen.thing.value, kitchen.thing.factor) == (1, 2.0)
    assert [t.value for t in kitchen.things] == [2, 3]
    assert kitchen.things[1].label == "three"
    assert isinstance(kitchen.named["a"], Thing) and kitchen.named["a"].value == 4
    assert isinstance(kitchen.camera, LocalCam) and kitchen.camera.exposure == 3.0


def test_converts_scalars_as_hints_ask(write: WriteFiles) -> None:
    path = write(
        {
            "kitchen.yaml": f"""\
class: {S}.Kitchen
count: 3
ratio: 2
enabled: true
mode: SLOW
speed: high
tags: [a, b]
limits: {{min: 1, max: 2.5}}
position: [1, 2]
camera: telescope_camera
timeout: null
untyped: {{class: {S}.Thing, value: 1}}
"""
        }
    )
    kitchen = load_and_build(path)
    assert isinstance(kitchen, Kitchen)
    assert (kitchen.count, kitchen.ratio, kitchen.enabled) == (3, 2.0, True)
    assert kitchen.mode is Mode.SLOW
    assert kitchen.speed == "high"
    assert kitchen.tags == ["a", "b"]
    assert kitchen.limits == {"min": 1, "max": 2.5}
    assert kitchen.position == (1.0, 2.0)
    # A string for ``str | ICamLike`` is a module name: the module makes a proxy of it later.
    assert kitchen.camera == "telescope_camera"
    assert kitchen.timeout is None
    # Without a hint a description is data, handed over as a plain dict.
    assert kitchen.untyped == {"class": f"{S}.Thing", "value": 1}
    assert type(kitchen.untyped) is dict


def test_enum_by_value(write: WriteFiles) -> None:
    assert load_and_build(write({"k.yaml": f"class: {S}.Kitchen\nmode: slow\n"})).mode is Mode.SLOW


def test_dict_without_class_for_object_or_dict_stays_a_dict(write: WriteFiles) -> None:
    middle = load_and_build(write({"m.yaml": f"class: {S}.Middle\nthing: {{value: 1}}\n"}))
    assert isinstance(middle, Middle)
    assert middle.thing == {"value": 1} and type(middle.thing) is dict


def test_include_inserts_a_file_relative_to_the_including_file(write: WriteFiles) -> None:
    path = write(
        {
            "conf/main.yaml": f"class: {S}.Middle\nthing: !include parts/thing.yaml\n",
            "conf/parts/thing.yaml": f"class: {S}.Thing\nvalue: 7\nlabel: !include label.yaml\n",
            "conf/parts/label.yaml": "seven\n",
        }
    )
    middle = load_and_build(path)
    assert isinstance(middle.thing, Thing)
    assert (middle.thing.value, middle.thing.label) == (7, "seven")


def test_merge_include_keys_of_the_including_file_win(write: WriteFiles) -> None:
    path = write(
        {
            "leaf.yaml": f"class: {S}.Leaf\n<<: !include base.yaml\nmessage: mine\n",
            "base.yaml": "message: base\ninterval: 3\nname: from-base\n",
        }
    )
    config = load_config(path)
    assert config == {"class": f"{S}.Leaf", "message": "mine", "interval": 3, "name": "from-base"}
    # Every key remembers the file it was written in.
    assert config.location_of("interval") == Location("base.yaml", 2)
    assert config.location_of("message") == Location("leaf.yaml", 3)


def test_merged_keys_the_including_file_replaces_are_not_read(write: WriteFiles) -> None:
    """An overlay's own comm replaces the bundled file's, whose password file need not exist."""
    path = write(
        {
            "leaf.yaml": f"class: {S}.Leaf\n<<: !include base.yaml\nmessage: mine\n",
            "base.yaml": "message: !include secrets/base.password\ninterval: 3\n",
        }
    )
    assert load_config(path) == {"class": f"{S}.Leaf", "message": "mine", "interval": 3}


def test_skipped_top_level_keys_are_not_read(write: WriteFiles) -> None:
    path = write({"leaf.yaml": f"class: {S}.Leaf\nmessage: !include missing.yaml\ninterval: ${{UNSET_X}}\n"})
    assert load_config(path, environ={}, skip_keys=("message", "interval")) == {"class": f"{S}.Leaf"}


def test_merge_of_several_sources_earlier_wins_and_anchors_work(write: WriteFiles) -> None:
    path = write(
        {
            "leaf.yaml": f"""\
defaults: &defaults
  interval: 1
  label: anchored
class: {S}.Leaf
""",
            "main.yaml": f"""\
class: {S}.Leaf
<<: [!include a.yaml, !include b.yaml]
message: hi
""",
            "a.yaml": "name: a\n",
            "b.yaml": "name: b\ninterval: 4\n",
        }
    )
    assert load_config(path)["defaults"] == {"interval": 1, "label": "anchored"}
    config = load_config("main.yaml")
    assert (config["name"], config["interval"]) == ("a", 4)
    write({"anchor.yaml": "base: &b {interval: 2, message: x}\nother:\n  <<: *b\n  message: y\n"})
    assert load_config("anchor.yaml")["other"] == {"interval": 2, "message": "y"}


def test_environment_placeholders(write: WriteFiles) -> None:
    path = write(
        {
            "env.yaml": """\
class: x.Y
interval: ${INTERVAL:-10}
ratio: ${RATIO}
flag: ${FLAG:-false}
quoted: "${INTERVAL:-10}"
url: http://${HOST:-localhost}:${PORT}/x
password: ${PASSWORD}
empty_uses_default: ${EMPTY:-fallback}
escaped: $${NOT_A_VAR}
nothing: ${NOTHING:-}
part: !include ${PART_DIR:-parts}/part.yaml
""",
            "parts/part.yaml": "42\n",
        }
    )
    environ = {"RATIO": "2.5", "PORT": "8080", "PASSWORD": "s3cret: 1", "EMPTY": ""}
    config = load_config(path, environ=environ)
    assert config["interval"] == 10 and isinstance(config["interval"], int)
    assert config["ratio"] == 2.5
    assert config["flag"] is False
    assert config["quoted"] == "10"
    assert config["url"] == "http://localhost:8080/x"
    # A substituted value is one scalar, never YAML structure.
    assert config["password"] == "s3cret: 1"
    assert config["empty_uses_default"] == "fallback"
    assert config["escaped"] == "${NOT_A_VAR}"
    assert config["nothing"] is None
    assert config["part"] == 42


def test_yaml_details_exponent_floats_and_keys_stay_strings(write: WriteFiles) -> None:
    config = load_config(write({"k.yaml": "class: x.Y\nratio: 1e3\nlimits:\n  on: 1\n  off: 2\n"}))
    assert config["ratio"] == 1000.0
    assert config["limits"] == {"on": 1, "off": 2}


def test_locations_of_nested_keys_and_list_items(write: WriteFiles) -> None:
    config = load_config(write({"k.yaml": "class: x.Y\nthings:\n  - a\n  - b\nsub:\n  key: 1\n"}))
    assert config.location == Location("k.yaml", 1)
    assert config["things"].location_of(1) == Location("k.yaml", 4)
    assert isinstance(config["sub"], ConfigNode)
    assert config["sub"].location_of("key") == Location("k.yaml", 6)


def test_validate_with_expected_class(write: WriteFiles) -> None:
    config = load_config(write({"leaf.yaml": f"class: {S}.Leaf\nmessage: hi\n"}))
    validate_config(config, Middle)
    with pytest.raises(ConfigError, match=f"{S}.Leaf does not derive from Thing") as info:
        validate_config(config, Thing)
    assert (info.value.file, info.value.line, info.value.key) == ("leaf.yaml", 1, "class")


def test_build_from_a_plain_dict() -> None:
    config: dict[str, Any] = {"class": f"{S}.Middle", "thing": {"class": f"{S}.Thing", "value": 1}}
    middle = build_object(config, Middle)
    assert isinstance(middle.thing, Thing)
    with pytest.raises(ConfigError, match="expected int, got str 'x'") as info:
        build_object({"class": f"{S}.Thing", "value": "x"})
    assert (info.value.file, info.value.line, info.value.key) == (None, None, "value")


def test_keys_added_in_code_are_validated_and_built(write: WriteFiles) -> None:
    config = load_config(write({"leaf.yaml": f"class: {S}.Leaf\nmessage: hi\n"}))
    config["name"] = "leaf"  # as ``nightcrew run`` does for a module without a name
    assert load_and_build("leaf.yaml").name is None
    assert build_object(config).name == "leaf"


def test_to_plain_strips_locations(write: WriteFiles) -> None:
    config = load_config(write({"k.yaml": "class: x.Y\na: {b: [1, {c: 2}]}\n"}))
    plain = to_plain(config)
    assert plain == {"class": "x.Y", "a": {"b": [1, {"c": 2}]}}
    assert type(plain["a"]) is dict and type(plain["a"]["b"]) is list


def test_unevaluable_hint_accepts_anything(write: WriteFiles) -> None:
    path = write({"h.yaml": "class: tests.config.hidden_hints.HalfHinted\nwhere: [1, 2]\ncount: 3\n"})
    built = load_and_build(path)
    assert (built.where, built.count) == ([1, 2], 3)


def test_public_api() -> None:
    import nightcrew.config

    assert sorted(nightcrew.config.__all__) == [
        "ConfigList",
        "ConfigNode",
        "DataPath",
        "InputPath",
        "Location",
        "build_object",
        "check_value",
        "config_files",
        "is_secret_key",
        "load_and_build",
        "load_config",
        "load_data_file",
        "parse_data",
        "parse_yaml",
        "to_plain",
        "unset_variable",
        "validate_config",
    ]
    assert all(hasattr(nightcrew.config, name) for name in nightcrew.config.__all__)
