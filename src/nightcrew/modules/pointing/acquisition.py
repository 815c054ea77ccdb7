"""Acquisition (centring): expose, find where the telescope really points, correct, until the
target sits on the chosen pixel.

Each iteration takes an image and runs the ``pipeline`` — detection and a plate solve near the
header position. When the frame has a WCS, the pointing error is read from it at ``target_pixel``
(default the frame centre): the sky there minus the position in the header (RA/DEC), which
*includes* the telescope's offsets; a pipeline without a solve ends in an offsets step instead
(e.g. :class:`~nightcrew.images.processors.offsets.BrightestStarOffsets`, with its own target).
The distance from the target is that error plus the offsets already applied. Below ``tolerance``
the target is acquired; above ``max_offset`` the measurement is not trusted (a wrong solve, the
wrong field) and nothing is moved; otherwise it is corrected by ``method``:

* ``offset``: the offsets that cancel the error are added
  (:class:`~nightcrew.modules.pointing.apply.ApplyRaDecOffsets`, or ``apply``);
* ``sync``: the mount is told where it really points (ISyncRaDec) and slews to the target again,
  so its own pointing model takes the correction (offsets are reset).

The result names the iterations (images taken) and the final offset; a target still off after
``max_iterations`` raises :class:`AcquisitionFailedError` with the last offset.

Example (YAML)::

    class: nightcrew.modules.pointing.Acquisition
    camera: camera
    telescope: telescope
    exposure_time: 2.0
    tolerance: 5.0          # arcsec
    target_pixel: [1023.5, 1023.5]   # 0-based (x, y); default the frame centre
    method: offset          # or sync
    max_iterations: 3
    max_offset: 1200.0      # arcsec
    pipeline:
      class: nightcrew.images.Pipeline
      steps:
        - {class: nightcrew.images.processors.detection.SepSourceDetection}
        - {class: nightcrew.images.astrometry.CatalogAstrometry}
"""

from __future__ import annotations

import logging
import math
from collections.abc import Iterable, Sequence
from pathlib import Path
from typing import Any, ClassVar, Literal

import astropy.units as u  # type: ignore[import-untyped]
from astropy.coordinates import Angle  # type: ignore[import-untyped]

from nightcrew.config import load_config, to_plain
from nightcrew.config._classes import ClassResolutionError, import_class
from nightcrew.errors import ConfigError, InterfaceError, InvalidArgumentError, NightcrewError
from nightcrew.images import Image, ImageProcessor
from nightcrew.images.astrometry import sky_to_standard, standard_to_sky
from nightcrew.images.processors.offsets import OFFSETS_KEY, AstrometryOffsets, Offsets
from nightcrew.interfaces import (
    IAcquisition,
    ICamera,
    IExposureTime,
    IImageType,
    ImageType,
    IPointingRaDec,
    ISyncRaDec,
)
from nightcrew.interfaces.quantities import ExposureTime
from nightcrew.modules.module import Module
from nightcrew.modules.motion.runner import MotionRunner
from nightcrew.modules.pointing.apply import ApplyOffsets, ApplyRaDecOffsets, SkyError, sky_error

__all__ = ["Acquisition", "AcquisitionFailedError", "CentringMethod", "target_pixel_problems"]

log = logging.getLogger(__name__)

#: How a measured error is corrected: telescope offsets, or a sync of the mount and a new slew.
CentringMethod = Literal["offset", "sync"]


class AcquisitionFailedError(NightcrewError):
    """The target was not centred within the allowed attempts."""


class Acquisition(Module, IAcquisition):
    """Centres the telescope's target on a pixel of the camera by iterated plate solves and corrections.

    Args:
        camera: Module offering ICamera (IExposureTime and IImageType are used if offered).
        telescope: The telescope: offered to the default ``apply``; synced with ``method: sync``.
        pipeline: Image processors: detection and a plate solve (or ending in an offsets step).
        apply: How offsets reach the telescope; default ``ApplyRaDecOffsets(telescope)``.
        exposure_time: Seconds per acquisition image.
        tolerance: Done when the target is closer than this to ``target_pixel`` (arcsec, > 0).
        target_pixel: 0-based (x, y) where the target should fall; None: the frame centre.
        method: ``offset`` (add offsets) or ``sync`` (sync the mount, slew to the target again).
        max_offset: Larger measured errors are refused and nothing is moved (arcsec).
        max_iterations: Most images taken (each is solved; all but a last one within tolerance
            are followed by a correction).
        position_angle: Detector orientation for images without a WCS (see pixel_error_to_sky).
        flip: East is +x on the detector.
        **kwargs: Module options.
    """

    config_moved_keys: ClassVar[dict[str, str]] = {
        "max_attempts": "is now 'max_iterations' (the same count: images taken)"
    }

    def __init__(
        self,
        *,
        camera: str | ICamera,
        pipeline: ImageProcessor,
        telescope: str = "telescope",
        apply: ApplyOffsets | None = None,
        exposure_time: ExposureTime = 2.0,
        tolerance: float = 5.0,
        target_pixel: Sequence[float] | None = None,
        method: CentringMethod = "offset",
        max_offset: float = 1200.0,
        max_iterations: int = 3,
        position_angle: float = 0.0,
        flip: bool = False,
        **kwargs: Any,
    ) -> None:
        super().__init__(**kwargs)
        if not tolerance > 0:
            raise ConfigError(f'tolerance must be > 0 arcsec, got {tolerance}"', key="tolerance")
        if not max_offset > tolerance:
            raise ConfigError(
                f'max_offset must be above tolerance ({tolerance:g}"), got {max_offset}"', key="max_offset"
            )
        if max_iterations < 1:
            raise ConfigError(f"max_iterations must be >= 1, got {max_iterations}", key="max_iterations")
        if not exposure_time >= 0:
            raise ConfigError(f"exposure_time must be >= 0 s, got {exposure_time}", key="exposure_time")
        if method not in ("offset", "sync"):
            raise ConfigError(f"method must be 'offset' or 'sync', got {method!r}", key="method")
        self._target_pixel = _target_pixel(target_pixel)
        self._camera, self._telescope, self._method = camera, telescope, method
        self._pipeline = self.add_child(pipeline)
        self._apply = self.add_child(apply or ApplyRaDecOffsets(telescope))
        self._locate = AstrometryOffsets(target=self._target_pixel)
        self._exposure_time = float(exposure_time)
        self._tolerance, self._max_offset = float(tolerance), float(max_offset)
        self._max_iterations = max_iterations
        self._position_angle, self._flip = float(position_angle), flip
        self._runner = MotionRunner("acquisition")

    async def is_running(self) -> bool:
        return self._runner.busy

    async def abort(self) -> None:
        await self._runner.stop("aborted on request")

    async def acquire_target(self) -> dict[str, Any]:
        self._runner.check_idle()
        return await self._runner.run("acquire_target", self._acquire())

    async def _acquire(self) -> dict[str, Any]:
        camera = await self.proxy(self._camera, ICamera)
        if isinstance(camera, IExposureTime):
            await camera.set_exposure_time(self._exposure_time)
        if isinstance(camera, IImageType):
            await camera.set_image_type(ImageType.ACQUISITION)
        history: list[float] = []
        for iteration in range(1, self._max_iterations + 1):
            applied = await self._apply.current()
            filename = await camera.grab_data(broadcast=False)
            async with self.clock.work("plate_solve"):
                image = await self._pipeline(await Image.from_vfs(self.vfs, filename))
                error, target = await self._measure(image, applied)
            history.append(error.distance)
            log.info(
                'iteration %d: target %.1f" off (E %.1f", N %.1f")',
                iteration,
                error.distance,
                error.east,
                error.north,
            )
            if error.distance < self._tolerance:
                log.info('centred in %d iteration(s): %.1f" from the target pixel', iteration, error.distance)
                return self._result(iteration, error, history)
            if error.distance > self._max_offset:
                raise InvalidArgumentError(
                    f'measured offset {error.distance:.1f}" exceeds max_offset {self._max_offset:g}": '
                    "not applied (wrong field or failed solve?)"
                )
            if self._method == "sync":
                await self._sync(error, target)
            else:
                await self._apply.apply(error)
        raise AcquisitionFailedError(
            f'target still {history[-1]:.1f}" off after {self._max_iterations} iterations '
            f'(tolerance {self._tolerance:g}"; offsets {", ".join(f"{d:.1f}" for d in history)}")'
        )

    async def _measure(self, image: Image, applied: SkyError) -> tuple[SkyError, tuple[float, float] | None]:
        """The error from the target at the target pixel (where it points minus the target), and
        the target: from the frame's WCS and the target in the header (OBJCTRA/OBJCTDEC) where it
        has them, so a mount that reports a little beside its target is still centred; else from
        the pipeline's offsets and the reported position (RA/DEC) less the offsets."""
        rows, cols = image.shape
        x, y = self._target_pixel or ((cols - 1) / 2.0, (rows - 1) / 2.0)
        if not (x <= cols - 1 and y <= rows - 1):
            raise InvalidArgumentError(
                f"target_pixel ({x:g}, {y:g}) is outside the {cols}x{rows} frame of the camera"
            )
        target = _header_target(image)
        if image.wcs is not None and target is not None:
            ra, dec = image.pixel_to_sky(x, y)
            east, north = sky_to_standard(ra, dec, *target)
            return SkyError(float(east) * 3600.0, float(north) * 3600.0), target
        offsets = image.metadata.get(OFFSETS_KEY)
        if image.wcs is not None and (offsets is None or offsets.source == AstrometryOffsets.__name__):
            offsets = (await self._locate(image)).metadata[OFFSETS_KEY]
        if not isinstance(offsets, Offsets):
            raise ConfigError("the acquisition pipeline gave neither a WCS nor offsets (add a plate solve)")
        measured = sky_error(offsets, image, position_angle=self._position_angle, flip=self._flip)
        reported = image.header.get("RA"), image.header.get("DEC")
        if not all(isinstance(v, int | float) and not isinstance(v, bool) for v in reported):
            return measured + applied, None
        ra, dec = standard_to_sky(-applied.east / 3600.0, -applied.north / 3600.0, *reported)
        return measured + applied, (float(ra), float(dec))  # the header position includes the offsets

    async def _sync(self, error: SkyError, target: tuple[float, float] | None) -> None:
        """Sync the mount on where the target pixel really points, then slew to the target again."""
        if target is None:
            raise InvalidArgumentError(
                "method: sync needs the target in the frame's header (OBJCTRA/OBJCTDEC or RA/DEC)"
            )
        try:
            sync = await self.proxy(self._telescope, ISyncRaDec)
        except InterfaceError as exc:
            raise InterfaceError(f"method: sync needs a telescope that syncs (ISyncRaDec): {exc}") from exc
        pointing = await self.proxy(self._telescope, IPointingRaDec)
        # The target pixel shows the target plus the error: the mount is told so, then slews by -error.
        true_ra, true_dec = standard_to_sky(error.east / 3600.0, error.north / 3600.0, *target)
        await sync.sync_radec(float(true_ra) % 360.0, float(true_dec))
        await pointing.move_radec(*target)

    def _result(self, iterations: int, error: SkyError, history: list[float]) -> dict[str, Any]:
        return {
            "iterations": iterations,
            "offset": error.distance,  # arcsec from the target pixel, remaining
            "offset_east": error.east,
            "offset_north": error.north,
            "offsets": history,  # arcsec, one per iteration
        }


def _header_target(image: Image) -> tuple[float, float] | None:
    """The telescope's target without offsets (OBJCTRA, OBJCTDEC: 'hh mm ss.ss', '+dd mm ss.s')."""
    ra, dec = image.header.get("OBJCTRA"), image.header.get("OBJCTDEC")
    if not (isinstance(ra, str) and isinstance(dec, str)):
        return None
    try:
        return float(Angle(ra, unit=u.hourangle).degree), float(Angle(dec, unit=u.deg).degree)
    except ValueError:
        return None


def _target_pixel(value: Sequence[float] | None) -> tuple[float, float] | None:
    if value is None:
        return None
    if len(value) != 2 or not all(isinstance(v, int | float) and math.isfinite(v) for v in value):
        raise ConfigError(f"target_pixel must be two numbers (x, y), got {value!r}", key="target_pixel")
    x, y = float(value[0]), float(value[1])
    if x < 0 or y < 0:
        raise ConfigError(
            f"target_pixel ({x:g}, {y:g}) is outside the frame (0-based pixels)", key="target_pixel"
        )
    return x, y


def target_pixel_problems(files: Iterable[Path]) -> list[str]:
    """For the module files of one observatory: a line per acquisition whose ``target_pixel`` lies
    outside the chip its camera (a module file among ``files``, by name) states (``detector``:
    ``chip_width``, ``chip_height``); cameras that state none are checked on the first frame."""
    modules: dict[str, tuple[Path, dict[str, Any]]] = {}
    for path in files:
        try:
            config = to_plain(load_config(path))
        except ConfigError:
            continue  # reported by the file's own check
        if isinstance(config, dict) and "class" in config:
            modules[str(config.get("name") or path.stem)] = (path, config)
    problems = []
    for path, config in modules.values():
        try:
            if not issubclass(import_class(str(config["class"])), Acquisition):
                continue
            camera_path, camera = modules[str(config.get("camera"))]
            detector = camera["detector"]
            x, y = (float(v) for v in config["target_pixel"])
            width, height = int(detector["chip_width"]), int(detector["chip_height"])
        except (ConfigError, ClassResolutionError, KeyError, TypeError, ValueError):
            continue  # no such camera or chip here, or a value the file's own check names
        if not (x <= width - 1 and y <= height - 1):
            problems.append(
                f"{path}: key 'target_pixel': ({x:g}, {y:g}) is outside the {width}x{height} frame "
                f"of the camera in {camera_path}"
            )
    return problems
