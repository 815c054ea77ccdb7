"""Telescope moves and offsets, announced when they start. Angles in degrees."""

from __future__ import annotations

from dataclasses import dataclass

from nightcrew.events.base import Event

__all__ = ["MoveAltAzEvent", "MoveRaDecEvent", "OffsetsAltAzEvent", "OffsetsRaDecEvent"]


@dataclass(frozen=True, kw_only=True)
class MoveRaDecEvent(Event):
    """The telescope started moving to equatorial coordinates."""

    ra: float
    dec: float


@dataclass(frozen=True, kw_only=True)
class MoveAltAzEvent(Event):
    """The telescope started moving to horizontal coordinates."""

    alt: float
    az: float  # east of north


@dataclass(frozen=True, kw_only=True)
class OffsetsRaDecEvent(Event):
    """New offsets along the RA axis (not scaled by cos dec) and the Dec axis."""

    dra: float
    ddec: float


@dataclass(frozen=True, kw_only=True)
class OffsetsAltAzEvent(Event):
    """New offsets along the altitude and azimuth axes."""

    dalt: float
    daz: float
