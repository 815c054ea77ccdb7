"""Device contract suites: pytest classes a driver's test module subclasses (see nightcrew.testing)."""

from nightcrew.testing.contracts._base import ContractProbe, ContractSetup, DeviceContract, timed_call
from nightcrew.testing.contracts.calibrator import CoverCalibratorContract
from nightcrew.testing.contracts.camera import CameraContract
from nightcrew.testing.contracts.filters import FilterWheelContract
from nightcrew.testing.contracts.focuser import FocuserContract
from nightcrew.testing.contracts.roof import DomeContract, RoofContract
from nightcrew.testing.contracts.rotator import RotatorContract
from nightcrew.testing.contracts.switch import SwitchContract
from nightcrew.testing.contracts.telescope import TelescopeContract
from nightcrew.testing.contracts.weather import WeatherStationContract

__all__ = [
    "CameraContract",
    "ContractProbe",
    "ContractSetup",
    "CoverCalibratorContract",
    "DeviceContract",
    "DomeContract",
    "FilterWheelContract",
    "FocuserContract",
    "RoofContract",
    "RotatorContract",
    "SwitchContract",
    "TelescopeContract",
    "WeatherStationContract",
    "timed_call",
]
