"""FocusKeeper: a failed focus run keeps the focus as it was and is tried again after a while."""

from __future__ import annotations

import asyncio
import logging
from typing import Any

import pytest

from nightcrew.focus import FocusSeriesError
from nightcrew.focus.sources import TemperatureSource
from nightcrew.interfaces import IAutoFocus
from nightcrew.modules import Module
from nightcrew.modules.sim import SimFocuser
from nightcrew.robotic.mastermind import FocusKeeper
from nightcrew.robotic.mastermind._observatory import ObservatoryControl
from nightcrew.testing import SITE, Observatory

RETRY_S = 600.0


class Focuser(Module, IAutoFocus):
    """A focus series whose first run finds no V (as at dusk with garbage widths), later runs succeed."""

    def __init__(self, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.runs: list[float] = []

    async def auto_focus(self, count: int, step: float, exposure_time: float) -> tuple[float, float]:
        self.runs.append(self.clock.time())
        await self.clock.sleep(count * exposure_time)
        if len(self.runs) == 1:
            raise FocusSeriesError("best focus 24.4952 ± 0.5207 is too uncertain (accepted: ± 0.1500)")
        return 25.0, 0.01

    async def auto_focus_status(self) -> dict[str, Any]:
        return {}

    async def abort(self) -> None:
        pass


async def _no_cause() -> str | None:
    return None


async def test_a_failed_focus_is_retried_after_the_interval_and_not_before(observatory: Observatory) -> None:
    focuser = await observatory.start(Focuser, "focus")
    control = ObservatoryControl(
        focuser,
        SITE,
        roof="roof",
        telescope="telescope",
        weather=None,
    )
    keeper = FocusKeeper(
        focuser,
        control,
        "focus",
        max_sun_altitude=-10.0,
        refocus_change=2.0,
        arguments=(7, 0.3, 15.0),
        retry_interval=RETRY_S,
    )

    async def focus() -> None:
        await keeper.focus(_no_cause, wake=asyncio.Event(), poll_interval=30.0, abort_timeout=60.0)

    assert await keeper.focus_below() == -10.0  # never focused: due
    await focus()  # fails: logged, not raised - the night goes on with the focus it has
    failed_at = observatory.clock.time()
    assert await keeper.focus_below() is None  # not again at once (e.g. before every task)
    await observatory.clock.sleep(RETRY_S - 60.0)
    assert await keeper.focus_below() is None
    await observatory.clock.sleep(120.0)
    assert await keeper.focus_below() == -10.0  # still due: the failed run did not count
    await focus()
    assert await keeper.focus_below() is None  # focused now (no temperature: not due again)
    assert len(focuser.runs) == 2 and focuser.runs[1] - failed_at >= RETRY_S


async def test_the_refocus_temperature_is_the_configured_sensor_and_a_wrong_one_is_said_once(
    observatory: Observatory, caplog: pytest.LogCaptureFixture
) -> None:
    host = await observatory.start(SimFocuser, "focuser", temperature=7.5)

    def control(sensor: str) -> ObservatoryControl:
        source = TemperatureSource("focuser", sensor=sensor)
        return ObservatoryControl(
            host, SITE, roof="roof", telescope="telescope", weather=None, temperature=source
        )

    assert await control("ambient").temperature() == 7.5
    wrong = control("temperature")  # the old default: no module had it, and nobody was told
    with caplog.at_level(logging.WARNING):
        assert await wrong.temperature() is None
        assert await wrong.temperature() is None
    said = [r.getMessage() for r in caplog.records if "no temperature" in r.getMessage()]
    assert said == [
        "focuser: no temperature for refocusing: "
        "focuser: temperature temperature: no such sensor (it has: ambient)"
    ]
