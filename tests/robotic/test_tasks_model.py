"""The task model: valid groups build, every malformed one is rejected naming the exact field."""

from __future__ import annotations

import copy
import json
import re
from datetime import UTC, datetime
from typing import Any

import pytest

from nightcrew.robotic.tasks import (
    DEFAULT_OVERHEADS,
    ConfigurationType,
    InvalidTaskError,
    OverheadModel,
    RequestGroup,
    estimate_duration,
    load_request_group_file,
    parse_request_group,
)


def valid_group_data() -> dict[str, Any]:
    """A small valid request group (two requests, three configuration types), as a file holds it."""
    window = {"start": "2026-11-10T17:50:00Z", "end": "2026-11-11T05:00:00Z"}
    return {
        "name": "m15 photometry",
        "proposal": "test",
        "priority": 2.0,
        "ipp": 1.5,
        "requests": [
            {
                "location": {"telescope_class": "0m4"},
                "windows": [dict(window)],
                "configurations": [
                    {
                        "type": "EXPOSE",
                        "target": {"name": "M15", "ra": 322.493, "dec": 12.167},
                        "constraints": {"max_airmass": 1.8},
                        "instrument_configs": [
                            {"exposure_time": 30, "exposure_count": 3, "optical_elements": {"filter": "V"}},
                            {"exposure_time": 20.0, "optical_elements": {"filter": "R"}, "binning": 2},
                        ],
                    },
                    {
                        "type": "SCRIPT",
                        "extra_params": {"script": "class: nightcrew.robotic.scripts.Noop", "duration": 60},
                    },
                ],
            },
            {
                "location": {"telescope_class": "0m4", "site": "sim"},
                "windows": [dict(window)],
                "configurations": [{"type": "BIAS", "instrument_configs": [{"exposure_time": 0}]}],
            },
        ],
    }


def test_a_valid_group_builds_with_defaults_and_utc_times() -> None:
    data = valid_group_data()
    data["requests"][0]["windows"][0]["end"] = "2026-11-11T05:00:00"  # no zone: UTC
    group = parse_request_group(data)
    assert isinstance(group, RequestGroup)
    request = group.requests[0]
    assert request.windows[0].end == datetime(2026, 11, 11, 5, tzinfo=UTC)
    assert request.configurations[0].type is ConfigurationType.EXPOSE
    assert request.configurations[0].constraints.max_airmass == 1.8
    assert request.configurations[0].constraints.max_sun_altitude == -12.0  # default
    assert request.acceptability_threshold == 90.0
    # JSON round trip gives the same group (what the SQLite archive stores).
    assert RequestGroup.model_validate_json(group.model_dump_json()) == group


def _set(data: dict[str, Any], path: str, value: Any) -> None:
    """Set (or with ``...`` delete) the value at a dotted path like ``requests.0.windows``."""
    *parents, last = path.split(".")
    node: Any = data
    for part in parents:
        node = node[int(part)] if part.isdigit() else node[part]
    key: Any = int(last) if last.isdigit() else last
    if value is ...:
        del node[key]
    else:
        node[key] = value


R0 = "requests.0"
C0 = "requests.0.configurations.0"
MALFORMED = [
    # (where to change, new value (... deletes), the expected message)
    ("name", "", "name: must not be empty"),
    ("proposal", ..., "proposal: required"),
    ("priority", 0, "priority: must be > 0"),
    ("ipp", 2.5, "ipp: must be <= 2"),
    ("observation_type", "SOON", "observation_type: must be one of 'NORMAL', 'TIME_CRITICAL' or"),
    ("requests", [], "requests: must have at least 1 entry"),
    (f"{R0}.windows", [], "requests[0].windows: at least one window is needed (or a cadence)"),
    (
        f"{R0}.windows.0.end",
        "2026-11-10T17:00:00Z",
        "requests[0].windows[0].end: must be after start (2026-11-10T17:50:00+00:00)",
    ),
    (f"{R0}.windows.0.start", "tonight", "requests[0].windows[0].start: expected a date and time"),
    (f"{R0}.location.telescope_class", ..., "requests[0].location.telescope_class: required"),
    (f"{R0}.acceptability_threshold", 101, "requests[0].acceptability_threshold: must be <= 100"),
    (f"{C0}.type", "OBSERVE", "requests[0].configurations[0].type: must be one of 'EXPOSE'"),
    (f"{C0}.target", ..., "requests[0].configurations[0].target: required for EXPOSE configurations"),
    (f"{C0}.target.ra", 360, "requests[0].configurations[0].target.ra: must be < 360"),
    (f"{C0}.target.dec", -91, "requests[0].configurations[0].target.dec: must be >= -90"),
    (f"{C0}.target.parallax", -1, "requests[0].configurations[0].target.parallax: must be >= 0"),
    (
        f"{C0}.constraints.max_airmass",
        0.9,
        "requests[0].configurations[0].constraints.max_airmass: must be >= 1",
    ),
    (
        f"{C0}.constraints.max_lunar_phase",
        1.5,
        "requests[0].configurations[0].constraints.max_lunar_phase: must be <= 1",
    ),
    (
        f"{C0}.constraints.min_sun_altitude",
        -6,
        "requests[0].configurations[0].constraints.min_sun_altitude: must be < max_sun_altitude (-12)",
    ),
    (
        f"{C0}.acquisition_config",
        {"mode": "MAGIC"},
        "requests[0].configurations[0].acquisition_config.mode: must be one of 'OFF', 'ON'",
    ),
    (
        f"{C0}.guiding_config",
        {"mode": "ON", "exposure_time": -1},
        "requests[0].configurations[0].guiding_config.exposure_time: must be > 0",
    ),
    (
        f"{C0}.instrument_configs",
        [],
        "requests[0].configurations[0].instrument_configs: EXPOSE configurations need",
    ),
    (
        f"{C0}.instrument_configs.0.exposure_time",
        0,
        "requests[0].configurations[0].instrument_configs[0].exposure_time: must be > 0",
    ),
    (
        f"{C0}.instrument_configs.1.exposure_time",
        "30",
        "requests[0].configurations[0].instrument_configs[1].exposure_time: expected a number, got str '30'",
    ),
    (
        f"{C0}.instrument_configs.0.exposure_count",
        0,
        "requests[0].configurations[0].instrument_configs[0].exposure_count: must be >= 1",
    ),
    (
        f"{C0}.instrument_configs.0.exposure_count",
        1.5,
        "requests[0].configurations[0].instrument_configs[0].exposure_count: expected a whole number",
    ),
    (
        f"{C0}.instrument_configs.0.binning",
        True,
        "requests[0].configurations[0].instrument_configs[0].binning: expected a whole number, got bool True",
    ),
    (
        f"{C0}.instrument_configs.0.exposure_tme",
        30,
        "requests[0].configurations[0].instrument_configs[0].exposure_tme: unknown field",
    ),
    (
        f"{C0}.repeat_duration",
        600,
        "requests[0].configurations[0].repeat_duration: only allowed for REPEAT_EXPOSE",
    ),
    (
        f"{C0}.type",
        "REPEAT_EXPOSE",
        "requests[0].configurations[0].repeat_duration: required for REPEAT_EXPOSE configurations",
    ),
    (
        "requests.0.configurations.1.extra_params.script",
        ...,
        "requests[0].configurations[1].extra_params.script: required for SCRIPT configurations",
    ),
    (
        "requests.0.configurations.1.extra_params.duration",
        -5,
        "requests[0].configurations[1].extra_params.duration: must be > 0",
    ),
    (
        "requests.1.configurations.0.instrument_configs.0.exposure_time",
        1.0,
        "requests[1].configurations[0].instrument_configs[0].exposure_time: must be 0 for BIAS",
    ),
]


@pytest.mark.parametrize(("path", "value", "message"), MALFORMED, ids=[case[0] for case in MALFORMED])
def test_a_malformed_group_is_rejected_naming_the_field(path: str, value: Any, message: str) -> None:
    data = valid_group_data()
    _set(data, path, value)
    with pytest.raises(InvalidTaskError, match="^" + re.escape(message)) as caught:
        parse_request_group(data)
    assert len(caught.value.problems) == 1, caught.value.problems


def test_all_problems_are_reported_in_document_order() -> None:
    data = valid_group_data()
    _set(data, "priority", -1)
    _set(data, f"{C0}.instrument_configs.0.exposure_time", 0)
    _set(data, "requests.1.windows", "always")
    with pytest.raises(InvalidTaskError, match=r"^priority: must be > 0 \(and 2 more problems\)$") as caught:
        parse_request_group(data)
    assert [p.path for p in caught.value.problems] == [
        "priority",
        "requests[0].configurations[0].instrument_configs[0].exposure_time",
        "requests[1].windows",
    ]


def test_files_name_themselves_in_the_message(tmp_path: Any) -> None:
    data = valid_group_data()
    good = tmp_path / "good.json"
    good.write_text(json.dumps(data))
    assert load_request_group_file(good).name == "m15 photometry"
    _set(data, "ipp", 0.1)
    bad = tmp_path / "bad.yaml"
    bad.write_text(json.dumps(data))  # JSON is YAML too
    with pytest.raises(InvalidTaskError, match=re.escape(f"{bad}: ipp: must be >= 0.5")):
        load_request_group_file(bad)
    broken = tmp_path / "broken.yaml"
    broken.write_text("name: [unclosed\n")
    with pytest.raises(InvalidTaskError, match="line 2: invalid YAML"):
        load_request_group_file(broken)
    with pytest.raises(InvalidTaskError, match="file not found"):
        load_request_group_file(tmp_path / "missing.yaml")
    listed = tmp_path / "list.yaml"
    listed.write_text("- 1\n")
    with pytest.raises(InvalidTaskError, match="expected a mapping, got a list"):
        load_request_group_file(listed)


def test_duration_adds_exposures_readouts_and_overheads() -> None:
    group = parse_request_group(valid_group_data())
    overheads = OverheadModel(
        request_setup_s=100,
        configuration_setup_s=10,
        filter_change_s=5,
        readout_s=4,
        readout_by_binning_s={2: 1},
        per_exposure_s=1,
    )
    estimate = estimate_duration(group.requests[0], overheads)
    expose = 10.0 + 5 + 3 * (30 + 4 + 1) + 5 + (20 + 1 + 1)  # set-up, V series, filter change, R binned
    script = 10.0 + 60
    assert estimate.setup_s == 100
    assert estimate.configurations_s == (expose, script)
    assert estimate.total_s == 100 + expose + script
    bias = estimate_duration(group.requests[1], overheads)
    assert bias.total_s == 100 + 10 + (0 + 4 + 1)  # no optical elements: no filter change


def test_duration_counts_acquisition_guiding_and_repeats() -> None:
    data = valid_group_data()
    config = data["requests"][0]["configurations"][0]
    config["type"] = "REPEAT_EXPOSE"
    config["repeat_duration"] = 1800
    config["acquisition_config"] = {"mode": "WCS"}
    config["guiding_config"] = {"mode": "ON"}
    request = parse_request_group(data).requests[0]
    overheads = DEFAULT_OVERHEADS
    expected = overheads.configuration_setup_s + overheads.acquisition_s + overheads.guiding_setup_s + 1800
    assert estimate_duration(request, overheads).configurations_s[0] == expected
    # A repeat shorter than one cycle still does the cycle once.
    config["repeat_duration"] = 1
    short = parse_request_group(data).requests[0]
    assert estimate_duration(short).configurations_s[0] > expected - 1800 + 100


def test_overhead_model_is_validated_too() -> None:
    with pytest.raises(ValueError, match="readout_s"):
        OverheadModel(readout_s=-1)


def test_models_are_immutable() -> None:
    group = parse_request_group(valid_group_data())
    with pytest.raises(ValueError, match="frozen"):
        group.name = "other"


def test_the_input_is_not_changed() -> None:
    data = valid_group_data()
    before = copy.deepcopy(data)
    parse_request_group(data)
    assert data == before
