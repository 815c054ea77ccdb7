"""The simulated observatory's devices: ordinary modules built on the device bases."""

from nightcrew.modules.sim.calibrator import SimCoverCalibrator
from nightcrew.modules.sim.camera import SimCamera
from nightcrew.modules.sim.filters import SimFilterWheel
from nightcrew.modules.sim.focuser import SimFocuser
from nightcrew.modules.sim.interfaces import ISimFocuserTruth, ISimTelescopeTruth, ISimWeatherTruth
from nightcrew.modules.sim.roof import SimDome, SimRoof
from nightcrew.modules.sim.rotator import SimRotator
from nightcrew.modules.sim.switch import SimSwitch
from nightcrew.modules.sim.telescope import SimTelescope
from nightcrew.modules.sim.weather import SimWeatherStation

__all__ = [
    "ISimFocuserTruth",
    "ISimTelescopeTruth",
    "ISimWeatherTruth",
    "SimCamera",
    "SimCoverCalibrator",
    "SimDome",
    "SimFilterWheel",
    "SimFocuser",
    "SimRoof",
    "SimRotator",
    "SimSwitch",
    "SimTelescope",
    "SimWeatherStation",
]
