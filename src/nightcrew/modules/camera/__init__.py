"""Cameras: the base class every camera driver derives from, and what it shares with spectrographs."""

from nightcrew.modules.camera.base import BaseCamera, ExposureSettings
from nightcrew.modules.camera.exposing import ExposingModule, Frame
from nightcrew.modules.camera.video import BaseVideo

__all__ = ["BaseCamera", "BaseVideo", "ExposingModule", "ExposureSettings", "Frame"]
