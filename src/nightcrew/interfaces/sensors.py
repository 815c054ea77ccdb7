"""Read-outs of device sensors that are not weather."""

from __future__ import annotations

from abc import abstractmethod

from nightcrew.interfaces.base import Interface

__all__ = ["ITemperatures"]


class ITemperatures(Interface):
    """A device with thermometers (detector, mirror, focuser, ...), e.g. for focus models and FITS headers."""

    @abstractmethod
    async def get_temperatures(self) -> dict[str, float]:
        """Sensor name → temperature in °C."""
