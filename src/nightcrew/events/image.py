"""Data products and the exposures that make them. Events carry VFS paths, never the data."""

from __future__ import annotations

from dataclasses import dataclass

from nightcrew.events.base import Event
from nightcrew.interfaces.enums import ExposureStatus, ImageType

__all__ = ["ExposureStatusChangedEvent", "NewImageEvent", "NewSpectrumEvent"]


@dataclass(frozen=True, kw_only=True)
class NewImageEvent(Event):
    """A camera wrote a new image."""

    filename: str  # VFS path of the image
    image_type: ImageType | None = None


@dataclass(frozen=True, kw_only=True)
class NewSpectrumEvent(Event):
    """A spectrograph wrote a new spectrum."""

    filename: str  # VFS path of the spectrum


@dataclass(frozen=True, kw_only=True)
class ExposureStatusChangedEvent(Event):
    """A camera's or spectrograph's exposure status changed."""

    persistent = True

    last: ExposureStatus | None  # None for the first status after start-up
    current: ExposureStatus
