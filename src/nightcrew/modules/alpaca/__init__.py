"""Modules driving ASCOM Alpaca devices, one per device type, on nightcrew's device bases."""

from nightcrew.modules.alpaca.covercalibrator import AlpacaCoverCalibrator
from nightcrew.modules.alpaca.device import AlpacaModule
from nightcrew.modules.alpaca.dome import AlpacaDome
from nightcrew.modules.alpaca.observingconditions import AlpacaObservingConditions
from nightcrew.modules.alpaca.roof import AlpacaRoof
from nightcrew.modules.alpaca.rotator import AlpacaRotator
from nightcrew.modules.alpaca.safetymonitor import AlpacaSafetyMonitor
from nightcrew.modules.alpaca.server import AlpacaServer
from nightcrew.modules.alpaca.switch import AlpacaSwitch

__all__ = [
    "AlpacaCoverCalibrator",
    "AlpacaDome",
    "AlpacaModule",
    "AlpacaObservingConditions",
    "AlpacaRoof",
    "AlpacaRotator",
    "AlpacaSafetyMonitor",
    "AlpacaServer",
    "AlpacaSwitch",
]
