"""Acquisition: expose, find where the telescope really points, offset, until the target is centred.

Each attempt takes an image, runs the ``pipeline`` — typically detection, a plate solve near the
header position and :class:`~nightcrew.images.processors.offsets.AstrometryOffsets` — and reads
``metadata["offsets"]``: the pointing error against the position in the header (RA/DEC), which
*includes* the telescope's offsets. The distance from the target is that error plus the offsets
already applied. Below ``tolerance`` the target is acquired; above ``max_offset`` the measurement
is not trusted (a wrong solve, the wrong field) and nothing is moved; otherwise the offsets that
cancel the error are added (:class:`~nightcrew.modules.pointing.apply.ApplyRaDecOffsets`).

Example (YAML)::

    class: nightcrew.modules.pointing.Acquisition
    camera: camera
    telescope: telescope
    exposure_time: 2.0
    tolerance: 2.0        # arcsec
    max_offset: 1200.0    # arcsec
    pipeline:
      class: nightcrew.images.Pipeline
      steps:
        - {class: nightcrew.images.processors.detection.SepSourceDetection}
        - {class: nightcrew.images.astrometry.CatalogAstrometry}
        - {class: nightcrew.images.processors.offsets.AstrometryOffsets}
"""

from __future__ import annotations

import logging
from typing import Any

from nightcrew.errors import ConfigError, InvalidArgumentError, NightcrewError
from nightcrew.images import Image, ImageProcessor
from nightcrew.images.processors.offsets import OFFSETS_KEY, Offsets
from nightcrew.interfaces import IAcquisition, ICamera, IExposureTime, IImageType, ImageType
from nightcrew.interfaces.quantities import ExposureTime
from nightcrew.modules.module import Module
from nightcrew.modules.motion.runner import MotionRunner
from nightcrew.modules.pointing.apply import ApplyOffsets, ApplyRaDecOffsets, SkyError, sky_error

__all__ = ["Acquisition", "AcquisitionFailedError"]

log = logging.getLogger(__name__)


class AcquisitionFailedError(NightcrewError):
    """The target was not centred within the allowed attempts."""


class Acquisition(Module, IAcquisition):
    """Centres the telescope's target on the camera by iterated exposures and offsets.

    Args:
        camera: Module offering ICamera (IExposureTime and IImageType are used if offered).
        telescope: The telescope, offered to the default ``apply``.
        pipeline: Image processors ending in an offsets processor (see the module docstring).
        apply: How offsets reach the telescope; default ``ApplyRaDecOffsets(telescope)``.
        exposure_time: Seconds per acquisition image.
        tolerance: Done when the target is closer than this to the centre (arcsec).
        max_offset: Larger measured errors are refused and nothing is moved (arcsec).
        max_attempts: Most images taken.
        position_angle: Detector orientation for images without a WCS (see pixel_error_to_sky).
        flip: East is +x on the detector.
        **kwargs: Module options.
    """

    def __init__(
        self,
        *,
        camera: str | ICamera,
        pipeline: ImageProcessor,
        telescope: str = "telescope",
        apply: ApplyOffsets | None = None,
        exposure_time: ExposureTime = 2.0,
        tolerance: float = 2.0,
        max_offset: float = 1200.0,
        max_attempts: int = 5,
        position_angle: float = 0.0,
        flip: bool = False,
        **kwargs: Any,
    ) -> None:
        super().__init__(**kwargs)
        if not (tolerance > 0 and max_offset > tolerance):
            raise ConfigError(
                f"need 0 < tolerance < max_offset, got {tolerance}, {max_offset}", key="tolerance"
            )
        if max_attempts < 1 or not exposure_time >= 0:
            raise ConfigError("max_attempts must be >= 1 and exposure_time >= 0", key="max_attempts")
        self._camera = camera
        self._pipeline = self.add_child(pipeline)
        self._apply = self.add_child(apply or ApplyRaDecOffsets(telescope))
        self._exposure_time = float(exposure_time)
        self._tolerance, self._max_offset = float(tolerance), float(max_offset)
        self._max_attempts = max_attempts
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
        for attempt in range(1, self._max_attempts + 1):
            applied = await self._apply.current()
            filename = await camera.grab_data(broadcast=False)
            async with self.clock.work("plate_solve"):
                image = await self._pipeline(await Image.from_vfs(self.vfs, filename))
            offsets = image.metadata.get(OFFSETS_KEY)
            if not isinstance(offsets, Offsets):
                raise ConfigError("the acquisition pipeline gave no offsets (end it with an offsets step)")
            measured = sky_error(offsets, image, position_angle=self._position_angle, flip=self._flip)
            error = measured + applied  # from the target: the header position includes the offsets
            history.append(error.distance)
            log.info(
                '%s: attempt %d: target %.1f" off (E %.1f", N %.1f")',
                self.name,
                attempt,
                error.distance,
                error.east,
                error.north,
            )
            if error.distance < self._tolerance:
                return self._result(attempt, error, history)
            if error.distance > self._max_offset:
                raise InvalidArgumentError(
                    f'measured offset {error.distance:.1f}" exceeds max_offset {self._max_offset:g}": '
                    "not applied (wrong field or failed solve?)"
                )
            await self._apply.apply(error)
        raise AcquisitionFailedError(
            f'target still {history[-1]:.1f}" off after {self._max_attempts} attempts '
            f'(tolerance {self._tolerance:g}"; distances {", ".join(f"{d:.1f}" for d in history)})'
        )

    def _result(self, attempts: int, error: SkyError, history: list[float]) -> dict[str, Any]:
        return {
            "attempts": attempts,
            "offset_east": error.east,  # arcsec, remaining
            "offset_north": error.north,
            "distance": error.distance,
            "distances": history,  # arcsec, one per attempt
        }
