"""The served dome's INDI adapter: a nightcrew roof or dome (IRoof, IDome) as an INDI dome.

==========================  ======================================================================
property                    nightcrew
==========================  ======================================================================
DOME_SHUTTER                roof/dome open_roof() / close_roof(); Busy while it moves
ABS_DOME_POSITION           dome get_azimuth()/move_azimuth(), degrees (IDome only)
DOME_PARK                   PARK: park() (closes), UNPARK: init() (opens); PARK On while parked
DOME_MOTION                 DOME_CW/DOME_CCW: move_azimuth() 90° that way; Off: stop_motion() (IDome)
DOME_ABORT_MOTION           roof/dome stop_motion()
==========================  ======================================================================

The work on the module is the served dome role's (:mod:`nightcrew.modules.served.dome`), which the
Alpaca Dome shares.
"""

from __future__ import annotations

from typing import Any

from nightcrew.bridges.indi.server_vectors import (
    NumberMember,
    Property,
    SwitchMember,
    SwitchRule,
)
from nightcrew.errors import InvalidArgumentError
from nightcrew.interfaces import IDome, IRoof, MotionStatus
from nightcrew.modules.served.device_indi import MAIN_GROUP, ServedDevice, Values, abort_vector, switch_on
from nightcrew.modules.served.dome import ServedDomeRole

__all__ = ["ServedDome"]

#: Degrees a dome turns for one DOME_MOTION request (less than half a turn: the way is clear).
_DOME_TURN = 90.0
#: The dome's rotation, as nightcrew's BaseDome names it in get_motion_status(device).
_AZIMUTH = "azimuth"


class ServedDome(ServedDevice[IRoof]):
    """An IRoof module (its shutter) or IDome module (shutter and azimuth) as an INDI dome."""

    interface = IRoof
    driver_interface = 32

    @property
    def role(self) -> ServedDomeRole:
        return ServedDomeRole(self.device)

    async def _build(self) -> list[Property[Any]]:
        self.shutter = Property(
            self.name,
            "DOME_SHUTTER",
            "Shutter",
            MAIN_GROUP,
            [SwitchMember("SHUTTER_OPEN", "Open"), SwitchMember("SHUTTER_CLOSE", "Close", True)],
            timeout=300.0,
        )
        self.park = Property(
            self.name,
            "DOME_PARK",
            "Parking",
            MAIN_GROUP,
            [SwitchMember("PARK", "Park(ed)", True), SwitchMember("UNPARK", "UnPark(ed)")],
            timeout=300.0,
        )
        self.abort = abort_vector(self.name, "DOME_ABORT_MOTION")
        vectors: list[Property[Any]] = [self.shutter, self.park, self.abort]
        self.azimuth: Property[NumberMember] | None = None
        self.motion: Property[SwitchMember] | None = None
        if self.role.dome is not None:
            self.motion = Property(
                self.name,
                "DOME_MOTION",
                "Motion",
                MAIN_GROUP,
                [SwitchMember("DOME_CW", "Dome CW"), SwitchMember("DOME_CCW", "Dome CCW")],
                rule=SwitchRule.AT_MOST_ONE,
                timeout=300.0,
            )
            vectors.append(self.motion)
            self.azimuth = Property(
                self.name,
                "ABS_DOME_POSITION",
                "Absolute Position",
                MAIN_GROUP,
                [NumberMember("DOME_ABSOLUTE_POSITION", "Degrees", 0.0, 0.0, 360.0, 0.0, "%6.2f")],
                timeout=300.0,
            )
            vectors.append(self.azimuth)
        return vectors

    async def _update(self) -> None:
        role = self.role
        status = await role.status()
        closed = status in (MotionStatus.PARKED, MotionStatus.PARKING)
        switch_on(self.shutter, "SHUTTER_CLOSE" if closed else "SHUTTER_OPEN")
        moving = status in (MotionStatus.MOVING, MotionStatus.PARKING)
        self._follow(self.shutter, busy=moving, failed=status is MotionStatus.ERROR)
        switch_on(self.park, "PARK" if status is MotionStatus.PARKED else "UNPARK")
        self._follow(self.park, busy=moving, failed=status is MotionStatus.ERROR)
        dome = role.dome
        if self.azimuth is not None and dome is not None:
            self.azimuth.by_name["DOME_ABSOLUTE_POSITION"].value = round(await dome.get_azimuth(), 6)
            turning = await dome.get_motion_status(_AZIMUTH) is MotionStatus.MOVING
            self._follow(self.azimuth, busy=turning)
            if self.motion is not None and not turning and not self.acting(self.motion):
                for member in self.motion.members:
                    member.on = False
                self._follow(self.motion, busy=False)

    async def _request(self, vector: Property[Any], values: Values) -> None:
        role, roof, dome = self.role, self.device, self.role.dome
        if vector is self.shutter:
            opening = bool(values.get("SHUTTER_OPEN"))
            # Closing always wins (it pre-empts an opening roof); opening waits its turn.
            self._start(self.shutter, role.open() if opening else role.close(), replace=not opening)
        elif vector is self.park:
            parking = bool(values.get("PARK"))
            self._start(self.park, roof.park() if parking else roof.init(), replace=parking)
        elif vector is self.motion and dome is not None:
            self._turn(dome, self.motion, values)
        elif vector is self.abort:
            if values.get("ABORT"):
                self._start(self.abort, role.stop())
        elif vector is self.azimuth and dome is not None:
            self._start(vector, dome.move_azimuth(float(values["DOME_ABSOLUTE_POSITION"]) % 360.0))
        else:
            raise InvalidArgumentError(f"{vector.where} cannot be set")

    def _turn(self, dome: IDome, vector: Property[SwitchMember], values: Values) -> None:
        """DOME_CW/CCW: turn a quarter that way (a new request replaces the turn); Off: stop."""
        direction = next((name for name, on in values.items() if on), None)
        for member in vector.members:
            member.on = member.name == direction
        if direction is None:
            self._start(vector, dome.stop_motion(), replace=True)
            return
        sign = 1.0 if direction == "DOME_CW" else -1.0  # clockwise seen from above: azimuth grows
        azimuth = self.azimuth.by_name["DOME_ABSOLUTE_POSITION"].value if self.azimuth is not None else 0.0
        self._start(vector, dome.move_azimuth((azimuth + sign * _DOME_TURN) % 360.0), replace=True)
