"""nightcrew's simulated observatory served by an AlpacaServer, for the server and discovery tests.

The devices run in real time (an accelerated clock at speed 1 that starts at a dark night, so the
simulated camera sees stars), and move fast, so the tests stay short. The server listens on
127.0.0.1 with a free HTTP port and a free discovery port.
"""

from __future__ import annotations

import asyncio
import time
from collections.abc import AsyncIterator, Callable
from contextlib import asynccontextmanager
from dataclasses import dataclass
from typing import Any, TypeVar

from nightcrew.modules.alpaca.server import AlpacaServer
from nightcrew.modules.sim import (
    SimCamera,
    SimCoverCalibrator,
    SimDome,
    SimFilterWheel,
    SimFocuser,
    SimRotator,
    SimSwitch,
    SimTelescope,
)
from nightcrew.modules.weather import SunStation, Weather
from nightcrew.testing import Observatory
from nightcrew.weather import Switch

__all__ = ["DARK_NIGHT", "MILKY_WAY", "Served", "served_observatory", "wait_in_thread"]

T = TypeVar("T")

#: New moon, the Sun 20° below the horizon at the test site, the field below at hour angle ~1.5 h.
DARK_NIGHT = "2024-08-04T22:00:00+00:00"
#: A field rich in catalogue stars (the one tests/sim/test_solve_field.py solves), (ra, dec) in degrees.
MILKY_WAY = (269.45, 4.7)
#: The device types served with ``more_devices`` and the modules behind them.
MORE_DEVICES = {"rotator": "rotator", "switch": "switch", "covercalibrator": "flatpanel"}
#: The served device types and the modules behind them.
DEVICES = {
    "telescope": "telescope",
    "camera": "camera",
    "dome": "dome",
    "focuser": "focuser",
    "filterwheel": "filters",
    "safetymonitor": "weather",
}


@dataclass
class Served:
    """The observatory and its Alpaca server."""

    observatory: Observatory
    server: AlpacaServer

    @property
    def address(self) -> str:
        """``host:port`` as alpyca wants it."""
        return f"127.0.0.1:{self.server.port}"

    @property
    def url(self) -> str:
        return f"http://127.0.0.1:{self.server.port}"


@asynccontextmanager
async def served_observatory(
    *,
    chip: int = 512,
    slew_rate: float = 90.0,
    focuser_speed: float = 20.0,
    filter_change_time: float = 0.2,
    dome_time: float = 1.0,
    more_devices: bool = False,
    **server_options: Any,
) -> AsyncIterator[Served]:
    """Telescope (``slew_rate`` °/s), camera (``chip`` x ``chip`` pixels), dome (opens, closes and
    turns 90° in ``dome_time`` s), focuser (``focuser_speed`` mm/s), filter wheel
    (``filter_change_time`` s) and weather, served by an AlpacaServer ``alpaca``; with
    ``more_devices`` also a rotator, a switch box and a flat panel (:data:`MORE_DEVICES`), quick."""
    async with Observatory(speed=1.0, epoch=DARK_NIGHT) as obs:
        await obs.start(SimTelescope, "telescope", slew_rate=slew_rate, settle_time=0.0, init_time=0.0)
        await obs.start(
            SimCamera,
            "camera",
            telescope="telescope",
            focuser=None,
            filters=None,
            roof=None,
            weather=None,
            detector={"chip_width": chip, "chip_height": chip},
            readout_time=0.0,
        )
        await obs.start(
            SimDome, "dome", open_time=dome_time, close_time=dome_time, rotation_speed=90.0 / dome_time
        )
        await obs.start(SimFocuser, "focuser", speed=focuser_speed, focus=20.0)
        await obs.start(SimFilterWheel, "filters", filters=["B", "V", "R"], change_time=filter_change_time)
        await obs.start(
            Weather,
            "weather",
            stations={"sun": SunStation()},
            checks={"sun.sun_altitude": Switch(bad_above=-6.0)},
            min_good_time=0.0,
            interval=1.0,
        )
        if more_devices:
            await obs.start(SimRotator, "rotator", speed=90.0)
            switches = [{"name": "power"}, {"name": "dew heater", "max_value": 100.0, "step": 1.0}]
            await obs.start(SimSwitch, "switch", switches=switches)
            await obs.start(SimCoverCalibrator, "flatpanel", cover_time=0.05, warmup_time=0.05)
        options: dict[str, Any] = {
            "devices": {**DEVICES, **MORE_DEVICES} if more_devices else DEVICES,
            "port": 0,
            "discovery_port": 0,
            "pixel_sizes": {"camera": 9.0},
            **server_options,
        }
        server = await obs.start(AlpacaServer, "alpaca", **options)
        yield Served(obs, server)


async def wait_in_thread(condition: Callable[[], bool], seconds: float, message: str) -> None:
    """Poll a blocking ``condition`` (an alpyca call) in a thread until it holds, bounded by
    ``seconds`` of wall time."""
    deadline = time.monotonic() + seconds
    while not await asyncio.to_thread(condition):
        if time.monotonic() > deadline:
            raise AssertionError(f"{message}: not within {seconds:g} s")
        await asyncio.sleep(0.05)
