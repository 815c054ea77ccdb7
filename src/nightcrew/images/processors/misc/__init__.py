"""Miscellaneous processors: masks, background removal, soft binning, flips, normalisation, FWHM
(seeing) measurement and file names."""

from nightcrew.images.processors.misc._filename import FILENAME_KEY, CreateFilename
from nightcrew.images.processors.misc._fwhm import (
    FWHM_KEY,
    FwhmMeasurement,
    MeasureFwhm,
    measure_fwhm,
    moffat_fwhm,
)
from nightcrew.images.processors.misc._pixels import (
    Flip,
    Mask,
    Normalise,
    RemoveBackground,
    SoftBin,
    soft_bin,
)

__all__ = [
    "FILENAME_KEY",
    "FWHM_KEY",
    "CreateFilename",
    "Flip",
    "FwhmMeasurement",
    "Mask",
    "MeasureFwhm",
    "Normalise",
    "RemoveBackground",
    "SoftBin",
    "measure_fwhm",
    "moffat_fwhm",
    "soft_bin",
]
