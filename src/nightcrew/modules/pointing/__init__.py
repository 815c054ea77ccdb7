"""Pointing automation: acquisition of targets, auto-guiding, and the offsets they send."""

from nightcrew.modules.pointing.acquisition import Acquisition, AcquisitionFailedError
from nightcrew.modules.pointing.apply import ApplyAltAzOffsets, ApplyOffsets, ApplyRaDecOffsets
from nightcrew.modules.pointing.guiding import AutoGuiding, BaseGuiding, ScienceFrameAutoGuiding
from nightcrew.modules.pointing.refit import PassivePointingRefit
from nightcrew.modules.pointing.series import PointingSeries as PointingSeries

__all__ = [
    "Acquisition",
    "AcquisitionFailedError",
    "ApplyAltAzOffsets",
    "ApplyOffsets",
    "ApplyRaDecOffsets",
    "AutoGuiding",
    "BaseGuiding",
    "PassivePointingRefit",
    "ScienceFrameAutoGuiding",
]
