"""Auto-focus: a series of exposures through focus, a width per frame, a hyperbola fit.

``auto_focus(count, step, exposure_time)`` takes ``count`` frames ``step`` mm apart, centred on the
focus the focuser has when called (shifted as a whole into an IFocusRange focuser's range near an
end), measures each frame's star width with a :class:`FocusMeasure` and fits
:func:`nightcrew.focus.series.fit_focus_hyperbola`; it ends early once too few frames are left to
fit. On success the focuser goes to the fitted focus and a FocusFoundEvent is sent; on any failure
(a minimum outside the series, too few stars, widths that form no clear V, an abort) the focuser
goes back to where it was, so a failed series never leaves the telescope worse focused than before;
a series that gave no best focus (not an abort) is announced by a FocusFailedEvent with the reason.
The default measure leaves out the hot pixels and cosmic rays of the raw focus frames, which would
count as (sharp) stars.

Example (YAML)::

    class: nightcrew.modules.focus.AutoFocusSeries
    camera: camera
    focuser: focuser
    measure: {class: nightcrew.modules.focus.series.PhotometryFocusMeasure, min_peak_snr: 10}
"""

from __future__ import annotations

import abc
import asyncio
import logging
import math
from typing import Any

from nightcrew.errors import ConfigError, InvalidArgumentError, NightcrewError
from nightcrew.events import FocusFailedEvent, FocusFoundEvent
from nightcrew.focus.series import (
    MIN_FRAMES,
    FocusSeriesError,
    fit_focus_hyperbola,
    photometry_width,
    point_defects,
    projection_width,
    series_positions,
)
from nightcrew.images import Image
from nightcrew.images.processors._shared import estimate_background, float_data, saturation_level
from nightcrew.images.processors.detection import detect_sources_sep
from nightcrew.interfaces import (
    IAutoFocus,
    ICamera,
    IExposureTime,
    IFocuser,
    IFocusRange,
    IImageType,
    ImageType,
)
from nightcrew.modules.module import Module
from nightcrew.modules.motion.runner import MotionRunner
from nightcrew.object import Object

__all__ = ["AutoFocusSeries", "FocusMeasure", "PhotometryFocusMeasure", "ProjectionFocusMeasure"]

log = logging.getLogger(__name__)


class FocusMeasure(Object, abc.ABC):
    """How sharp a frame is: a width in pixels, smaller is sharper."""

    async def __call__(self, image: Image) -> float:
        return await asyncio.to_thread(self._blocking_width, image)

    @abc.abstractmethod
    def _blocking_width(self, image: Image) -> float:
        """The width (pixels); raises FocusSeriesError when the frame cannot tell."""


class ProjectionFocusMeasure(FocusMeasure):
    """Width of the autocorrelation peak of the frame's x/y projections (no detection; donuts work)."""

    def _blocking_width(self, image: Image) -> float:
        return projection_width(image.data, image.mask)


class PhotometryFocusMeasure(FocusMeasure):
    """Median FWHM of the detected stars (SEP detection, as the image processors use it).

    Focus frames are raw: hot pixels and cosmic rays are left out (:func:`point_defects`), else
    they would be the sharpest "stars" of every frame.

    Args:
        threshold: Detection threshold in sigma.
        min_peak_snr: Only stars whose peak is this many sigma above the sky count.
        min_stars: Fewest stars a frame needs.
    """

    def __init__(
        self, *, threshold: float = 5.0, min_peak_snr: float = 10.0, min_stars: int = 3, **kwargs: Any
    ) -> None:
        super().__init__(**kwargs)
        if not (threshold > 0 and min_peak_snr > 0 and min_stars >= 1):
            raise ConfigError(
                f"need threshold > 0, min_peak_snr > 0, min_stars >= 1; got {threshold}, "
                f"{min_peak_snr}, {min_stars}",
                key="threshold",
            )
        self.threshold, self.min_peak_snr, self.min_stars = threshold, min_peak_snr, min_stars

    def _blocking_width(self, image: Image) -> float:
        data = float_data(image)
        background = estimate_background(data, image.mask)
        residual = data - background.level
        catalog = detect_sources_sep(
            data, image.mask, threshold=self.threshold, saturation=saturation_level(image, None)
        )
        return photometry_width(
            catalog["fwhm"],
            catalog["flags"],
            catalog["peak"],
            noise=background.global_rms,
            min_peak_snr=self.min_peak_snr,
            min_stars=self.min_stars,
            defects=point_defects(residual, catalog["x"], catalog["y"], catalog["peak"]),
        )


class AutoFocusSeries(Module, IAutoFocus):
    """Finds the best focus by a series of exposures.

    Args:
        camera: Module offering ICamera (with IExposureTime and IImageType).
        focuser: Module offering IFocuser.
        measure: How sharp a frame is; default :class:`PhotometryFocusMeasure`.
        use_offset: Step the focuser's offset instead of its base position (keeps a focus model's
            base untouched; the result is then base + offset).
        **kwargs: Module options.
    """

    def __init__(
        self,
        *,
        camera: str | ICamera,
        focuser: str | IFocuser,
        measure: FocusMeasure | None = None,
        use_offset: bool = False,
        **kwargs: Any,
    ) -> None:
        super().__init__(**kwargs)
        self._camera, self._focuser = camera, focuser
        self._measure = self.add_child(measure or PhotometryFocusMeasure())
        self._use_offset = use_offset
        self._runner = MotionRunner("focus series")
        self._status: dict[str, Any] = {"running": False}

    # --- IAutoFocus ----------------------------------------------------------------------------

    async def auto_focus(self, count: int, step: float, exposure_time: float) -> tuple[float, float]:
        if not (isinstance(count, int) and count >= MIN_FRAMES):
            raise InvalidArgumentError(f"count must be an integer >= {MIN_FRAMES}, got {count!r}")
        if not (math.isfinite(step) and step > 0 and math.isfinite(exposure_time) and exposure_time >= 0):
            raise InvalidArgumentError(
                f"step must be > 0 mm and exposure_time >= 0 s, got {step} and {exposure_time}"
            )
        self._runner.check_idle()
        return await self._runner.run("auto_focus", self._series(count, step, exposure_time))

    async def auto_focus_status(self) -> dict[str, Any]:
        return dict(self._status)

    async def abort(self) -> None:
        await self._runner.stop("aborted on request")

    # --- the series ----------------------------------------------------------------------------

    async def _series(self, count: int, step: float, exposure_time: float) -> tuple[float, float]:
        focuser = await self.proxy(self._focuser, IFocuser)
        camera = await self.proxy(self._camera, ICamera)
        original = await (focuser.get_focus_offset() if self._use_offset else focuser.get_focus())
        positions = series_positions(original, count, step, await self._reachable(focuser))
        widths: list[float] = []
        frame_problems: dict[str, int] = {}  # why frames gave no width, and how many
        self._status = {"running": True, "count": count, "step": step, "done": 0, "measurements": []}
        found = False
        try:
            if isinstance(camera, IExposureTime):
                await camera.set_exposure_time(exposure_time)
            if isinstance(camera, IImageType):
                await camera.set_image_type(ImageType.FOCUS)
            filter_name: str | None = None
            for position in positions:
                await self._move(focuser, position)
                filename = await camera.grab_data(broadcast=False)
                async with self.clock.work("measure_focus"):
                    image = await Image.from_vfs(self.vfs, filename)
                    filter_name = _filter_of(image)
                    try:
                        width = await self._measure(image)
                    except NightcrewError as exc:  # a frame without stars does not end the series
                        log.warning("%s: focus %.4f: no width (%s)", self.name, position, exc)
                        frame_problems[str(exc)] = frame_problems.get(str(exc), 0) + 1
                        width = math.nan
                widths.append(width)
                log.info("%s: focus %.4f mm: width %.2f px", self.name, position, width)
                self._status["done"] = len(widths)
                self._status["measurements"].append((position, width))
                _check_widths_can_fit(widths, count)
            fit = fit_focus_hyperbola(positions, widths)
            await self._move(focuser, fit.focus)
            found = True
        except FocusSeriesError as exc:
            reason = _failure(exc, frame_problems)
            log.warning("%s: focus series failed: %s", self.name, reason)
            self._status["failed"] = reason
            await self.comm.send_event(FocusFailedEvent(reason=reason, filter_name=filter_name))
            if reason == str(exc):
                raise
            raise type(exc)(reason) from exc  # the same kind (e.g. outside the series), with the cause
        finally:
            self._status["running"] = False
            if not found:
                await asyncio.shield(self._restore(focuser, original))
        best = fit.focus + (await focuser.get_focus() if self._use_offset else 0.0)
        log.info(
            "%s: best focus %.4f ± %.4f mm (min width %.2f px)", self.name, best, fit.error, fit.min_width
        )
        self._status.update(focus=best, error=fit.error)
        await self.comm.send_event(FocusFoundEvent(focus=best, error=fit.error, filter_name=filter_name))
        return best, fit.error

    async def _reachable(self, focuser: IFocuser) -> tuple[float, float] | None:
        """The positions the series may use (offsets when it steps the offset), if the focuser says."""
        if not isinstance(focuser, IFocusRange):
            return None
        low, high = await focuser.get_focus_range()
        base = await focuser.get_focus() if self._use_offset else 0.0
        return low - base, high - base

    async def _move(self, focuser: IFocuser, position: float) -> None:
        await (focuser.set_focus_offset(position) if self._use_offset else focuser.set_focus(position))

    async def _restore(self, focuser: IFocuser, original: float) -> None:
        try:
            await self._move(focuser, original)
            log.info("%s: focus restored to %.4f", self.name, original)
        except NightcrewError as exc:
            log.error("%s: could not restore the focus to %.4f: %s", self.name, original, exc)


def _check_widths_can_fit(widths: list[float], count: int) -> None:
    """End a series as soon as too many frames gave no width for the fit to work (e.g. a camera
    showing no stars): the frames left would be taken in vain."""
    missing = sum(1 for width in widths if not (math.isfinite(width) and width > 0))
    if count - missing < MIN_FRAMES:
        raise FocusSeriesError(
            f"{missing} of {len(widths)} frames gave no width: fewer than {MIN_FRAMES} of {count} can"
        )


def _failure(exc: FocusSeriesError, frame_problems: dict[str, int]) -> str:
    """The fit's reason, with why frames gave no width (the cause a user can act on)."""
    if not frame_problems:
        return str(exc)
    causes = "; ".join(f"{count} x {problem}" for problem, count in frame_problems.items())
    return f"{exc} (frames without a width: {causes})"


def _filter_of(image: Image) -> str | None:
    value = image.header.get("FILTER")
    return value if isinstance(value, str) else None
