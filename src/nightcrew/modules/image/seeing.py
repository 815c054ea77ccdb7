"""Seeing: the star FWHM of every new image, as arcseconds at the zenith, with a running median.

On each NewImageEvent (object frames by default) the module reads the image through its VFS and
measures the median star FWHM with
:class:`~nightcrew.images.processors.misc.MeasureFwhm` (Moffat fits). The seeing is that FWHM:

* with the instrument's own blur (``optics_fwhm``) removed in quadrature — image FWHMs add
  roughly in quadrature, so ``seeing = sqrt(fwhm² - optics²)``;
* scaled to the zenith by ``airmass^-0.6`` when the header has ``AIRMASS`` and
  ``zenith_correction`` is on: Kolmogorov turbulence gives ``FWHM ∝ airmass^(3/5)``
  (Roddier 1981), so the zenith seeing is comparable between frames at different altitudes.

The median of the last ``history`` measurements is offered to cameras as the ``SEEING`` card
(IFitsHeaderBefore), so each frame records the conditions it was taken in.

Example (YAML)::

    class: nightcrew.modules.image.Seeing
    optics_fwhm: 0.8
    history: 10
"""

from __future__ import annotations

import logging
import math
import statistics
from collections import deque
from typing import Any

from nightcrew.errors import ConfigError, NightcrewError
from nightcrew.events import NewImageEvent
from nightcrew.images import Image
from nightcrew.images.processors.misc import FWHM_KEY, FwhmMeasurement, MeasureFwhm
from nightcrew.interfaces import FitsCard, IFitsHeaderBefore, ImageType
from nightcrew.modules.module import Module

__all__ = ["Seeing", "zenith_seeing"]

log = logging.getLogger(__name__)

#: Turbulence-limited FWHM grows with airmass to this power (Kolmogorov spectrum).
AIRMASS_EXPONENT = 0.6


def zenith_seeing(fwhm_arcsec: float, *, optics_fwhm: float = 0.0, airmass: float | None = None) -> float:
    """Seeing (arcsec) from an image FWHM: optics removed in quadrature, scaled to the zenith.

    Raises:
        ValueError: ``fwhm_arcsec`` is not larger than ``optics_fwhm``, or ``airmass`` < 1.
    """
    if not fwhm_arcsec > optics_fwhm >= 0:
        raise ValueError(f'image FWHM {fwhm_arcsec:.3f}" is not above the optics\' {optics_fwhm:.3f}"')
    seeing = math.sqrt(fwhm_arcsec**2 - optics_fwhm**2)
    if airmass is not None:
        if not airmass >= 1.0:
            raise ValueError(f"airmass must be >= 1, got {airmass}")
        seeing *= airmass**-AIRMASS_EXPONENT
    return seeing


class Seeing(Module, IFitsHeaderBefore):
    """Measures the seeing on new images and offers the running median as a FITS card.

    Args:
        sources: Only images from these modules (None: every module sending NewImageEvents).
        image_types: Only these image types (unknown types count as object frames).
        optics_fwhm: The instrument's own FWHM (arcsec), removed in quadrature.
        zenith_correction: Scale to the zenith by ``airmass^-0.6`` when the header has AIRMASS.
        history: Number of recent measurements the median is taken over.
        max_age: Clock seconds after which the median is stale and no card is offered.
        fwhm: The FWHM measurement; default ``MeasureFwhm()``.
        **kwargs: Module options.
    """

    def __init__(
        self,
        *,
        sources: list[str] | None = None,
        image_types: list[ImageType] | None = None,
        optics_fwhm: float = 0.0,
        zenith_correction: bool = True,
        history: int = 10,
        max_age: float = 1800.0,
        fwhm: MeasureFwhm | None = None,
        **kwargs: Any,
    ) -> None:
        super().__init__(**kwargs)
        if not (math.isfinite(optics_fwhm) and optics_fwhm >= 0):
            raise ConfigError(f"must be >= 0 arcsec, got {optics_fwhm}", key="optics_fwhm")
        if history < 1:
            raise ConfigError(f"must be >= 1, got {history}", key="history")
        if not max_age > 0:
            raise ConfigError(f"must be > 0 seconds, got {max_age}", key="max_age")
        self._sources = None if sources is None else set(sources)
        self._image_types = {ImageType(t) for t in (image_types or [ImageType.OBJECT])}
        self._optics_fwhm = float(optics_fwhm)
        self._zenith_correction = zenith_correction
        self._max_age = float(max_age)
        self._measure = self.add_child(fwhm or MeasureFwhm())
        self._values: deque[tuple[float, float]] = deque(maxlen=history)  # (clock time, arcsec)

    async def open(self) -> None:
        await super().open()
        await self.comm.register_event(NewImageEvent, self.on_new_image)

    @property
    def seeing(self) -> float | None:
        """Median seeing (arcsec) of the recent measurements; None if none is recent enough."""
        now = self.clock.time()
        recent = [value for when, value in self._values if now - when <= self._max_age]
        return statistics.median(recent) if recent else None

    async def on_new_image(self, event: NewImageEvent, sender: str) -> bool:
        if self._sources is not None and sender not in self._sources:
            return False
        if event.image_type is not None and event.image_type not in self._image_types:
            return False
        try:
            # Not on the observing path, but in a one-process simulation it holds the GIL the
            # others need: at real time it stalls them for its wall time only (Clock.work).
            async with self.clock.work("measure_seeing"):
                image = await self._measure(await Image.from_vfs(self.vfs, event.filename))
            value = self.seeing_of(image)
        except (NightcrewError, ValueError) as exc:
            log.info("%s: no seeing from %s: %s", self.name, event.filename, exc)
            return False
        self._values.append((self.clock.time(), value))
        log.info('%s: seeing %.2f" from %s (median %.2f")', self.name, value, event.filename, self.seeing)
        return True

    def seeing_of(self, image: Image) -> float:
        """Seeing (arcsec) of an image that went through MeasureFwhm (see the module docstring)."""
        measurement = image.metadata.get(FWHM_KEY)
        if not isinstance(measurement, FwhmMeasurement) or measurement.fwhm_arcsec is None:
            raise ValueError("no FWHM in arcsec (the image has no pixel scale)")
        airmass = image.header.get("AIRMASS") if self._zenith_correction else None
        airmass = (
            float(airmass) if isinstance(airmass, int | float) and not isinstance(airmass, bool) else None
        )
        return zenith_seeing(measurement.fwhm_arcsec, optics_fwhm=self._optics_fwhm, airmass=airmass)

    async def get_fits_header_before(self, namespaces: list[str] | None = None) -> dict[str, FitsCard]:
        seeing = self.seeing
        if seeing is None:
            return {}
        where = "at zenith" if self._zenith_correction else "along the line of sight"
        return {"SEEING": (round(seeing, 3), f"Median seeing {where} [arcsec]")}
