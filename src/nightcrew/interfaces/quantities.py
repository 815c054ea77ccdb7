"""Units and ranges of interface parameters, declared in the type hint.

A parameter's hint may carry its unit and bounds with :data:`typing.Annotated`::

    async def move_radec(self, ra: RightAscension, dec: Declination) -> None: ...
    async def set_exposure_time(self, exposure_time: Annotated[float, Ge(0), Unit("s")]) -> None: ...

Bounds are the ``annotated-types`` markers (``Ge``, ``Gt``, ``Le``, ``Lt``, ``Interval``), the
standard vocabulary pydantic also reads. The codec enforces them when a call arrives, before the
call's timeout is announced, so an out-of-range argument is refused at once; the catalogue
publishes them as JSON Schema ``minimum``/``maximum`` and the unit as ``x-unit``. Implementations
may keep plain ``float`` hints: the interface's declaration is what calls are checked against.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Annotated, Any

from annotated_types import Ge, Interval

__all__ = ["Altitude", "Azimuth", "Declination", "Degrees", "RightAscension", "Seconds", "Unit"]


@dataclass(frozen=True)
class Unit:
    """The unit of a value, as a symbol: ``deg``, ``s``, ``degC``, ``%``, ``adu``."""

    symbol: str

    def __get_pydantic_json_schema__(self, core_schema: Any, handler: Any) -> dict[str, Any]:
        # pydantic builds the catalogue's JSON Schema; JSON Schema has no unit keyword.
        schema: dict[str, Any] = handler(core_schema)
        schema["x-unit"] = self.symbol
        return schema


Degrees = Annotated[float, Unit("deg")]
RightAscension = Annotated[float, Interval(ge=0.0, lt=360.0), Unit("deg")]
Declination = Annotated[float, Interval(ge=-90.0, le=90.0), Unit("deg")]
Altitude = Annotated[float, Interval(ge=-90.0, le=90.0), Unit("deg")]
Azimuth = Annotated[float, Unit("deg")]  # east of north; implementations wrap it into 0..360
Seconds = Annotated[float, Ge(0.0), Unit("s")]
