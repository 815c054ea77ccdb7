"""The served focuser's INDI adapter: a nightcrew focuser (IFocuser) as an INDI focuser.

==========================  ======================================================================
property                    nightcrew
==========================  ======================================================================
ABS_FOCUS_POSITION          focuser get_focus()/set_focus(), in steps of 1 µm (nightcrew: mm)
REL_FOCUS_POSITION          focuser set_focus(position -/+ steps), the direction FOCUS_MOTION's
FOCUS_MOTION                FOCUS_INWARD (towards 0) or FOCUS_OUTWARD; a choice kept for moves
FOCUS_MAX (ro)              the highest step offered (the focuser refuses what is beyond its range)
FOCUS_TEMPERATURE (ro)      the first of the focuser's get_temperatures() (ITemperatures), °C
FOCUS_ABORT_MOTION          focuser stop_motion()
==========================  ======================================================================

The work on the module is the served focuser role's (:mod:`nightcrew.modules.served.focuser`),
which the Alpaca Focuser shares.
"""

from __future__ import annotations

from typing import Any

from nightcrew.bridges.indi.server_vectors import (
    NumberMember,
    Permission,
    Property,
    PropertyState,
    SwitchMember,
)
from nightcrew.errors import InvalidArgumentError
from nightcrew.interfaces import IFocuser, MotionStatus
from nightcrew.modules.served.device_indi import MAIN_GROUP, ServedDevice, Values, abort_vector, switch_on
from nightcrew.modules.served.focuser import ServedFocuserRole

__all__ = ["ServedFocuser"]

#: INDI focuser steps per nightcrew millimetre: a step is a micrometre.
STEPS_PER_MM = 1000.0
#: Range offered to clients; the focuser refuses what lies outside its own range (Alert).
_FOCUS_STEPS = 100_000.0


class ServedFocuser(ServedDevice[IFocuser]):
    """An IFocuser module as an INDI focuser with an absolute position."""

    interface = IFocuser
    driver_interface = 8

    @property
    def role(self) -> ServedFocuserRole:
        return ServedFocuserRole(self.device, STEPS_PER_MM)

    async def _build(self) -> list[Property[Any]]:
        self.position = Property(
            self.name,
            "ABS_FOCUS_POSITION",
            "Absolute Position",
            MAIN_GROUP,
            [NumberMember("FOCUS_ABSOLUTE_POSITION", "Steps (µm)", 0.0, 0.0, _FOCUS_STEPS, 1.0, "%6.0f")],
            timeout=300.0,
        )
        self.relative = Property(
            self.name,
            "REL_FOCUS_POSITION",
            "Relative Position",
            MAIN_GROUP,
            [NumberMember("FOCUS_RELATIVE_POSITION", "Steps (µm)", 0.0, 0.0, _FOCUS_STEPS, 1.0, "%6.0f")],
            timeout=300.0,
        )
        self.direction = Property(
            self.name,
            "FOCUS_MOTION",
            "Direction",
            MAIN_GROUP,
            [SwitchMember("FOCUS_INWARD", "Focus In", True), SwitchMember("FOCUS_OUTWARD", "Focus Out")],
            state=PropertyState.OK,
        )
        self.maximum = Property(
            self.name,
            "FOCUS_MAX",
            "Max. Position",
            MAIN_GROUP,
            [NumberMember("FOCUS_MAX_VALUE", "Steps", _FOCUS_STEPS, 0.0, _FOCUS_STEPS, 1.0, "%6.0f")],
            perm=Permission.READ_ONLY,
            state=PropertyState.OK,
        )
        self.abort = abort_vector(self.name, "FOCUS_ABORT_MOTION")
        vectors: list[Property[Any]] = [
            self.position,
            self.relative,
            self.direction,
            self.maximum,
            self.abort,
        ]
        self.temperature: Property[NumberMember] | None = None
        if self.role.has_temperature:
            self.temperature = Property(
                self.name,
                "FOCUS_TEMPERATURE",
                "Temperature",
                MAIN_GROUP,
                [NumberMember("TEMPERATURE", "Celsius", 0.0, -50.0, 70.0, 0.0, "%6.2f")],
                perm=Permission.READ_ONLY,
            )
            vectors.append(self.temperature)
        return vectors

    async def _update(self) -> None:
        role = self.role
        status = await role.status()
        self.position.by_name["FOCUS_ABSOLUTE_POSITION"].value = round(await role.position(), 3)
        self._follow(self.position, busy=status is MotionStatus.MOVING, failed=status is MotionStatus.ERROR)
        self._follow(self.relative, busy=status is MotionStatus.MOVING, failed=status is MotionStatus.ERROR)
        if self.temperature is not None:
            temperature = await role.temperature()
            if temperature is not None:
                self.temperature.by_name["TEMPERATURE"].value = round(temperature, 2)
                self.temperature.state = PropertyState.OK

    async def _request(self, vector: Property[Any], values: Values) -> None:
        if vector is self.position:
            steps = float(values["FOCUS_ABSOLUTE_POSITION"])
            self._start(self.position, self.role.move(steps))
        elif vector is self.relative:
            steps = float(values["FOCUS_RELATIVE_POSITION"])
            self.relative.by_name["FOCUS_RELATIVE_POSITION"].value = steps
            inward = self.direction.by_name["FOCUS_INWARD"].on
            target = self.position.by_name["FOCUS_ABSOLUTE_POSITION"].value + (-steps if inward else steps)
            self._start(self.relative, self.role.move(target))
        elif vector is self.direction:
            switch_on(self.direction, "FOCUS_INWARD" if values.get("FOCUS_INWARD") else "FOCUS_OUTWARD")
            self.direction.state = PropertyState.OK
            self._link.publish(self.direction)
        elif vector is self.abort:
            if values.get("ABORT"):
                self._start(self.abort, self.role.stop())
        else:
            raise InvalidArgumentError(f"{vector.where} cannot be set")
