"""nightcrew.interfaces: the catalogue of interfaces modules offer, with their enums and result types.

Interfaces are small and composed by inheritance (``ITelescope`` is ``IMotion`` plus pointing).
Importing this package registers all of them, so :func:`interface_by_name` knows every name.
"""

from nightcrew.interfaces.automation import IAcquisition, IAutoGuiding, IFlatField, IPointingSeries
from nightcrew.interfaces.base import Interface, interface_by_name, interface_methods, interfaces_of
from nightcrew.interfaces.calibrator import CalibratorState, CoverState, ICoverCalibrator
from nightcrew.interfaces.camera import (
    Binning,
    CoolingStatus,
    IBinning,
    ICamera,
    ICooling,
    IData,
    IExposure,
    IExposureTime,
    IGain,
    IImageType,
    IStoppableExposure,
    IVideo,
    IWindow,
    Window,
)
from nightcrew.interfaces.control import IAbortable, IReady, IRunnable, IRunning, IStartStop
from nightcrew.interfaces.enums import (
    ExposureStatus,
    ImageType,
    LoopState,
    ModuleState,
    MotionStatus,
    PierSide,
    WeatherSensor,
)
from nightcrew.interfaces.filters import IFilters
from nightcrew.interfaces.fits import FitsCard, FitsValue, IFitsHeaderAfter, IFitsHeaderBefore
from nightcrew.interfaces.focus import IAutoFocus, IFocuser, IFocusModel, IFocusRange
from nightcrew.interfaces.module import IConfig, IModule
from nightcrew.interfaces.motion import IMotion
from nightcrew.interfaces.pointing import (
    IOffsetsAltAz,
    IOffsetsRaDec,
    IPierSide,
    IPointingAltAz,
    IPointingRaDec,
    ISyncRaDec,
    ITelescope,
)
from nightcrew.interfaces.robotic import (
    IAutonomous,
    IRobotic,
    IRoboticScheduler,
    IScriptRunner,
    Plan,
    PlannedTask,
    RoboticStatus,
    RoboticTask,
    UnplannedTask,
)
from nightcrew.interfaces.roof import IDome, IRoof
from nightcrew.interfaces.rotator import IRotator
from nightcrew.interfaces.sensors import ITemperatures
from nightcrew.interfaces.spectrograph import ISpectrograph
from nightcrew.interfaces.switch import ISwitch, SwitchInfo
from nightcrew.interfaces.tracking import INonSidereal
from nightcrew.interfaces.weather import IWeather, SensorValue, WeatherReport

__all__ = [
    "Binning",
    "CalibratorState",
    "CoolingStatus",
    "CoverState",
    "ExposureStatus",
    "FitsCard",
    "FitsValue",
    "IAbortable",
    "IAcquisition",
    "IAutoFocus",
    "IAutoGuiding",
    "IAutonomous",
    "IBinning",
    "ICamera",
    "IConfig",
    "ICooling",
    "ICoverCalibrator",
    "IData",
    "IDome",
    "IExposure",
    "IExposureTime",
    "IFilters",
    "IFitsHeaderAfter",
    "IFitsHeaderBefore",
    "IFlatField",
    "IFocusModel",
    "IFocusRange",
    "IFocuser",
    "IGain",
    "IImageType",
    "IModule",
    "IMotion",
    "INonSidereal",
    "IOffsetsAltAz",
    "IOffsetsRaDec",
    "IPierSide",
    "IPointingAltAz",
    "IPointingRaDec",
    "IPointingSeries",
    "IReady",
    "IRobotic",
    "IRoboticScheduler",
    "IRoof",
    "IRotator",
    "IRunnable",
    "IRunning",
    "IScriptRunner",
    "ISpectrograph",
    "IStartStop",
    "IStoppableExposure",
    "ISwitch",
    "ISyncRaDec",
    "ITelescope",
    "ITemperatures",
    "IVideo",
    "IWeather",
    "IWindow",
    "ImageType",
    "Interface",
    "LoopState",
    "ModuleState",
    "MotionStatus",
    "PierSide",
    "Plan",
    "PlannedTask",
    "RoboticStatus",
    "RoboticTask",
    "SensorValue",
    "SwitchInfo",
    "UnplannedTask",
    "WeatherReport",
    "WeatherSensor",
    "Window",
    "interface_by_name",
    "interface_methods",
    "interfaces_of",
]
