"""The JavaScript client's XML-RPC codec against nightcrew's own (comm/xmpp), in both directions.

``clients/js/test/wire.mjs`` encodes sample values as the client sends them, which nightcrew's
parser must read as the same values; and decodes what nightcrew writes.
"""

from __future__ import annotations

import json
import math
import subprocess
import xml.etree.ElementTree as ET
from datetime import UTC, datetime
from typing import Any

from nightcrew.comm.xmpp._xmlrpc import NS_RPC, build_call, parse_call

from .node import CLIENT, node_ready

WIRE = CLIENT / "test" / "wire.mjs"


def node(mode: str, stdin: str = "") -> str:
    done = subprocess.run(
        ["node", str(WIRE), mode], input=stdin, capture_output=True, text=True, timeout=60, check=False
    )
    assert done.returncode == 0, f"wire.mjs {mode} exited {done.returncode}:\n{done.stderr}"
    return done.stdout


def test_what_the_client_sends_is_read_by_nightcrew() -> None:
    node_ready()
    method, args = parse_call(ET.fromstring(f'<query xmlns="{NS_RPC}">{node("encode")}</query>'))
    assert method == "sample"
    nan, minus_inf = args[6], args[7]
    assert math.isnan(nan) and minus_inf == -math.inf
    assert args[:6] + args[8:] == [
        None,
        True,
        42,
        2**40,
        1.5,
        10.0,
        "a <b> & 'c' \u00b0",
        datetime(2026, 11, 10, 17, 50, 0, 250000, tzinfo=UTC),
        b"\x00\x01\xfe\xff",
        [1, "two", [3.5]],
        {"ra": 322.95, "name": "M39", "tags": []},
    ]
    assert isinstance(args[5], float)  # a whole `number` still travels as <double>


def test_what_nightcrew_sends_is_read_by_the_client() -> None:
    node_ready()
    values: list[Any] = [
        None,
        False,
        -7,
        -(2**40),
        0.1,
        math.inf,
        "x < y",
        datetime(2026, 11, 10, 5, 6, 7, 123456, tzinfo=UTC),
        b"\xff",
        {"nested": [{"a": 1}]},
    ]
    decoded = json.loads(node("decode", build_call("sample", values)))
    assert decoded == {
        "method": "sample",
        "params": [
            None,
            False,
            -7,
            -(2**40),
            0.1,
            {"number": "Infinity"},
            "x < y",
            {"date": "2026-11-10T05:06:07.123Z"},  # JavaScript dates hold milliseconds
            {"base64": "/w=="},
            {"struct": {"nested": [{"struct": {"a": 1}}]}},
        ],
    }


def test_events_are_decoded_by_the_catalogue_and_bad_ones_refused() -> None:
    node_ready()
    events = [
        ["NewImageEvent", '{"filename": "/images/a.fits", "image_type": "bias", "added_later": 1}'],
        ["GoodWeatherEvent", '{"eta": "2026-11-10T18:00:00+00:00"}'],
        ["NewImageEvent", '{"image_type": "bias"}'],
        ["NewImageEvent", '{"filename": "/images/a.fits", "image_type": "flat"}'],
        ["MoveRaDecEvent", '{"ra": "east", "dec": 1.0}'],
        ["NoSuchEvent", "{}"],
        ["TestEvent", "{not json"],
    ]
    decoded = json.loads(node("events", json.dumps(events)))
    assert decoded[:2] == [
        # A field the catalogue does not know (a newer sender) is ignored.
        {"class": "NewImageEvent", "fields": {"filename": "/images/a.fits", "image_type": "bias"}},
        {"class": "GoodWeatherEvent", "fields": {"eta": {"date": "2026-11-10T18:00:00.000Z"}}},
    ]
    assert [entry["problem"] for entry in decoded[2:-1]] == [
        "must have required property 'filename'",
        'at /image_type: expected "object"|"bias"|"dark"|"skyflat"|"domeflat"|"focus"|"acquisition"|'
        '"guiding"|null, got string "flat"',
        'at /ra: expected number, got string "east"',
        "an event the catalogue does not have",
    ]
    assert decoded[-1]["problem"].startswith("not JSON (")
