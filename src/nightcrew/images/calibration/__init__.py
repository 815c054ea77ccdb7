"""Calibration: master bias, dark and flat from raw frames, and their application.

Array functions (:func:`combine_frames`, :func:`master_bias`, :func:`master_dark`,
:func:`master_flat`, :func:`calibrate_pixels`) do the arithmetic; :func:`build_master` and
:func:`calibrate_image` do it on :class:`~nightcrew.images.Image` with headers; the
:class:`Calibration` processor picks masters from a VFS directory (:func:`select_master`) and
keeps them in a :class:`CalibrationCache`.
"""

from nightcrew.images.calibration._combine import combine_frames
from nightcrew.images.calibration._images import build_master, calibrate_image, master_kind
from nightcrew.images.calibration._library import (
    TEMPERATURE_MARGIN,
    CalibrationCache,
    FrameKey,
    MasterInfo,
    MasterKind,
    frame_key,
    off_set_point,
    select_master,
)
from nightcrew.images.calibration._masters import (
    Combined,
    calibrate_pixels,
    master_bias,
    master_dark,
    master_flat,
)
from nightcrew.images.calibration._processor import Calibration, CalibrationError

__all__ = [
    "TEMPERATURE_MARGIN",
    "Calibration",
    "CalibrationCache",
    "CalibrationError",
    "Combined",
    "FrameKey",
    "MasterInfo",
    "MasterKind",
    "build_master",
    "calibrate_image",
    "calibrate_pixels",
    "combine_frames",
    "frame_key",
    "master_bias",
    "master_dark",
    "master_flat",
    "master_kind",
    "off_set_point",
    "select_master",
]
