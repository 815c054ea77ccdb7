"""pyobs' value vocabulary and event bodies ↔ nightcrew's wire values (no server needed)."""

from __future__ import annotations

import json
import logging
import time
import xml.etree.ElementTree as ET
from collections.abc import Callable
from datetime import UTC, datetime
from typing import Any

import pytest

from nightcrew.comm.rpc import Fault
from nightcrew.comm.xmpp import XmppComm
from nightcrew.comm.xmpp._pyobs_events import event_body, translate_event
from nightcrew.comm.xmpp._pyobs_states import pyobs_state, state_namespace
from nightcrew.comm.xmpp._pyobs_values import (
    build_pyobs_fault,
    build_pyobs_params,
    is_pyobs_call,
    parse_pyobs_fault,
    parse_pyobs_params,
    state_element,
)
from nightcrew.errors import CodecError, ConfigError
from nightcrew.events import LogEvent
from nightcrew.focus.series import FocusOutsideSeriesError

RPC = "{jabber:iq:rpc}"
PY = "{urn:pyobs:rpc:1}"


def _params(*inner: str) -> ET.Element:
    """``<params>`` as pyobs writes them: the inner elements in pyobs' namespace after a round trip."""
    values = "".join(
        f"<param><value><value xmlns='urn:pyobs:rpc:1'>{x}</value></value></param>" for x in inner
    )
    return ET.fromstring(f"<params xmlns='jabber:iq:rpc'>{values}</params>")


@pytest.mark.parametrize(
    "value",
    [None, True, False, 0, -7, 2.5, float("inf"), "text <&>", [1, "a", None], {"a": [1.5, {"b": True}]}, []],
)
def test_values_survive_a_round_trip(value: Any) -> None:
    wire = ET.fromstring(ET.tostring(build_pyobs_params([value], "argument")))
    assert parse_pyobs_params(wire, "argument") == [value]


def test_pyobs_elements_are_read_in_its_namespace_or_none() -> None:
    params = _params(
        "<double>3.25</double>",
        "<boolean>true</boolean>",
        "<tuple><item><int>1</int></item><item><string>x</string></item></tuple>",
        "<dict><entry><key><string>k</string></key><val><nil/></val></entry></dict>",
        "<state><ra><double>10.0</double></ra><dec><double>-5.0</double></dec></state>",
    )
    assert parse_pyobs_params(params, "argument") == [
        3.25,
        True,
        [1, "x"],
        {"k": None},
        {"ra": 10.0, "dec": -5.0},
    ]


@pytest.mark.parametrize(
    ("inner", "message"),
    [
        ("<complex>1+2j</complex>", "argument 1: pyobs value <complex> has no nightcrew equivalent"),
        ("<int>1.5</int>", "argument 1: '1.5' is not a valid pyobs <int>"),
        ("<boolean>yes</boolean>", "argument 1: 'yes' is not a valid pyobs <boolean>"),
        ("<items><item><base64>AA==</base64></item></items>", r"argument 1\[0\]: pyobs value <base64>"),
        ("<dict><entry><key><double>1.0</double></key><val><nil/></val></entry></dict>", "key must be"),
    ],
)
def test_what_nightcrew_cannot_map_is_one_clear_codec_error(inner: str, message: str) -> None:
    with pytest.raises(CodecError, match=message):
        parse_pyobs_params(_params(inner), "argument")


def test_bytes_cannot_travel_to_pyobs() -> None:
    with pytest.raises(CodecError, match=r"result 1: a bytes cannot travel to pyobs"):
        build_pyobs_params([b"\x00"], "result")


def test_a_pyobs_call_is_told_by_its_wrapped_values() -> None:
    plain = ET.fromstring(
        "<query xmlns='jabber:iq:rpc'><methodCall><methodName>add</methodName><params>"
        "<param><value><double>1.0</double></value></param></params></methodCall></query>"
    )
    pyobs = ET.fromstring(
        "<query xmlns='jabber:iq:rpc'><methodCall><methodName>add</methodName></methodCall></query>"
    )
    pyobs.find(f"{RPC}methodCall").append(_params("<double>1.0</double>"))  # type: ignore[union-attr]
    assert not is_pyobs_call(plain)
    assert is_pyobs_call(pyobs)


def test_faults_keep_shared_classes_and_name_the_nearest_shared_base() -> None:
    moved = ET.fromstring(ET.tostring(build_pyobs_fault(Fault("MoveError", "below the horizon"))))
    body = moved.find(f"{RPC}value/{PY}fault")
    assert body is not None
    assert body.findtext("exception") == "pyobs.utils.exceptions.MoveError"
    assert [b.text for b in body.iter("base")] == ["pyobs.utils.exceptions.MotionError"]
    name = FocusOutsideSeriesError.__name__  # imported: known to nightcrew's error registry
    ours = ET.fromstring(ET.tostring(build_pyobs_fault(Fault(name, "move the series"))))
    body = ours.find(f"{RPC}value/{PY}fault")
    assert body is not None
    assert body.findtext("exception") == "nightcrew.errors.FocusOutsideSeriesError"
    assert [b.text for b in body.iter("base")] == ["pyobs.utils.exceptions.InvalidArgumentError"]
    fault = parse_pyobs_fault(moved)
    assert (fault.error_class, fault.message) == ("MoveError", "below the horizon")


def _body(name: str, data: dict[str, Any], age: float = 0.0) -> str:
    return json.dumps({"type": name, "timestamp": time.time() - age, "uuid": "u", "data": data})


def test_pyobs_event_bodies_become_nightcrew_fields() -> None:
    body = _body("NewImageEvent", {"filename": "/a.fits", "image_type": "object", "raw": None})
    assert translate_event(body, "NewImageEvent", "cam") == {"filename": "/a.fits", "image_type": "object"}


def test_fields_pyobs_names_otherwise_are_renamed_and_known_extras_dropped() -> None:
    offsets = _body("OffsetsRaDecEvent", {"ra": 0.5, "dec": -0.25})
    assert translate_event(offsets, "OffsetsRaDecEvent", "tel") == {"dra": 0.5, "ddec": -0.25}
    task = _body("TaskFinishedEvent", {"name": "M31", "id": "7", "obsnum": 3})
    assert translate_event(task, "TaskFinishedEvent", "robotic") == {"name": "M31", "id": "7"}


def test_pyobs_log_records_become_nightcrew_log_events_quietly(caplog: pytest.LogCaptureFixture) -> None:
    # The fields pyobs-core 2.19's CommLoggingHandler sends (time is UTC without an offset).
    record = {
        "time": "2026-11-27T15:27:13.357000",
        "level": "INFO",
        "filename": "module.py",
        "function": "open",
        "line": 896,
        "message": "Set module state to ready.",
        "sender": "",
    }
    with caplog.at_level(logging.INFO, logger="nightcrew.comm.xmpp._pyobs_events"):
        fields = translate_event(_body("LogEvent", record), "LogEvent", "pytel")
    assert caplog.text == ""
    assert fields is not None
    event = LogEvent.from_dict(fields)
    assert (event.level, event.logger, event.message) == ("INFO", "pyobs", "Set module state to ready.")
    assert (event.filename, event.line, event.time.isoformat()) == (
        "module.py",
        896,
        "2026-11-27T15:27:13.357000+00:00",
    )


def test_nightcrew_log_events_carry_every_field_pyobs_requires() -> None:
    event = LogEvent(time=datetime(2026, 11, 27, tzinfo=UTC), level="WARNING", logger="x", message="m")
    data = json.loads(event_body("LogEvent", event.to_dict()))["data"]
    # pyobs builds LogEvent(time, level, filename, function, line, message) from these keys.
    assert {"time", "level", "filename", "function", "line", "message"} <= set(data)
    assert (data["filename"], data["function"], data["line"], data["message"]) == ("", "", 0, "m")


@pytest.mark.parametrize(
    ("make_body", "logged"),
    [
        (
            lambda: _body("NewImageEvent", {"filename": "/a", "raw": "/r"}),
            "fields nightcrew's NewImageEvent lacks: raw",
        ),
        (lambda: _body("TestEvent", {"message": "x"}), "type 'TestEvent' on the node of NewImageEvent"),
        (lambda: "{not json", "skipped malformed pyobs NewImageEvent from cam"),
        (lambda: _body("NewImageEvent", {"filename": "/a"}, age=120), "120 s old"),
    ],
)
def test_pyobs_events_nightcrew_cannot_take_are_logged_and_skipped(
    make_body: Callable[[], str], logged: str, caplog: pytest.LogCaptureFixture
) -> None:
    # Bodies are made when the test runs: their timestamps must be fresh, not from collection.
    with caplog.at_level(logging.INFO, logger="nightcrew.comm.xmpp._pyobs_events"):
        assert translate_event(make_body(), "NewImageEvent", "cam") is None
    assert logged in caplog.text


def test_the_dialect_is_checked_when_the_comm_is_built() -> None:
    assert XmppComm("camera@obs.test", "pw", dialect="pyobs").jid == "camera@obs.test/pyobs"
    assert XmppComm("camera@obs.test/dome", "pw", dialect="pyobs").jid == "camera@obs.test/dome"
    with pytest.raises(ConfigError, match="unknown dialect 'pyobs2' \\(known: nightcrew, pyobs\\)") as caught:
        XmppComm("camera@obs.test", "pw", dialect="pyobs2")
    assert caught.value.key == "dialect"


def test_own_events_become_the_pyobs_states_they_tell() -> None:
    now = datetime(2026, 11, 27, 15, 0, 0, 500000, tzinfo=UTC)
    motion = pyobs_state("MotionStatusChangedEvent", {"status": "moving", "devices": {"axis": "idle"}}, now)
    assert motion is not None
    element = state_element(state_namespace("IMotion"), motion, "state")
    ns = "{urn:pyobs:state:IMotion:1}"
    assert element.tag == f"{ns}state"
    # nightcrew's "moving" is pyobs' "slewing"; times without an offset (astropy's Time reads them).
    assert element.findtext(f"{ns}status/string") == "slewing"
    assert element.findtext(f"{ns}time/string") == "2026-11-27T15:00:00.500000"
    device = element.find(f"{ns}devices/items/item/{{urn:pyobs:rpc:1}}state")
    assert device is not None and [child.tag.rpartition("}")[2] for child in device] == ["name", "status"]
    assert pyobs_state("FilterChangedEvent", {"filter_name": "R"}, now) == {
        "filter": "R",
        "time": "2026-11-27T15:00:00.500000",
    }
    assert pyobs_state("NewImageEvent", {"filename": "/a.fits"}, now) is None
