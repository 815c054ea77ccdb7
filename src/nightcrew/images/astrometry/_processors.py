"""Astrometry processors: each solves an image's detected stars and writes the WCS into its header.

From YAML, after a detection step::

    - class: nightcrew.images.astrometry.CatalogAstrometry
      index_dir: /usr/share/astrometry  # the index files whose stars it matches
      pixel_scale_arcsec: 1.16        # unbinned; times XBINNING
    - class: nightcrew.images.astrometry.SolveFieldAstrometry
      solver: {class: nightcrew.images.astrometry.SolveField, timeout_s: 60, index_dir: /data/indexes}
    - class: nightcrew.images.astrometry.RemoteAstrometry
      solver: {class: nightcrew.images.astrometry.RemoteSolver, url: "http://solver.example.org:8080"}
    - class: nightcrew.images.astrometry.FirstSolution   # the first solver that succeeds
      solvers: [{class: ...CatalogAstrometry}, {class: ...SolveFieldAstrometry}]

Each processor takes its configured solver object (``matcher`` or ``solver``) and keeps only what
it reads from the image (hints, catalog, star column); the solver's own options are set on it.

The result is also in ``image.metadata["astrometry"]`` (:class:`AstrometryResult`).
"""

from __future__ import annotations

import asyncio
import inspect
from collections.abc import Mapping, Sequence
from typing import Any, ClassVar

from astropy.io import fits  # type: ignore[import-untyped]

from nightcrew.config import build_object
from nightcrew.errors import ConfigError
from nightcrew.images.astrometry._coverage import DEFAULT_INDEX_DIR
from nightcrew.images.astrometry._errors import AstrometryError
from nightcrew.images.astrometry._image_wcs import (
    AstrometryResult,
    image_pixel_scale,
    image_pointing,
    image_stars,
    require_pointing,
    with_wcs,
)
from nightcrew.images.astrometry._index_catalog import IndexCatalog
from nightcrew.images.astrometry._match import CatalogMatch, CatalogMatcher
from nightcrew.images.astrometry._remote import RemoteSolver
from nightcrew.images.astrometry._solve_field import SolveField, SolveHints
from nightcrew.images.errors import ImageError, MissingWcsError
from nightcrew.images.image import Image
from nightcrew.images.processor import ImageProcessor, require

__all__ = ["CatalogAstrometry", "FirstSolution", "RemoteAstrometry", "SolveFieldAstrometry"]


_REMOVED_CATALOG = (
    "is gone: the matcher's stars are those of the index files in index_dir "
    "(the simulated sky's: nightcrew sim prints its index directory)"
)


def _configured(build: Any, **arguments: Any) -> Any:
    """``build(**arguments)``, a ValueError turned into a ConfigError naming its argument."""
    try:
        return build(**arguments)
    except ValueError as exc:
        name = str(exc).split(" ", 1)[0]
        raise ConfigError(str(exc), key=name if name in arguments else None) from exc


def _moved_into(solver: type, key: str) -> dict[str, str]:
    """The solver's options, once the processor's own keys, → where they are set now."""
    return {
        name: f"is an option of the solver object now: {key}: "
        f"{{class: nightcrew.images.astrometry.{solver.__name__}, {name}: ...}}"
        for name in inspect.signature(solver).parameters
    }


def _reject_moved(processor: type, options: Mapping[str, Any]) -> None:
    """A clear error for a moved key given in code (a config file's is reported by the validator)."""
    moved: dict[str, str] = getattr(processor, "config_moved_keys", {})
    for name in options:
        if name in moved:
            raise ConfigError(f"key '{name}' of {processor.__name__} {moved[name]}", key=name)


class CatalogAstrometry(ImageProcessor):
    """Fast solve near the header's RA/DEC (:class:`CatalogMatcher`) against the stars of index files.

    Args:
        index_dir: Directory of the astrometry.net index files whose stars are the reference
            catalog (:class:`IndexCatalog`): the same directory ``solve-field`` and
            ``nightcrew solver`` use (``~`` is expanded).
        pixel_scale_arcsec: Unbinned pixel scale (times ``XBINNING``); None: from the image.
        flux_column: Catalog column ranking the detected stars.
        matcher: The configured :class:`CatalogMatcher` (``search_radius_arcmin``, ...); its defaults
            when None.
        **kwargs: Processor options.
    """

    config_moved_keys: ClassVar[dict[str, str]] = {
        **_moved_into(CatalogMatcher, "matcher"),
        "catalog_depth": _REMOVED_CATALOG,
        "catalog_seed": _REMOVED_CATALOG,
    }

    def __init__(
        self,
        *,
        index_dir: str = DEFAULT_INDEX_DIR,
        pixel_scale_arcsec: float | None = None,
        flux_column: str = "flux",
        matcher: CatalogMatcher | None = None,
        **kwargs: Any,
    ) -> None:
        _reject_moved(CatalogAstrometry, kwargs)
        super().__init__(**kwargs)
        require(
            pixel_scale_arcsec is None or pixel_scale_arcsec > 0,
            "pixel_scale_arcsec",
            f"pixel_scale_arcsec must be positive, got {pixel_scale_arcsec}",
        )
        self.pixel_scale_arcsec = pixel_scale_arcsec
        self.flux_column = flux_column
        self.catalog = IndexCatalog(index_dir)
        self.matcher = matcher or CatalogMatcher()

    async def __call__(self, image: Image) -> Image:
        match = await asyncio.to_thread(self._blocking_solve, image)
        result = AstrometryResult("catalog", match.matched, match.rms_arcsec)
        return with_wcs(image, match.wcs.header_cards(), result)

    def _blocking_solve(self, image: Image) -> CatalogMatch:
        x, y, flux = image_stars(image, self.flux_column)
        ra, dec = require_pointing(image)
        scale = image_pixel_scale(image, self.pixel_scale_arcsec)
        if scale is None:
            raise MissingWcsError("the catalog matcher needs a pixel scale: configure pixel_scale_arcsec")
        radius = self.matcher.catalog_radius_deg(image.shape, scale)
        catalog_ra, catalog_dec, catalog_mag = self.catalog.query(ra, dec, radius)
        return self.matcher.solve(
            x,
            y,
            flux,
            shape=image.shape,
            catalog_ra=catalog_ra,
            catalog_dec=catalog_dec,
            catalog_mag=catalog_mag,
            ra_deg=ra,
            dec_deg=dec,
            pixel_scale_arcsec=scale,
        )


class _HintedSolver(ImageProcessor):
    """Common options of the solvers that take :class:`SolveHints`."""

    def __init__(
        self,
        *,
        pixel_scale_arcsec: float | None,
        scale_tolerance: float,
        radius_deg: float,
        flux_column: str,
        **kwargs: Any,
    ) -> None:
        super().__init__(**kwargs)
        _configured(
            SolveHints,
            pixel_scale_arcsec=pixel_scale_arcsec,
            scale_tolerance=scale_tolerance,
            radius_deg=radius_deg,
        )
        self.pixel_scale_arcsec = pixel_scale_arcsec
        self.scale_tolerance = scale_tolerance
        self.radius_deg = radius_deg
        self.flux_column = flux_column

    def hints(self, image: Image) -> SolveHints:
        """Position (when the header has one) and scale (when known) of ``image``."""
        pointing = image_pointing(image)
        return SolveHints(
            ra_deg=None if pointing is None else pointing[0],
            dec_deg=None if pointing is None else pointing[1],
            radius_deg=self.radius_deg,
            pixel_scale_arcsec=image_pixel_scale(image, self.pixel_scale_arcsec),
            scale_tolerance=self.scale_tolerance,
        )


class SolveFieldAstrometry(_HintedSolver):
    """Local astrometry.net ``solve-field`` on the detected stars (or on the pixels without a catalog).

    Args:
        pixel_scale_arcsec: Unbinned pixel scale hint (times ``XBINNING``); None: from the image.
        scale_tolerance: Relative uncertainty of the scale hint.
        radius_deg: Search radius around the header's position.
        use_pixels: Let solve-field find the stars even when the image has a catalog.
        solver: The configured :class:`SolveField` (``timeout_s``, ``config``, ...); its defaults
            when None.
        **kwargs: Processor options.
    """

    config_moved_keys: ClassVar[dict[str, str]] = _moved_into(SolveField, "solver")

    def __init__(
        self,
        *,
        pixel_scale_arcsec: float | None = None,
        scale_tolerance: float = 0.1,
        radius_deg: float = 1.0,
        flux_column: str = "flux",
        use_pixels: bool = False,
        solver: SolveField | None = None,
        **kwargs: Any,
    ) -> None:
        _reject_moved(SolveFieldAstrometry, kwargs)
        super().__init__(
            pixel_scale_arcsec=pixel_scale_arcsec,
            scale_tolerance=scale_tolerance,
            radius_deg=radius_deg,
            flux_column=flux_column,
            **kwargs,
        )
        self.use_pixels = use_pixels
        self.solver = solver or SolveField()

    async def __call__(self, image: Image) -> Image:
        hints = self.hints(image)
        cards: fits.Header
        if self.use_pixels or image.catalog is None:
            cards = await self.solver.solve_image(image.data, hints=hints)
        else:
            x, y, flux = image_stars(image, self.flux_column)
            cards = await self.solver.solve_stars(x, y, flux, shape=image.shape, hints=hints)
        return with_wcs(image, cards, AstrometryResult("astrometry.net"))


class RemoteAstrometry(_HintedSolver):
    """A remote solve service (:class:`RemoteSolver`, JSON API documented there) on the detected stars.

    Args:
        solver: The configured :class:`RemoteSolver` (``url``, ``timeout_s``, ``max_stars``).
        pixel_scale_arcsec, scale_tolerance, radius_deg: Hints, as for :class:`SolveFieldAstrometry`.
        **kwargs: Processor options.
    """

    config_moved_keys: ClassVar[dict[str, str]] = _moved_into(RemoteSolver, "solver")

    def __init__(
        self,
        *,
        solver: RemoteSolver | None = None,
        pixel_scale_arcsec: float | None = None,
        scale_tolerance: float = 0.1,
        radius_deg: float = 1.0,
        flux_column: str = "flux",
        **kwargs: Any,
    ) -> None:
        _reject_moved(RemoteAstrometry, kwargs)
        if solver is None:
            raise ConfigError(
                "name the service: solver: {class: nightcrew.images.astrometry.RemoteSolver, url: ...}",
                key="solver",
            )
        super().__init__(
            pixel_scale_arcsec=pixel_scale_arcsec,
            scale_tolerance=scale_tolerance,
            radius_deg=radius_deg,
            flux_column=flux_column,
            **kwargs,
        )
        self.solver = solver

    async def __call__(self, image: Image) -> Image:
        x, y, flux = image_stars(image, self.flux_column)
        cards = await self.solver.solve_stars(x, y, flux, shape=image.shape, hints=self.hints(image))
        return with_wcs(image, cards, AstrometryResult("remote"))


class FirstSolution(ImageProcessor):
    """Tries solvers in order and returns the first solution (e.g. the fast matcher, then solve-field).

    An image error of one solver (no solution, missing solver, too few stars) is logged at debug
    level and the next one is tried; when all fail, the last error is raised.

    Args:
        solvers: Processors, or their descriptions (mappings with ``class``).
    """

    def __init__(self, solvers: Sequence[ImageProcessor | Mapping[str, Any]], **kwargs: Any) -> None:
        super().__init__(**kwargs)
        require(len(solvers) > 0, "solvers", "solvers must name at least one processor")
        self.solvers: list[ImageProcessor] = []
        for index, solver in enumerate(solvers):
            if not isinstance(solver, ImageProcessor | Mapping):
                raise ConfigError(
                    f"expected an image processor or its description, got {solver!r}", key=f"solvers.{index}"
                )
            built = solver if isinstance(solver, ImageProcessor) else build_object(solver, ImageProcessor)
            self.solvers.append(self.add_child(built))

    async def __call__(self, image: Image) -> Image:
        error: ImageError | None = None
        for solver in self.solvers:
            try:
                return await solver(image)
            except ImageError as exc:
                error = exc
        assert error is not None
        raise (
            error if isinstance(error, AstrometryError) else AstrometryError(f"no solver succeeded: {error}")
        )
