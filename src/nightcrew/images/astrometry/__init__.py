"""Plate solving: turning detected stars (or pixels) into a WCS.

Three solvers, fastest first:

- :class:`CatalogMatcher` matches detected stars against :class:`~nightcrew.sim.catalog.StarCatalog`
  stars near a known pointing (no internet, well under a second per frame).
- :class:`SolveField` runs astrometry.net's ``solve-field`` locally (a blind search is possible).
- :class:`RemoteSolver` asks a remote solve service over HTTP (see :mod:`._remote` for the API).

Each has a processor for pipelines (:class:`CatalogAstrometry`, :class:`SolveFieldAstrometry`,
:class:`RemoteAstrometry`, and :class:`FirstSolution` to chain them as fallbacks).

:func:`index_coverage_problem` says whether the installed index files fit a camera's field.

Errors derive from :class:`AstrometryError` (an :class:`~nightcrew.images.errors.ImageError`).
"""

from nightcrew.images.astrometry._coverage import (
    camera_field_arcmin,
    camera_fields_arcmin,
    index_coverage_problem,
    observatory_coverage_problems,
)
from nightcrew.images.astrometry._errors import AstrometryError, NoSolutionError, SolverUnavailableError
from nightcrew.images.astrometry._image_wcs import AstrometryResult, is_wcs_keyword, with_wcs
from nightcrew.images.astrometry._match import CatalogMatch, CatalogMatcher
from nightcrew.images.astrometry._processors import (
    CatalogAstrometry,
    FirstSolution,
    RemoteAstrometry,
    SolveFieldAstrometry,
)
from nightcrew.images.astrometry._remote import API_VERSION, RemoteSolver
from nightcrew.images.astrometry._solve_field import SolveField, SolveHints
from nightcrew.images.astrometry._tan import TanFit, TanWcs, fit_tan_wcs, sky_to_standard, standard_to_sky

__all__ = [
    "API_VERSION",
    "AstrometryError",
    "AstrometryResult",
    "CatalogAstrometry",
    "CatalogMatch",
    "CatalogMatcher",
    "FirstSolution",
    "NoSolutionError",
    "RemoteAstrometry",
    "RemoteSolver",
    "SolveField",
    "SolveFieldAstrometry",
    "SolveHints",
    "SolverUnavailableError",
    "TanFit",
    "TanWcs",
    "camera_field_arcmin",
    "camera_fields_arcmin",
    "fit_tan_wcs",
    "index_coverage_problem",
    "is_wcs_keyword",
    "observatory_coverage_problems",
    "sky_to_standard",
    "standard_to_sky",
    "with_wcs",
]
