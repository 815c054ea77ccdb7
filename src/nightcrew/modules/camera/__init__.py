"""Cameras: the base class every camera driver derives from, what it shares with spectrographs, and
the cooling schedule that runs a camera's cooler for the night."""

from nightcrew.modules.camera.base import BaseCamera, ExposureSettings
from nightcrew.modules.camera.cooling import CoolingSchedule
from nightcrew.modules.camera.exposing import ExposingModule, Frame
from nightcrew.modules.camera.video import BaseVideo

__all__ = ["BaseCamera", "BaseVideo", "CoolingSchedule", "ExposingModule", "ExposureSettings", "Frame"]
