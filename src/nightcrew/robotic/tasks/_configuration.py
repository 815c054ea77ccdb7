"""One configuration of a request: what the telescope and the instrument do on one target.

A :class:`Configuration` has a type (:class:`ConfigurationType`), usually a :class:`Target`, the
:class:`Constraints` under which it may run, how to acquire and guide, and a list of
:class:`InstrumentConfig` (exposure time, count, filter, binning). Rules per type:

=============  ======  ===========================  =============================================
type           target  instrument_configs           also
=============  ======  ===========================  =============================================
EXPOSE         needed  >= 1, exposure_time > 0
REPEAT_EXPOSE  needed  >= 1, exposure_time > 0      ``repeat_duration`` (s): the cycle repeats
BIAS           -       >= 1, exposure_time == 0
DARK           -       >= 1, exposure_time > 0
SKY_FLAT       -       >= 1, exposure_time > 0      (a first guess; the flat-fielder adapts it)
PANEL_FLAT     -       >= 1, exposure_time > 0      (a first guess); ``extra_params.level`` (ADU)
AUTO_FOCUS     any     >= 1, exposure_time > 0
SCRIPT         any     any, exposure_time > 0       ``extra_params.script`` (str), ``.duration`` (s)
=============  ======  ===========================  =============================================

Physical bounds hold for every type: an exposure time is at most
:data:`~nightcrew.interfaces.quantities.MAX_EXPOSURE_TIME` (a day, what a camera may be asked for),
a series at most :data:`MAX_EXPOSURE_COUNT` exposures, and a repeat or a script's duration at most
:data:`MAX_TASK_SECONDS`, so every duration derived from a task is a finite number of seconds.
"""

from __future__ import annotations

from collections.abc import Iterator
from enum import StrEnum
from typing import Annotated, Self

from pydantic import Discriminator, Field, Strict, Tag, model_validator

from nightcrew.interfaces.quantities import MAX_EXPOSURE_TIME
from nightcrew.robotic.tasks._base import ExtraParams, Integer, Number, TaskModel, raise_problems
from nightcrew.robotic.tasks._moving import (
    MajorBodyTarget,
    MpcElementsTarget,
    OrbitalElementsTarget,
    SatelliteTarget,
    target_kind,
)

__all__ = [
    "MAX_EXPOSURE_COUNT",
    "MAX_TASK_SECONDS",
    "AcquisitionConfig",
    "AcquisitionMode",
    "AnyTarget",
    "Configuration",
    "ConfigurationType",
    "Constraints",
    "DitherConfig",
    "DitherPattern",
    "GuidingConfig",
    "GuidingMode",
    "InstrumentConfig",
    "Target",
]

#: Most exposures in one series (a night of one-second frames is about 40,000).
MAX_EXPOSURE_COUNT = 100_000
#: Longest repeat or script, in seconds: a request runs in one go, within a night.
MAX_TASK_SECONDS = 86_400.0


class ConfigurationType(StrEnum):
    """What a configuration does; the runner picks the script by it."""

    EXPOSE = "EXPOSE"
    REPEAT_EXPOSE = "REPEAT_EXPOSE"
    BIAS = "BIAS"
    DARK = "DARK"
    SKY_FLAT = "SKY_FLAT"
    PANEL_FLAT = "PANEL_FLAT"
    AUTO_FOCUS = "AUTO_FOCUS"
    SCRIPT = "SCRIPT"


#: Types that point at a target of their own.
TYPES_NEEDING_TARGET = frozenset({ConfigurationType.EXPOSE, ConfigurationType.REPEAT_EXPOSE})


class AcquisitionMode(StrEnum):
    """How to put the target on the chosen pixel before exposing."""

    OFF = "OFF"  # trust the pointing
    ON = "ON"  # the telescope's own acquisition
    WCS = "WCS"  # plate-solve and offset
    BRIGHTEST = "BRIGHTEST"  # centre the brightest star


class GuidingMode(StrEnum):
    """Whether to guide during the exposures."""

    OFF = "OFF"
    ON = "ON"


class DitherPattern(StrEnum):
    """Where successive dither positions lie (see :mod:`nightcrew.robotic.scripts._dither`)."""

    SPIRAL = "SPIRAL"  # a square spiral of steps ``amplitude`` long around the target
    RANDOM = "RANDOM"  # uniform within ``amplitude`` of the target along each axis


class DitherConfig(TaskModel):
    """Moving the telescope a little between science frames (the guider follows).

    Args:
        pattern: Where the positions lie.
        amplitude: Arcsec: the spiral's step, or the random offsets' largest along each axis;
            0 (the default) never dithers. ``nightcrew check`` refuses one larger than the
            camera's field.
        every: Dither after every this many frames, >= 1.
    """

    pattern: DitherPattern = DitherPattern.SPIRAL
    amplitude: Number = Field(default=0.0, ge=0.0, le=3600.0)
    every: Integer = Field(default=1, ge=1, le=MAX_EXPOSURE_COUNT)


class Target(TaskModel):
    """A fixed (sidereal) target, ICRS.

    Args:
        name: For people and FITS headers.
        ra: Right ascension in degrees at ``epoch``, 0 <= ra < 360.
        dec: Declination in degrees, -90..90.
        proper_motion_ra: mu_alpha* = mu_alpha cos(dec), milliarcseconds per year.
        proper_motion_dec: mu_delta, milliarcseconds per year.
        epoch: Julian epoch of ``ra``/``dec`` (2000 for J2000, 2016 for Gaia DR3).
        parallax: Milliarcseconds, >= 0.
    """

    name: str = Field(min_length=1)
    ra: Number = Field(ge=0.0, lt=360.0)
    dec: Number = Field(ge=-90.0, le=90.0)
    proper_motion_ra: Number = 0.0
    proper_motion_dec: Number = 0.0
    epoch: Number = Field(default=2000.0, ge=1900.0, le=2100.0)
    parallax: Number = Field(default=0.0, ge=0.0)


#: A configuration's target: sidereal (no ``type``) or one of the moving kinds of :mod:`._moving`.
AnyTarget = Annotated[
    Annotated[Target, Tag("SIDEREAL")]
    | Annotated[OrbitalElementsTarget, Tag("ORBITAL_ELEMENTS")]
    | Annotated[MpcElementsTarget, Tag("MPC_ELEMENTS")]
    | Annotated[MajorBodyTarget, Tag("MAJOR_BODY")]
    | Annotated[SatelliteTarget, Tag("SATELLITE")],
    Discriminator(target_kind),
]


class Constraints(TaskModel):
    """Conditions the whole configuration must run under. A limit at its loosest value is no limit.

    Args:
        max_airmass: Highest airmass, >= 1.
        min_lunar_distance: Smallest distance to the Moon in degrees, 0..180.
        max_lunar_phase: Largest illuminated fraction of the Moon, 0 (new) ..1 (full).
        max_sun_altitude: Highest altitude of the Sun in degrees (-12: nautical twilight has ended).
        min_sun_altitude: Lowest altitude of the Sun, for twilight flats; must be below the maximum.
    """

    max_airmass: Number = Field(default=2.0, ge=1.0)
    min_lunar_distance: Number = Field(default=30.0, ge=0.0, le=180.0)
    max_lunar_phase: Number = Field(default=1.0, ge=0.0, le=1.0)
    max_sun_altitude: Number = Field(default=-12.0, ge=-90.0, le=90.0)
    min_sun_altitude: Number | None = Field(default=None, ge=-90.0, le=90.0)

    @model_validator(mode="after")
    def _check_sun_range(self) -> Self:
        if self.min_sun_altitude is not None and self.min_sun_altitude >= self.max_sun_altitude:
            raise_problems([("min_sun_altitude", f"must be < max_sun_altitude ({self.max_sun_altitude:g})")])
        return self


class AcquisitionConfig(TaskModel):
    """How to acquire the target; ``exposure_time`` (s) of the acquisition images, if not the default."""

    mode: AcquisitionMode = AcquisitionMode.OFF
    exposure_time: Number | None = Field(default=None, gt=0.0, le=MAX_EXPOSURE_TIME)
    extra_params: ExtraParams = Field(default_factory=dict)


class GuidingConfig(TaskModel):
    """How to guide; with ``optional`` the exposures go on when guiding fails."""

    mode: GuidingMode = GuidingMode.OFF
    optional: Annotated[bool, Strict()] = True
    exposure_time: Number | None = Field(default=None, gt=0.0, le=MAX_EXPOSURE_TIME)
    extra_params: ExtraParams = Field(default_factory=dict)


class InstrumentConfig(TaskModel):
    """A series of identical exposures.

    Args:
        exposure_time: Seconds per exposure (0 only for BIAS; see the module's table).
        exposure_count: Number of exposures, >= 1.
        optical_elements: Element kind to name, e.g. ``{"filter": "V"}``.
        binning: Square binning factor, 1..16.
        extra_params: Free parameters for the camera (e.g. ``defocus``).
    """

    exposure_time: Number = Field(ge=0.0, le=MAX_EXPOSURE_TIME)
    exposure_count: Integer = Field(default=1, ge=1, le=MAX_EXPOSURE_COUNT)
    optical_elements: dict[str, str] = Field(default_factory=dict)
    binning: Integer = Field(default=1, ge=1, le=16)
    extra_params: ExtraParams = Field(default_factory=dict)


class Configuration(TaskModel):
    """A set of exposures of one kind on one target; see the module docstring for the rules per type.

    Args:
        type: What to do.
        instrument_type: The kind of instrument that must do it (free text, e.g. ``0M4-SIM-CAMERA``).
        target: Where to point (sidereal or moving); needed for EXPOSE and REPEAT_EXPOSE.
        constraints: Conditions to run under.
        acquisition_config: How to acquire the target.
        guiding_config: How to guide.
        dither_config: How to dither between science frames (EXPOSE, REPEAT_EXPOSE).
        instrument_configs: The exposure series, taken in order.
        repeat_duration: REPEAT_EXPOSE only: seconds to keep cycling through the series.
        extra_params: Free parameters; SCRIPT needs ``script`` (what to run) and ``duration`` (s).
    """

    type: ConfigurationType
    instrument_type: str = ""
    target: AnyTarget | None = None
    constraints: Constraints = Field(default=Constraints())
    acquisition_config: AcquisitionConfig = Field(default=AcquisitionConfig())
    guiding_config: GuidingConfig = Field(default=GuidingConfig())
    dither_config: DitherConfig = Field(default=DitherConfig())
    instrument_configs: tuple[InstrumentConfig, ...] = ()
    repeat_duration: Number | None = Field(default=None, gt=0.0, le=MAX_TASK_SECONDS)
    extra_params: ExtraParams = Field(default_factory=dict)

    @model_validator(mode="after")
    def _check_type_rules(self) -> Self:
        raise_problems(self._type_problems())
        return self

    def _type_problems(self) -> Iterator[tuple[str, str]]:
        kind = self.type.value
        if self.type in TYPES_NEEDING_TARGET and self.target is None:
            yield "target", f"required for {kind} configurations"
        if self.type is not ConfigurationType.SCRIPT and not self.instrument_configs:
            yield "instrument_configs", f"{kind} configurations need at least one entry"
        for index, instrument_config in enumerate(self.instrument_configs):
            where = f"instrument_configs[{index}].exposure_time"
            if self.type is ConfigurationType.BIAS and instrument_config.exposure_time != 0:
                yield where, "must be 0 for BIAS configurations"
            elif self.type is not ConfigurationType.BIAS and not instrument_config.exposure_time > 0:
                yield where, "must be > 0"
        if self.type is ConfigurationType.REPEAT_EXPOSE and self.repeat_duration is None:
            yield "repeat_duration", "required for REPEAT_EXPOSE configurations"
        if self.type is not ConfigurationType.REPEAT_EXPOSE and self.repeat_duration is not None:
            yield "repeat_duration", "only allowed for REPEAT_EXPOSE configurations"
        if self.type not in TYPES_NEEDING_TARGET and self.dither_config.amplitude > 0:
            yield "dither_config.amplitude", "dithering is only for EXPOSE and REPEAT_EXPOSE configurations"
        if self.type is ConfigurationType.SCRIPT:
            yield from _script_problems(self.extra_params)
        if self.type is ConfigurationType.PANEL_FLAT:
            yield from _flat_level_problems(self.extra_params)

    @property
    def script_duration(self) -> float:
        """SCRIPT only: the seconds the script is expected to take (``extra_params.duration``)."""
        return float(self.extra_params["duration"])


#: The highest level a frame can hold: cameras write 16-bit unsigned pixels.
SATURATION_ADU = 65535


def _flat_level_problems(extra_params: ExtraParams) -> Iterator[tuple[str, str]]:
    level = extra_params.get("level")
    if level is None:
        return
    if isinstance(level, bool) or not isinstance(level, int | float) or not level > 0:
        yield "extra_params.level", f"must be a positive number of ADU, got {level!r}"
    elif level >= SATURATION_ADU:
        yield "extra_params.level", f"{level:g} ADU is at or above saturation ({SATURATION_ADU} ADU)"


def _script_problems(extra_params: ExtraParams) -> Iterator[tuple[str, str]]:
    script = extra_params.get("script")
    if not isinstance(script, str) or not script.strip():
        yield "extra_params.script", "required for SCRIPT configurations (the script to run, as text)"
    duration = extra_params.get("duration")
    if isinstance(duration, bool) or not isinstance(duration, int | float):
        yield "extra_params.duration", "required for SCRIPT configurations (expected seconds, a number)"
    elif not 0 < duration <= MAX_TASK_SECONDS:
        yield "extra_params.duration", f"must be > 0 and <= {MAX_TASK_SECONDS:g} (seconds)"
