"""Small but real drivers and peers for the device tests (hooks implemented, nothing mocked)."""

from __future__ import annotations

import asyncio
from typing import Any, TypeVar

import numpy as np

from nightcrew.errors import InvalidArgumentError
from nightcrew.events import Event, NewImageEvent
from nightcrew.interfaces import (
    ExposureStatus,
    FitsCard,
    IFitsHeaderAfter,
    IFitsHeaderBefore,
    ModuleState,
    Window,
)
from nightcrew.interfaces.camera import Binning
from nightcrew.modules import Module
from nightcrew.modules.camera import BaseCamera, ExposureSettings, Frame
from nightcrew.modules.focuser import BaseFocuser
from nightcrew.modules.spectrograph import BaseSpectrograph

E = TypeVar("E", bound=Event)


class GradientCamera(BaseCamera):
    """A 64x48 chip whose frames are a gradient; exposing takes the exposure time plus 1 s readout."""

    def _hw_full_frame(self) -> Window:
        return Window(0, 0, 64, 48)

    def _hw_binnings(self) -> list[Binning]:
        return [Binning(1, 1), Binning(2, 2)]

    async def _hw_expose(self, settings: ExposureSettings) -> Frame:
        await self.clock.sleep(settings.exposure_time)
        await self._set_exposure_status(ExposureStatus.READOUT)
        await self.clock.sleep(1.0)
        rows, cols = settings.shape
        data = (np.arange(rows)[:, None] * 100 + np.arange(cols)[None, :]).astype(np.uint16)
        return Frame(data, {"CCD-TEMP": (-10.2, "Detector temperature [degC]")})

    async def _hw_set_cooling(self, enabled: bool, setpoint: float) -> None:
        if setpoint < -40:
            raise InvalidArgumentError(f"this cooler reaches -40 °C at best, not {setpoint}")


class HeaderPeer(Module, IFitsHeaderBefore, IFitsHeaderAfter):
    """Gives fixed cards before and after, after ``delay`` clock seconds."""

    def __init__(self, *, cards: dict[str, Any], delay: float = 0.0, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self._cards = cards
        self._delay = delay
        self.calls = 0

    async def get_fits_header_before(self, namespaces: list[str] | None = None) -> dict[str, FitsCard]:
        self.calls += 1
        await self.clock.sleep(self._delay)
        return {key: (value, "from a peer") for key, value in self._cards.items()}

    async def get_fits_header_after(self, namespaces: list[str] | None = None) -> dict[str, FitsCard]:
        return {"AFTERKEY": (True, "from a peer, after")}


class ImageListener(Module):
    """Collects NewImageEvents."""

    def __init__(self, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.images: list[tuple[NewImageEvent, str]] = []
        self.arrived = asyncio.Event()

    async def open(self) -> None:
        if self.state is not ModuleState.STARTING:
            return
        await super().open()
        await self.comm.register_event(NewImageEvent, self.on_new_image)

    async def on_new_image(self, event: NewImageEvent, sender: str) -> None:
        self.images.append((event, sender))
        self.arrived.set()


class BrokenFocuser(BaseFocuser):
    """A focuser whose motor fails."""

    async def _hw_move_focus(self, position: float) -> None:
        raise OSError("motor driver not responding")

    async def _hw_stop(self) -> None:
        pass


class LineSpectrograph(BaseSpectrograph):
    """A spectrograph producing one emission line on a flat continuum."""

    async def _hw_expose_spectrum(self, exposure_time: float) -> Frame:
        await self.clock.sleep(exposure_time)
        flux = np.full(256, 100.0) + 1000.0 * np.exp(-0.5 * ((np.arange(256) - 128) / 3.0) ** 2)
        return Frame(flux.astype(np.float32), {"GRATING": ("600/mm", "Grating")})
