"""Modules driving ASCOM Alpaca devices, one per device type, on nightcrew's device bases."""

from nightcrew.modules.alpaca.camera import AlpacaCamera
from nightcrew.modules.alpaca.covercalibrator import AlpacaCoverCalibrator
from nightcrew.modules.alpaca.device import AlpacaModule
from nightcrew.modules.alpaca.dome import AlpacaDome
from nightcrew.modules.alpaca.filterwheel import AlpacaFilterWheel
from nightcrew.modules.alpaca.focuser import AlpacaFocuser
from nightcrew.modules.alpaca.observingconditions import AlpacaObservingConditions
from nightcrew.modules.alpaca.roof import AlpacaRoof
from nightcrew.modules.alpaca.rotator import AlpacaRotator
from nightcrew.modules.alpaca.safetymonitor import AlpacaSafetyMonitor
from nightcrew.modules.alpaca.server import AlpacaServer
from nightcrew.modules.alpaca.switch import AlpacaSwitch
from nightcrew.modules.alpaca.telescope import AlpacaTelescope

__all__ = [
    "AlpacaCamera",
    "AlpacaCoverCalibrator",
    "AlpacaDome",
    "AlpacaFilterWheel",
    "AlpacaFocuser",
    "AlpacaModule",
    "AlpacaObservingConditions",
    "AlpacaRoof",
    "AlpacaRotator",
    "AlpacaSafetyMonitor",
    "AlpacaServer",
    "AlpacaSwitch",
    "AlpacaTelescope",
]
