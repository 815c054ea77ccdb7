// Generated from the nightcrew catalogue by `nightcrew catalogue --js clients/js/generated`.
// Do not edit: change the Python interface, event or error and generate again.
import { IAbortable } from "./interfaces/IAbortable.js";
import { IAcquisition } from "./interfaces/IAcquisition.js";
import { IAutoFocus } from "./interfaces/IAutoFocus.js";
import { IAutoGuiding } from "./interfaces/IAutoGuiding.js";
import { IAutonomous } from "./interfaces/IAutonomous.js";
import { IBinning } from "./interfaces/IBinning.js";
import { ICamera } from "./interfaces/ICamera.js";
import { IConfig } from "./interfaces/IConfig.js";
import { ICooling } from "./interfaces/ICooling.js";
import { ICoverCalibrator } from "./interfaces/ICoverCalibrator.js";
import { IData } from "./interfaces/IData.js";
import { IDome } from "./interfaces/IDome.js";
import { IExposure } from "./interfaces/IExposure.js";
import { IExposureTime } from "./interfaces/IExposureTime.js";
import { IFilters } from "./interfaces/IFilters.js";
import { IFitsHeaderAfter } from "./interfaces/IFitsHeaderAfter.js";
import { IFitsHeaderBefore } from "./interfaces/IFitsHeaderBefore.js";
import { IFlatField } from "./interfaces/IFlatField.js";
import { IFocusModel } from "./interfaces/IFocusModel.js";
import { IFocuser } from "./interfaces/IFocuser.js";
import { IGain } from "./interfaces/IGain.js";
import { IImageType } from "./interfaces/IImageType.js";
import { IModule } from "./interfaces/IModule.js";
import { IMotion } from "./interfaces/IMotion.js";
import { IOffsetsAltAz } from "./interfaces/IOffsetsAltAz.js";
import { IOffsetsRaDec } from "./interfaces/IOffsetsRaDec.js";
import { IPointingAltAz } from "./interfaces/IPointingAltAz.js";
import { IPointingRaDec } from "./interfaces/IPointingRaDec.js";
import { IPointingSeries } from "./interfaces/IPointingSeries.js";
import { IReady } from "./interfaces/IReady.js";
import { IRobotic } from "./interfaces/IRobotic.js";
import { IRoboticScheduler } from "./interfaces/IRoboticScheduler.js";
import { IRoof } from "./interfaces/IRoof.js";
import { IRotator } from "./interfaces/IRotator.js";
import { IRunnable } from "./interfaces/IRunnable.js";
import { IRunning } from "./interfaces/IRunning.js";
import { IScriptRunner } from "./interfaces/IScriptRunner.js";
import { ISimFocuserTruth } from "./interfaces/ISimFocuserTruth.js";
import { ISimTelescopeTruth } from "./interfaces/ISimTelescopeTruth.js";
import { ISimWeatherTruth } from "./interfaces/ISimWeatherTruth.js";
import { ISpectrograph } from "./interfaces/ISpectrograph.js";
import { IStartStop } from "./interfaces/IStartStop.js";
import { ISwitch } from "./interfaces/ISwitch.js";
import { ISyncRaDec } from "./interfaces/ISyncRaDec.js";
import { ITelescope } from "./interfaces/ITelescope.js";
import { ITemperatures } from "./interfaces/ITemperatures.js";
import { IVideo } from "./interfaces/IVideo.js";
import { IWeather } from "./interfaces/IWeather.js";
import { IWindow } from "./interfaces/IWindow.js";
export * from "./events.js";
export * from "./errors.js";

export { IAbortable, IAcquisition, IAutoFocus, IAutoGuiding, IAutonomous, IBinning, ICamera, IConfig, ICooling, ICoverCalibrator, IData, IDome, IExposure, IExposureTime, IFilters, IFitsHeaderAfter, IFitsHeaderBefore, IFlatField, IFocusModel, IFocuser, IGain, IImageType, IModule, IMotion, IOffsetsAltAz, IOffsetsRaDec, IPointingAltAz, IPointingRaDec, IPointingSeries, IReady, IRobotic, IRoboticScheduler, IRoof, IRotator, IRunnable, IRunning, IScriptRunner, ISimFocuserTruth, ISimTelescopeTruth, ISimWeatherTruth, ISpectrograph, IStartStop, ISwitch, ISyncRaDec, ITelescope, ITemperatures, IVideo, IWeather, IWindow };
/** Every interface class, by the name in its disco#info feature. */
export const INTERFACES = { IAbortable, IAcquisition, IAutoFocus, IAutoGuiding, IAutonomous, IBinning, ICamera, IConfig, ICooling, ICoverCalibrator, IData, IDome, IExposure, IExposureTime, IFilters, IFitsHeaderAfter, IFitsHeaderBefore, IFlatField, IFocusModel, IFocuser, IGain, IImageType, IModule, IMotion, IOffsetsAltAz, IOffsetsRaDec, IPointingAltAz, IPointingRaDec, IPointingSeries, IReady, IRobotic, IRoboticScheduler, IRoof, IRotator, IRunnable, IRunning, IScriptRunner, ISimFocuserTruth, ISimTelescopeTruth, ISimWeatherTruth, ISpectrograph, IStartStop, ISwitch, ISyncRaDec, ITelescope, ITemperatures, IVideo, IWeather, IWindow };
/** Calls without an announcement may take this many clock seconds. */
export const DEFAULT_TIMEOUT = 10.0;
