"""Astrometry errors, under :class:`nightcrew.images.errors.ImageError`::

ImageError
└── AstrometryError          a plate solve could not be done
    ├── SolverUnavailableError  the solver is missing (no solve-field) or unreachable (service)
    └── NoSolutionError         the solver ran but found no WCS for the stars
"""

from __future__ import annotations

from nightcrew.images.errors import ImageError

__all__ = ["AstrometryError", "NoSolutionError", "SolverUnavailableError"]


class AstrometryError(ImageError):
    """Base of all plate-solving errors."""


class SolverUnavailableError(AstrometryError):
    """The solver cannot be run: solve-field is not installed, or the service does not answer."""


class NoSolutionError(AstrometryError):
    """The solver ran but found no solution (too few stars, wrong hints, a field off the catalog)."""
