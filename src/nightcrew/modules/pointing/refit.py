"""Passive refit: the pointing model learns from the frames the observatory takes anyway.

On each NewImageEvent of an object frame (from ``sources``, all cameras by default) the frame is
read and plate-solved (``solver``: SEP detection and :class:`CatalogAstrometry` by default), and
its solved centre is paired with where the mount was sent: ``MNT-RA``/``MNT-DEC`` when the
telescope applies a pointing model, else ``RA``/``DEC``, at the frame's ``DATE-OBS``. The latest
``max_pairs`` pairs are kept; every ``every`` new pairs the model is fitted again with outlier
rejection and replaces the one in ``model`` (the telescope's ``pointing_model`` file, which it reads
again when it changes) by the rule of :mod:`nightcrew.astro.pointing_refit`. Each decision is
logged. Frames that do not solve are skipped (logged at DEBUG): a cloudy frame is no pair.

Example (YAML)::

    class: nightcrew.modules.pointing.PassivePointingRefit
    telescope: telescope
    model: pointing-model.yaml    # the telescope's pointing_model
    rule: {min_pairs: 30, every: 10, min_improvement: 0.25}
"""

from __future__ import annotations

import asyncio
import logging
from collections import deque
from collections.abc import Mapping
from typing import Any

from nightcrew.astro.pointing import PointingModelError, PointingPair, icrs_pair
from nightcrew.astro.pointing_refit import RefitRule, refit_decision
from nightcrew.config import DataPath
from nightcrew.errors import ConfigError, NightcrewError
from nightcrew.events import NewImageEvent
from nightcrew.images import Image, ImageProcessor, Pipeline
from nightcrew.images.astrometry import CatalogAstrometry
from nightcrew.images.processors.detection import SepSourceDetection
from nightcrew.interfaces import ImageType, ModuleState
from nightcrew.modules.module import Module
from nightcrew.modules.pointing.series import exposure_start, solved_centre
from nightcrew.modules.telescope.pointing_model import TelescopePointingModel, save_pointing_model

__all__ = ["PassivePointingRefit"]

log = logging.getLogger(__name__)


class PassivePointingRefit(Module):
    """Refits the telescope's pointing model from routine frames (see the module docstring).

    Args:
        telescope: Name of the telescope module (the model file must be for it).
        model: The telescope's ``pointing_model`` file, written when a refit replaces the model.
        solver: Image processors that leave a WCS in the image.
        sources: Only frames from these modules; all by default.
        rule: Options of :class:`~nightcrew.astro.pointing_refit.RefitRule` (``terms``,
            ``min_pairs``, ``max_pairs``, ``every``, ``min_improvement``, ``max_rms``, ``max_term``,
            ``max_sigma``, ``clip``).
        max_queue: Frames waiting to be solved at most; more are dropped.
        **kwargs: Module options (``site`` is required).
    """

    def __init__(
        self,
        *,
        telescope: str = "telescope",
        model: DataPath,
        solver: ImageProcessor | None = None,
        sources: list[str] | None = None,
        rule: Mapping[str, Any] | None = None,
        max_queue: int = 20,
        **kwargs: Any,
    ) -> None:
        super().__init__(**kwargs)
        if self.site is None:
            raise ConfigError("a pointing refit needs the observatory site (hour angles)", key="site")
        try:
            options = dict(rule or {})
            if "terms" in options:
                options["terms"] = tuple(options["terms"])
            self._rule = RefitRule(**options)
        except (PointingModelError, TypeError) as exc:
            raise ConfigError(str(exc), key="rule") from exc
        if max_queue < 1:
            raise ConfigError(f"must be >= 1, got {max_queue}", key="max_queue")
        self._telescope, self._path = telescope, model
        self._current = TelescopePointingModel(model, telescope, self.site)  # ConfigError if not its file
        self._solver = self.add_child(solver or Pipeline([SepSourceDetection(), CatalogAstrometry()]))
        self._sources = set(sources) if sources is not None else None
        self._pairs: deque[PointingPair] = deque(maxlen=self._rule.max_pairs)
        self._new_pairs = 0
        self._queue: asyncio.Queue[str] = asyncio.Queue(max_queue)
        self.add_background_task(self._solve_loop)

    @property
    def pairs(self) -> int:
        """Pairs kept now."""
        return len(self._pairs)

    async def join(self) -> None:
        """Return once every frame received so far has been measured (or skipped)."""
        await self._queue.join()

    async def open(self) -> None:
        if self.state is not ModuleState.STARTING:
            return
        await super().open()
        await self.comm.register_event(NewImageEvent, self.on_new_image)

    async def on_new_image(self, event: NewImageEvent, sender: str) -> None:
        if self._sources is not None and sender not in self._sources:
            return
        if event.image_type not in (ImageType.OBJECT, ImageType.ACQUISITION):
            return
        try:
            self._queue.put_nowait(event.filename)
        except asyncio.QueueFull:
            log.warning("%s: %d frames waiting; %s not used", self.name, self._queue.qsize(), event.filename)

    async def _solve_loop(self) -> None:
        while True:
            path = await self._queue.get()
            try:
                pair = await self.measure(path)
                if pair is not None:
                    self.add_pair(pair)
            except NightcrewError as exc:
                log.debug("%s: %s gives no pair: %s", self.name, path, exc)
            finally:
                self._queue.task_done()

    async def measure(self, path: str) -> PointingPair | None:
        """The pair of the frame at VFS ``path``; None if its header says nothing of the mount."""
        image = await Image.from_vfs(self.vfs, path)
        header = image.header
        keys = ("MNT-RA", "MNT-DEC") if "MNT-RA" in header else ("RA", "DEC")
        if not all(isinstance(header.get(key), int | float) for key in keys):
            return None
        commanded = (float(header[keys[0]]), float(header[keys[1]]))
        start = exposure_start(image, self.clock.time())
        async with self.clock.work("plate_solve"):
            solved = solved_centre(await self._solver(image))
        assert self.site is not None  # checked in the constructor
        return icrs_pair(commanded, solved, self.site.longitude, start)

    def add_pair(self, pair: PointingPair) -> None:
        """Keep the pair; every ``every`` new pairs, refit and maybe replace the model."""
        self._pairs.append(pair)
        self._new_pairs += 1
        if self._new_pairs >= self._rule.every:
            self._new_pairs = 0
            self.refit()

    def refit(self) -> bool:
        """Fit the pairs kept; write the model if the rule says it replaces the current one."""
        assert self.site is not None
        current = self._current.model
        decision = refit_decision(
            list(self._pairs), current, self._rule, mount=self._telescope, latitude=self.site.latitude
        )
        if decision.model is None:
            log.info("%s: pointing model kept (%d pairs): %s", self.name, len(self._pairs), decision.reason)
            return False
        save_pointing_model(self._path, decision.model)
        log.info(
            "%s: pointing model replaced from %d pairs: %s; written to %s",
            self.name,
            len(self._pairs),
            decision.reason,
            self._path,
        )
        return True
