"""INDI devices as nightcrew modules (on the device bases), and nightcrew devices served over INDI."""

from nightcrew.modules.indi.calibrator import IndiCoverCalibrator
from nightcrew.modules.indi.camera import IndiCamera
from nightcrew.modules.indi.dome import IndiDome
from nightcrew.modules.indi.filters import IndiFilterWheel
from nightcrew.modules.indi.focuser import IndiFocuser
from nightcrew.modules.indi.link import IndiLink, IndiModule
from nightcrew.modules.indi.roof import IndiRoof
from nightcrew.modules.indi.rotator import IndiRotator
from nightcrew.modules.indi.server import IndiServer
from nightcrew.modules.indi.telescope import IndiTelescope
from nightcrew.modules.indi.weather import IndiWeather

__all__ = [
    "IndiCamera",
    "IndiCoverCalibrator",
    "IndiDome",
    "IndiFilterWheel",
    "IndiFocuser",
    "IndiLink",
    "IndiModule",
    "IndiRoof",
    "IndiRotator",
    "IndiServer",
    "IndiTelescope",
    "IndiWeather",
]
