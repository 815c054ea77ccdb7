"""Switch devices (outlets, relays, dew heaters, dimmers): the base class for their drivers."""

from nightcrew.modules.switch.base import BaseSwitch

__all__ = ["BaseSwitch"]
