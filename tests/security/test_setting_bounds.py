"""The settings and arguments the review found without physical bounds, bounded (issue 26):
the watchdog's interval and limits, the XMPP comm's pings and timeouts, a camera's gain and
offset, a focus series' step. Each refusal is one line naming the key or argument."""

from __future__ import annotations

import typing
from typing import Any

import pytest

from nightcrew.comm.codec import decode
from nightcrew.config import build_object
from nightcrew.errors import CodecError, ConfigError
from nightcrew.interfaces import IAutoFocus, IGain

WATCHDOG = {
    "class": "nightcrew.modules.safety.SafetyWatchdog",
    "roof": "roof",
    "telescope": None,
    "name": "w",
}
XMPP = {"class": "nightcrew.comm.xmpp.XmppComm", "jid": "roof@observatory.local", "password": "x"}


@pytest.mark.parametrize(
    ("base", "key", "value", "message"),
    [
        (WATCHDOG, "interval", 1e-320, "1e-320 is out of range (must be >= 0.01 s)"),
        (WATCHDOG, "answer_timeout", 1e9, "1000000000.0 is out of range (must be <= 86400.0 s)"),
        (WATCHDOG, "watch", {"roof": 1e308}, "1e+308 is out of range (must be <= 86400.0 s)"),
        (XMPP, "ping_interval", 1e-320, "1e-320 is out of range (must be >= 0.01 s)"),
        (XMPP, "ping_timeout", 1e308, "1e+308 is out of range (must be <= 86400.0 s)"),
        (XMPP, "connect_timeout", 0, "0 is out of range (must be >= 0.01 s)"),
    ],
)
def test_settings_beyond_physics_are_one_error(
    base: dict[str, Any], key: str, value: Any, message: str
) -> None:
    config = {"watch": {"roof": 60}, **base, key: value} if base is WATCHDOG else {**base, key: value}
    with pytest.raises(ConfigError) as refused:
        build_object(config)
    named = f"{key}.roof" if isinstance(value, dict) else key
    assert str(refused.value) == f"key '{named}': {message}"


def test_the_bounded_settings_keep_their_ordinary_values() -> None:
    build_object({**WATCHDOG, "watch": {"roof": 60}, "interval": 10, "answer_timeout": 10})
    build_object({**XMPP, "ping_interval": None, "ping_timeout": 10, "connect_timeout": 10})


def _hint(method: Any, argument: str) -> Any:
    return typing.get_type_hints(method, include_extras=True)[argument]


@pytest.mark.parametrize(
    ("method", "argument", "value", "problem"),
    [
        (IGain.set_gain, "gain", 1e308, "must be <= 1000000.0"),
        (IGain.set_gain, "gain", -1.0, "must be >= 0.0"),
        (IGain.set_offset, "offset", -1e308, "must be >= -1000000.0"),
        (IAutoFocus.auto_focus, "step", 0.0, "must be > 0.0 mm"),
        (IAutoFocus.auto_focus, "step", 1e308, "must be <= 100.0 mm"),
    ],
)
def test_arguments_beyond_physics_are_refused_by_the_codec(
    method: Any, argument: str, value: float, problem: str
) -> None:
    with pytest.raises(CodecError, match=rf"^{argument}: .* is out of range \({problem}\)$"):
        decode(value, _hint(method, argument), argument)
    assert decode(1.0, _hint(method, argument), argument) == 1.0  # an ordinary value passes
