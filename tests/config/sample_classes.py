"""Small classes with typed constructors for the configuration tests.

They mimic the real module ladder (``StandAlone(message, interval, **kwargs)`` → ``Module`` →
``Object``) without depending on it.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from enum import Enum
from typing import Any, Literal

from nightcrew.errors import ConfigError
from nightcrew.interfaces.base import Interface


class ICamLike(Interface):
    """A test interface (registered by name, so its name must be unique)."""

    @abstractmethod
    async def grab(self) -> str: ...


class Mode(Enum):
    FAST = "fast"
    SLOW = "slow"


class Thing:
    def __init__(self, value: int, label: str = "") -> None:
        self.value = value
        self.label = label


class SpecialThing(Thing):
    def __init__(self, factor: float = 1.0, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.factor = factor


class Other:
    def __init__(self) -> None:
        pass


class LocalCam(ICamLike):
    """A local object implementing the test interface."""

    def __init__(self, exposure: float = 1.0) -> None:
        self.exposure = exposure

    async def grab(self) -> str:
        return "image.fits"


class AbstractThing(Thing, ABC):
    @abstractmethod
    def run(self) -> None: ...


class Base:
    """Like ``Object``: ends the kwargs chain (no ``**kwargs``)."""

    def __init__(self, name: str | None = None, timeout: float = 5.0) -> None:
        self.name = name
        self.timeout = timeout


class Middle(Base):
    """Like ``Module``: adds keys and forwards the rest."""

    def __init__(
        self,
        label: str | None = None,
        thing: Thing | dict[str, Any] | None = None,
        camera: str | ICamLike | None = None,
        **kwargs: Any,
    ) -> None:
        super().__init__(**kwargs)
        self.label = label
        self.thing = thing
        self.camera = camera


class Leaf(Middle):
    """Like ``StandAlone``: required and defaulted keys of its own."""

    def __init__(self, message: str, interval: float = 10, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.message = message
        self.interval = interval


class Kitchen:
    """Exercises every kind of hint the validator knows."""

    def __init__(
        self,
        count: int = 0,
        ratio: float = 1.0,
        enabled: bool = False,
        mode: Mode = Mode.FAST,
        speed: Literal["low", "high"] = "low",
        tags: list[str] | None = None,
        limits: dict[str, float] | None = None,
        position: tuple[float, float] = (0.0, 0.0),
        things: list[Thing] | None = None,
        named: dict[str, Thing] | None = None,
        camera: str | ICamLike = "camera",
        thing: Thing | dict[str, Any] | None = None,
        timeout: float | None = None,
        untyped=None,  # deliberately without a hint: accepts anything
    ) -> None:
        self.count = count
        self.ratio = ratio
        self.enabled = enabled
        self.mode = mode
        self.speed = speed
        self.tags = tags
        self.limits = limits
        self.position = position
        self.things = things
        self.named = named
        self.camera = camera
        self.thing = thing
        self.timeout = timeout
        self.untyped = untyped


class Picky(Thing):
    """A constructor that refuses a value the type hint cannot rule out."""

    def __init__(self, value: int, limit: int = 10) -> None:
        if value < 0:
            raise ValueError("value must not be negative")
        if value > limit:
            raise ConfigError(f"value must be <= {limit}, got {value}", key="value")
        super().__init__(value)
