"""Aperture photometry on the catalog's positions: SEP and photutils, radii in arcsec or px."""

from nightcrew.images.processors.photometry._apertures import AperturePhotometry, flux_columns
from nightcrew.images.processors.photometry._implementations import PhotutilsPhotometry, SepPhotometry

__all__ = ["AperturePhotometry", "PhotutilsPhotometry", "SepPhotometry", "flux_columns"]
