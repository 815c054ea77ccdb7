"""A served telescope's hand controls and guide port: INDI motion N/S/W/E, slew rates, timed guiding.

All of them move the telescope by its RA/Dec offsets (IOffsetsRaDec), from the target it tracks:

==========================  ======================================================================
property                    nightcrew
==========================  ======================================================================
TELESCOPE_SLEW_RATE         the rate of TELESCOPE_MOTION_*: SLEW_GUIDE 1x, SLEW_CENTERING 8x,
                            SLEW_FIND 64x, SLEW_MAX 512x sidereal (15.04 arcsec/s)
TELESCOPE_MOTION_NS/WE      while MOTION_NORTH/SOUTH/WEST/EAST is On, the offsets grow at that rate
                            every 0.2 wall seconds; Off stops (the offset reached stays)
GUIDE_RATE                  GUIDE_RATE_WE, GUIDE_RATE_NS: a pulse's rate, 0.1..1 of sidereal
TELESCOPE_TIMED_GUIDE_NS/WE a pulse of N ms: the offset rate x N ms is applied at once, the
                            property stays Busy for the pulse, then Ok with its members back at 0
==========================  ======================================================================

West lowers RA, east raises it (in RA degrees, as sidereal rate counts); north raises Dec.
"""

from __future__ import annotations

import asyncio
import contextlib
from typing import TYPE_CHECKING, Any

from nightcrew.bridges.indi.server_vectors import (
    NumberMember,
    Property,
    PropertyState,
    SwitchMember,
    SwitchRule,
)
from nightcrew.errors import InvalidArgumentError
from nightcrew.interfaces import IOffsetsRaDec

if TYPE_CHECKING:
    from nightcrew.modules.served.device_indi import ServerLink, Values

__all__ = ["GUIDE_VECTORS", "HandControls"]

#: Sidereal rate in degrees of RA per (sidereal-rate) second.
SIDEREAL_DEG_PER_S = 15.041 / 3600.0
#: Multiples of sidereal rate of each slew rate, slowest first.
SLEW_RATES = {"SLEW_GUIDE": 1.0, "SLEW_CENTERING": 8.0, "SLEW_FIND": 64.0, "SLEW_MAX": 512.0}
#: Wall seconds between two steps of a manual motion.
MOTION_STEP = 0.2
#: Longest guide pulse taken, in milliseconds.
MAX_PULSE_MS = 60_000.0
_MOTION_GROUP = "Motion Control"
_GUIDE_GROUP = "Guide"
#: Member -> (RA sign, Dec sign).
_DIRECTIONS = {
    "MOTION_NORTH": (0, 1),
    "MOTION_SOUTH": (0, -1),
    "MOTION_WEST": (-1, 0),
    "MOTION_EAST": (1, 0),
    "TIMED_GUIDE_N": (0, 1),
    "TIMED_GUIDE_S": (0, -1),
    "TIMED_GUIDE_W": (-1, 0),
    "TIMED_GUIDE_E": (1, 0),
}
#: The properties this module serves (for the driver interface's GUIDER bit and docs).
GUIDE_VECTORS = (
    "TELESCOPE_SLEW_RATE",
    "TELESCOPE_MOTION_NS",
    "TELESCOPE_MOTION_WE",
    "GUIDE_RATE",
    "TELESCOPE_TIMED_GUIDE_NS",
    "TELESCOPE_TIMED_GUIDE_WE",
)


def _pulse_vector(
    device: str, name: str, label: str, members: tuple[str, str], labels: tuple[str, str]
) -> Property[Any]:
    return Property(
        device,
        name,
        label,
        _GUIDE_GROUP,
        [
            NumberMember(m, lab, 0.0, 0.0, MAX_PULSE_MS, 1.0, "%5.0f")
            for m, lab in zip(members, labels, strict=True)
        ],
        timeout=MAX_PULSE_MS / 1000.0 + 5.0,
    )


class HandControls:
    """The motion, slew-rate and guiding properties of one served telescope offering IOffsetsRaDec."""

    def __init__(self, device: str, link: ServerLink) -> None:
        self._link = link
        # property name -> its motion loop and what stops it
        self._moving: dict[str, tuple[asyncio.Task[None], asyncio.Event]] = {}
        self.slew_rate = Property(
            device,
            "TELESCOPE_SLEW_RATE",
            "Slew Rate",
            _MOTION_GROUP,
            [SwitchMember(n, f"{r:g}x", n == "SLEW_CENTERING") for n, r in SLEW_RATES.items()],
            state=PropertyState.OK,
        )
        self.motion_ns = Property(
            device,
            "TELESCOPE_MOTION_NS",
            "Motion N/S",
            _MOTION_GROUP,
            [SwitchMember("MOTION_NORTH", "North"), SwitchMember("MOTION_SOUTH", "South")],
            rule=SwitchRule.AT_MOST_ONE,
        )
        self.motion_we = Property(
            device,
            "TELESCOPE_MOTION_WE",
            "Motion W/E",
            _MOTION_GROUP,
            [SwitchMember("MOTION_WEST", "West"), SwitchMember("MOTION_EAST", "East")],
            rule=SwitchRule.AT_MOST_ONE,
        )
        self.guide_rate = Property(
            device,
            "GUIDE_RATE",
            "Guiding Rate",
            _GUIDE_GROUP,
            [
                NumberMember("GUIDE_RATE_WE", "W/E Rate", 0.5, 0.1, 1.0, 0.1, "%g"),
                NumberMember("GUIDE_RATE_NS", "N/S Rate", 0.5, 0.1, 1.0, 0.1, "%g"),
            ],
            state=PropertyState.OK,
        )
        self.guide_ns = _pulse_vector(
            device,
            "TELESCOPE_TIMED_GUIDE_NS",
            "Guide N/S",
            ("TIMED_GUIDE_N", "TIMED_GUIDE_S"),
            ("North (ms)", "South (ms)"),
        )
        self.guide_we = _pulse_vector(
            device,
            "TELESCOPE_TIMED_GUIDE_WE",
            "Guide W/E",
            ("TIMED_GUIDE_W", "TIMED_GUIDE_E"),
            ("West (ms)", "East (ms)"),
        )

    @property
    def vectors(self) -> list[Property[Any]]:
        return [self.slew_rate, self.motion_ns, self.motion_we, self.guide_rate, self.guide_ns, self.guide_we]

    def set_rate(self, vector: Property[Any], values: Values) -> None:
        """A new slew rate or guide rate: kept here, Ok at once."""
        if vector is self.slew_rate:
            for member in self.slew_rate.members:
                member.on = bool(values.get(member.name, False))
        else:
            for name, value in values.items():
                vector.by_name[name].value = float(value)
        vector.state = PropertyState.OK
        self._link.publish(vector)

    async def motion(self, telescope: IOffsetsRaDec, vector: Property[Any], values: Values) -> None:
        """Start or stop a manual motion; the vector is Busy while it moves.

        A running motion ends after its current step (never cancelled halfway through a call to
        the telescope, which would leave its offset slew unfinished).
        """
        running = self._moving.pop(vector.name, None)
        if running is not None:
            task, stop = running
            stop.set()
            await asyncio.gather(task, return_exceptions=True)
        direction = next((name for name, on in values.items() if on), None)
        for member in vector.members:
            member.on = member.name == direction
        if direction is None:
            vector.state = PropertyState.OK if vector.state is not PropertyState.ALERT else PropertyState.IDLE
            self._link.publish(vector)
            return
        vector.state = PropertyState.BUSY
        self._link.publish(vector)
        stop = asyncio.Event()
        task = asyncio.create_task(
            self._move(telescope, vector, direction, stop), name=f"INDI {vector.where}"
        )
        self._moving[vector.name] = (task, stop)

    async def _move(
        self, telescope: IOffsetsRaDec, vector: Property[Any], direction: str, stop: asyncio.Event
    ) -> None:
        rate = next(SLEW_RATES[m.name] for m in self.slew_rate.members if m.on) * SIDEREAL_DEG_PER_S
        step = rate * MOTION_STEP
        try:
            while not stop.is_set():
                await _offset_by(telescope, direction, step)
                with contextlib.suppress(TimeoutError):  # a hand paddle moves in the user's (wall) time
                    async with asyncio.timeout(MOTION_STEP):
                        await stop.wait()
        except Exception as exc:  # the motion ends in Alert with the reason; the server goes on
            for member in vector.members:
                member.on = False
            vector.state, vector.message = PropertyState.ALERT, f"{type(exc).__name__}: {exc}"
            self._link.publish(vector)

    async def pulse(self, telescope: IOffsetsRaDec, vector: Property[Any], values: Values) -> None:
        """One timed guide pulse (the action a served device runs Busy, then Ok)."""
        pulses = {name: float(ms) for name, ms in values.items() if float(ms) > 0.0}
        if len(pulses) > 1:
            raise InvalidArgumentError(f"{vector.where}: one direction per pulse, got {', '.join(pulses)}")
        for name, ms in pulses.items():
            vector.by_name[name].value = ms
            rate_name = "GUIDE_RATE_NS" if vector is self.guide_ns else "GUIDE_RATE_WE"
            rate = self.guide_rate.by_name[rate_name].value * SIDEREAL_DEG_PER_S
            await _offset_by(telescope, name, rate * ms / 1000.0)
            await asyncio.sleep(ms / 1000.0)  # the guider waits the pulse out in wall time
        for member in vector.members:
            member.value = 0.0

    async def close(self) -> None:
        running = list(self._moving.values())
        self._moving.clear()
        for _, stop in running:
            stop.set()
        await asyncio.gather(*(task for task, _ in running), return_exceptions=True)


async def _offset_by(telescope: IOffsetsRaDec, direction: str, degrees: float) -> None:
    sign_ra, sign_dec = _DIRECTIONS[direction]
    dra, ddec = await telescope.get_offsets_radec()
    await telescope.set_offsets_radec(dra + sign_ra * degrees, ddec + sign_dec * degrees)
