"""The Weather module and its stations (the pure evaluation lives in :mod:`nightcrew.weather`)."""

from nightcrew.modules.weather.module import FITS_KEYWORDS, Weather
from nightcrew.modules.weather.stations import (
    Average,
    CombinedStation,
    CsvFileStation,
    Current,
    HttpJsonStation,
    ModuleStation,
    Station,
    SunStation,
)

__all__ = [
    "FITS_KEYWORDS",
    "Average",
    "CombinedStation",
    "CsvFileStation",
    "Current",
    "HttpJsonStation",
    "ModuleStation",
    "Station",
    "SunStation",
    "Weather",
]
