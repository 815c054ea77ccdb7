"""Plate solving: turning detected stars (or pixels) into a WCS.

Three solvers, fastest first:

- :class:`CatalogMatcher` matches detected stars against :class:`~nightcrew.sim.catalog.StarCatalog`
  stars near a known pointing (no internet, well under a second per frame).
- :class:`SolveField` runs astrometry.net's ``solve-field`` locally (a blind search is possible).
- :class:`RemoteSolver` asks a remote solve service over HTTP (see :mod:`._remote` for the API).

Errors derive from :class:`AstrometryError` (an :class:`~nightcrew.images.errors.ImageError`).
"""

from nightcrew.images.astrometry._errors import AstrometryError, NoSolutionError, SolverUnavailableError
from nightcrew.images.astrometry._match import CatalogMatch, CatalogMatcher
from nightcrew.images.astrometry._remote import API_VERSION, RemoteSolver
from nightcrew.images.astrometry._solve_field import SolveField, SolveHints
from nightcrew.images.astrometry._tan import TanFit, TanWcs, fit_tan_wcs, sky_to_standard, standard_to_sky

__all__ = [
    "API_VERSION",
    "AstrometryError",
    "CatalogMatch",
    "CatalogMatcher",
    "NoSolutionError",
    "RemoteSolver",
    "SolveField",
    "SolveHints",
    "SolverUnavailableError",
    "TanFit",
    "TanWcs",
    "fit_tan_wcs",
    "sky_to_standard",
    "standard_to_sky",
]
