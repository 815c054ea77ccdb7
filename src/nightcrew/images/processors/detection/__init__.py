"""Source detection: SEP (default) and photutils' DAOStarFinder, both filling ``image.catalog``
with the columns described in :mod:`._catalog`."""

from nightcrew.images.processors.detection._catalog import COLUMNS, FLAG_SATURATED
from nightcrew.images.processors.detection._daofind import DaoSourceDetection, detect_sources_dao
from nightcrew.images.processors.detection._sep import SepSourceDetection, detect_sources_sep

__all__ = [
    "COLUMNS",
    "FLAG_SATURATED",
    "DaoSourceDetection",
    "SepSourceDetection",
    "detect_sources_dao",
    "detect_sources_sep",
]
