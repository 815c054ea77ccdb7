"""States and kinds shared by interfaces and events.

All are ``StrEnum``: their wire value is a readable lower-case string, so logs, FITS headers and
JSON events show ``"tracking"`` rather than a number, and new members never renumber old ones.
"""

from __future__ import annotations

from enum import StrEnum

__all__ = [
    "ExposureStatus",
    "ImageType",
    "LoopState",
    "ModuleState",
    "MotionStatus",
    "PierSide",
    "WeatherSensor",
]


class ModuleState(StrEnum):
    """Lifecycle state of a module."""

    STARTING = "starting"
    READY = "ready"
    ERROR = "error"
    CLOSING = "closing"
    CLOSED = "closed"


class MotionStatus(StrEnum):
    """What a moving device (telescope, roof, focuser, filter wheel, ...) is doing."""

    PARKED = "parked"
    INITIALIZING = "initializing"
    IDLE = "idle"
    SLEWING = "slewing"
    TRACKING = "tracking"
    MOVING = "moving"
    PARKING = "parking"
    ABORTING = "aborting"
    ERROR = "error"
    UNKNOWN = "unknown"


class PierSide(StrEnum):
    """Pointing state of a German-equatorial mount, as ASCOM's ``SideOfPier`` defines it.

    EAST is the normal state (the tube on the east side of the pier, looking west of the meridian);
    WEST the through-the-pole state (tube on the west side, looking east). A mount that tracks
    across the meridian keeps its side until it flips, so the side is not a function of hour angle.
    """

    EAST = "east"
    WEST = "west"
    UNKNOWN = "unknown"


class ExposureStatus(StrEnum):
    """What a camera or spectrograph is doing."""

    IDLE = "idle"
    EXPOSING = "exposing"
    READOUT = "readout"
    ERROR = "error"


class ImageType(StrEnum):
    """Purpose of an image; written to the FITS header (IMAGETYP) and used to file it."""

    OBJECT = "object"
    BIAS = "bias"
    DARK = "dark"
    SKYFLAT = "skyflat"
    DOMEFLAT = "domeflat"
    FOCUS = "focus"
    ACQUISITION = "acquisition"
    GUIDING = "guiding"


class LoopState(StrEnum):
    """State of a closed-loop controller such as auto-guiding."""

    STOPPED = "stopped"
    ACQUIRING = "acquiring"  # looking for a reference frame / guide star
    CLOSED = "closed"  # correcting
    LOST = "lost"  # reference lost, trying to recover


class WeatherSensor(StrEnum):
    """Kinds of weather measurements, with their units in the comments."""

    TEMPERATURE = "temperature"  # °C
    HUMIDITY = "humidity"  # percent
    PRESSURE = "pressure"  # hPa
    WIND_SPEED = "wind_speed"  # km/h
    WIND_DIRECTION = "wind_direction"  # degrees east of north
    RAIN = "rain"  # 1 when raining, 0 otherwise
    SKY_TEMPERATURE = "sky_temperature"  # °C, below ambient when clear
    DEW_POINT = "dew_point"  # °C
    SUN_ALTITUDE = "sun_altitude"  # degrees above the horizon (computed, not measured)
    PARTICLES = "particles"  # counts per m³
    SKY_BRIGHTNESS = "sky_brightness"  # mag/arcsec²
    SAFE = "safe"  # 1 when a safety monitor (e.g. Alpaca SafetyMonitor IsSafe) says safe, 0 otherwise
