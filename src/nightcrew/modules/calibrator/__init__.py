"""Telescope covers and flat-field lights: the base class for their drivers."""

from nightcrew.modules.calibrator.base import BaseCoverCalibrator

__all__ = ["BaseCoverCalibrator"]
