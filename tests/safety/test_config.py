"""Bad watchdog, roof and telescope options are refused when the module is built, naming the key."""

from __future__ import annotations

from typing import Any

import pytest

from nightcrew.errors import ConfigError
from nightcrew.modules.safety import SafetyWatchdog
from nightcrew.modules.sim import SimRoof, SimTelescope


@pytest.mark.parametrize(
    ("options", "message"),
    [
        ({"watch": {}}, "key 'watch': name at least one module to watch"),
        ({"watch": {"weather": 0}}, "key 'watch.weather': must be > 0 seconds, got 0"),
        ({"watch": {"weather": 60}, "interval": 0}, "key 'interval': must be > 0 seconds, got 0"),
        (
            {"watch": {"weather": 60}, "answer_timeout": -1},
            "key 'answer_timeout': must be > 0 seconds, got -1",
        ),
        (
            {"watch": {"weather": 60}, "roof": None, "telescope": None},
            "key 'roof': name a roof or a telescope",
        ),
    ],
)
def test_watchdog_options(options: dict[str, Any], message: str) -> None:
    with pytest.raises(ConfigError) as caught:
        SafetyWatchdog(name="watchdog", **options)
    assert message in str(caught.value)


def test_roof_park_when_offline_must_be_positive() -> None:
    with pytest.raises(ConfigError) as caught:
        SimRoof(name="roof", park_when_offline=0)
    assert "key 'park_when_offline': must be > 0 seconds or null, got 0" in str(caught.value)


def test_telescope_park_when_offline_must_be_positive() -> None:
    with pytest.raises(ConfigError) as caught:
        SimTelescope(name="telescope", site={"latitude": 50, "longitude": 10}, park_when_offline=-1)
    assert "key 'park_when_offline': must be > 0 seconds or null, got -1" in str(caught.value)
