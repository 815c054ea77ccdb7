"""Exposure time estimation from the image itself."""

from nightcrew.images.processors.exptime._star import (
    EXPOSURE_TIME_KEY,
    ExposureTimeEstimate,
    StarExposureTime,
    star_exposure_time,
)

__all__ = ["EXPOSURE_TIME_KEY", "ExposureTimeEstimate", "StarExposureTime", "star_exposure_time"]
