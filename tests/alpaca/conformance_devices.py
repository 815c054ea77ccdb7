"""The checks of each device type's own members (ConformU's per-type protocol tests).

See :mod:`tests.alpaca.conformance` for the rules; here the members ConformU reads and writes per
type, the first-use checks from the interface definitions, and the cheap methods.
"""

from __future__ import annotations

from typing import Any

from .conformance import (
    BAD_REQUEST,
    BAD_VALUE,
    INVALID_OPERATION,
    VALUE_NOT_SET,
    Check,
    Current,
    calls,
    ids,
)

__all__ = ["device_checks"]

_GETS = {
    "camera": "BayerOffsetX BayerOffsetY BinX BinY CameraState CameraXSize CameraYSize CanAbortExposure "
    "CanAsymmetricBin CanFastReadout CanGetCoolerPower CanPulseGuide CanSetCCDTemperature CanStopExposure "
    "CCDTemperature CoolerOn CoolerPower ElectronsPerADU ExposureMax ExposureMin ExposureResolution "
    "FastReadout FullWellCapacity Gain GainMax GainMin Gains HasShutter HeatSinkTemperature ImageReady "
    "IsPulseGuiding MaxADU MaxBinX MaxBinY NumX NumY Offset OffsetMax OffsetMin Offsets PercentCompleted "
    "PixelSizeX PixelSizeY ReadoutMode ReadoutModes SensorName SensorType SetCCDTemperature StartX StartY "
    "SubExposureDuration",
    "covercalibrator": "Brightness CalibratorState CoverState MaxBrightness",
    "dome": "AtHome AtPark Azimuth CanFindHome CanPark CanSetAltitude CanSetAzimuth CanSetPark CanSetShutter "
    "CanSlave CanSyncAzimuth ShutterStatus Slaved Slewing",
    "filterwheel": "FocusOffsets Names Position",
    "focuser": "Absolute IsMoving MaxIncrement MaxStep Position StepSize TempComp TempCompAvailable "
    "Temperature",
    "observingconditions": "AveragePeriod CloudCover DewPoint Humidity Pressure RainRate SkyBrightness "
    "SkyQuality SkyTemperature StarFWHM Temperature WindDirection WindGust WindSpeed",
    "rotator": "CanReverse IsMoving MechanicalPosition Position Reverse StepSize TargetPosition",
    "safetymonitor": "IsSafe",
    "switch": "MaxSwitch",
    "telescope": "AlignmentMode Altitude ApertureArea ApertureDiameter AtHome AtPark Azimuth CanPark "
    "CanPulseGuide CanSetDeclinationRate CanSetGuideRates CanSetPark CanSetPierSide CanSetTracking CanSlew "
    "CanSlewAltAz CanSlewAltAzAsync CanSync CanSyncAltAz CanUnpark Declination DeclinationRate "
    "DoesRefraction EquatorialSystem FocalLength GuideRateDeclination GuideRateRightAscension "
    "IsPulseGuiding RightAscension RightAscensionRate SideOfPier SiderealTime SiteElevation SiteLatitude "
    "SiteLongitude Slewing SlewSettleTime Tracking TrackingRate TrackingRates UTCDate",
}

#: Properties written back with the value just read (ConformU's PutOneParameter), and fallbacks.
_PUTS = {
    "camera": {"BinX": "1", "BinY": "1", "CoolerOn": "False", "FastReadout": "False", "Gain": "1",
               "NumX": "1", "NumY": "1", "Offset": "1", "ReadoutMode": "0", "SetCCDTemperature": "1",
               "StartX": "0", "StartY": "0", "SubExposureDuration": "1"},
    "dome": {"Slaved": "False"},
    "focuser": {"TempComp": "False"},
    "observingconditions": {"AveragePeriod": "0.0"},
    "rotator": {"Reverse": "False"},
    "telescope": {"DeclinationRate": "0.0", "DoesRefraction": "False", "GuideRateDeclination": "0.1",
                  "GuideRateRightAscension": "0.1", "RightAscensionRate": "0.0", "SideOfPier": "0",
                  "SiteElevation": "0", "SiteLatitude": "0", "SiteLongitude": "0", "SlewSettleTime": "0",
                  "TargetDeclination": "0", "TargetRightAscension": "0", "Tracking": "False",
                  "TrackingRate": "0", "UTCDate": "2026-01-01T00:00:00.000Z"},
}  # fmt: skip


def device_checks(device_type: str, number: int) -> list[Check]:
    """The type's own members: first-use checks, then reads, writes and cheap methods."""
    base = f"/api/v1/{device_type}/{number}"
    checks: list[Check] = []
    if device_type == "camera":
        checks.append(
            Check(
                "GET LastExposureDuration before any exposure",
                "GET",
                f"{base}/lastexposureduration",
                ids(),
                errors=frozenset({INVALID_OPERATION}),
            )
        )
    if device_type == "telescope":
        for member in ("TargetRightAscension", "TargetDeclination"):
            checks.append(
                Check(
                    f"GET {member} before it is set",
                    "GET",
                    f"{base}/{member.lower()}",
                    ids(),
                    errors=frozenset({VALUE_NOT_SET}),
                )
            )
    for member in _GETS[device_type].split():
        checks += calls(base, "GET", member)
    for member, fallback in _PUTS.get(device_type, {}).items():
        checks += calls(base, "PUT", member, ((member, Current(member, fallback)),))
    checks += _methods(device_type, base)
    return checks


def _methods(device_type: str, base: str) -> list[Check]:
    if device_type == "telescope":
        return [
            *calls(base, "PUT", "AbortSlew"),
            *calls(base, "GET", "AxisRates", (("Axis", "0"),)),
            *calls(base, "GET", "CanMoveAxis", (("Axis", "0"),)),
            *calls(base, "PUT", "MoveAxis", (("Axis", "0"), ("Rate", "0.0"))),
            *calls(
                base,
                "PUT",
                "PulseGuide",
                (("Direction", "0"), ("Duration", "0")),
                wait_while=("IsPulseGuiding", True),
            ),
        ]
    if device_type == "camera":
        return _exposure(base)
    if device_type == "focuser":
        return [
            *calls(base, "PUT", "Halt"),
            *calls(
                base, "PUT", "Move", (("Position", Current("Position", "0")),), wait_while=("IsMoving", True)
            ),
        ]
    if device_type == "filterwheel":
        return calls(
            base, "PUT", "Position", (("Position", Current("Position", "0")),), wait_while=("Position", -1)
        )
    if device_type == "dome":
        return calls(base, "PUT", "AbortSlew")
    if device_type == "observingconditions":
        sensor = (("SensorName", "Pressure"),)
        return [
            *calls(base, "PUT", "Refresh"),
            *calls(base, "GET", "SensorDescription", sensor),
            *calls(base, "GET", "TimeSinceLastUpdate", sensor),
        ]
    if device_type == "switch":
        ident = (("Id", "0"),)
        members = "CanWrite GetSwitch GetSwitchDescription GetSwitchName GetSwitchValue MinSwitchValue "
        members += "MaxSwitchValue CanAsync SwitchStep"
        checks = [check for member in members.split() for check in calls(base, "GET", member, ident)]
        state = Current("GetSwitch", "False", ident)
        value = Current("GetSwitchValue", "0", ident)
        name = Current("GetSwitchName", "switch", ident)
        checks += calls(base, "PUT", "SetSwitch", (*ident, ("State", state)))
        checks += calls(base, "PUT", "SetSwitchName", (*ident, ("Name", name)), bad_values=("Id",))
        checks += calls(base, "PUT", "SetSwitchValue", (*ident, ("Value", value)))
        return checks
    if device_type == "rotator":
        moving: tuple[str, Any] = ("IsMoving", True)
        return [
            *calls(base, "PUT", "Halt"),
            *calls(base, "PUT", "Move", (("Position", "0"),), wait_while=moving),
            *calls(base, "PUT", "MoveAbsolute", (("Position", Current("Position", "0")),), wait_while=moving),
            *calls(
                base,
                "PUT",
                "MoveMechanical",
                (("Position", Current("MechanicalPosition", "0")),),
                wait_while=moving,
            ),
            *calls(base, "PUT", "Sync", (("Position", Current("Position", "0")),)),
        ]
    if device_type == "covercalibrator":
        changing: tuple[str, Any] = ("CalibratorState", 2)
        cover: tuple[str, Any] = ("CoverState", 2)
        brightness = (("Brightness", Current("MaxBrightness", "1")),)
        return [
            *calls(base, "PUT", "CalibratorOff", wait_while=changing),
            *calls(base, "PUT", "CalibratorOn", brightness, wait_while=changing),
            *calls(base, "PUT", "OpenCover", wait_while=cover),
            *calls(base, "PUT", "HaltCover", wait_while=cover),
            *calls(base, "PUT", "CloseCover", wait_while=cover),
        ]
    return []


def _exposure(base: str) -> list[Check]:
    """One short exposure of a 64 x 64 window (so the JSON ImageArray stays small), its image and
    times; then StartExposure's malformed variants, which must not start one."""
    good, expose = ids(), f"{base}/startexposure"
    window = [
        Check(f"PUT {n}=64", "PUT", f"{base}/{n.lower()}", (*good, (n, "64"))) for n in ("NumX", "NumY")
    ]
    exposure = (*good, ("Duration", "0.1"), ("Light", "True"))
    return [
        *window,
        Check("PUT StartExposure", "PUT", expose, exposure, wait_while=("ImageReady", False)),
        *calls(base, "GET", "ImageArray", image_array=True),
        *calls(base, "GET", "LastExposureDuration"),
        *calls(base, "GET", "LastExposureStartTime"),
        Check(
            "PUT StartExposure: Duration meaningless",
            "PUT",
            expose,
            (*good, ("Duration", BAD_VALUE), ("Light", "True")),
            statuses=BAD_REQUEST,
            invalid_value_ok=True,
        ),
        Check(
            "PUT StartExposure: Light meaningless",
            "PUT",
            expose,
            (*good, ("Duration", "0.1"), ("Light", BAD_VALUE)),
            statuses=BAD_REQUEST,
            invalid_value_ok=True,
        ),
        Check(
            "PUT StartExposure: Duration mis-cased",
            "PUT",
            expose,
            (*good, ("dURATION", "0.1"), ("Light", "True")),
            statuses=BAD_REQUEST,
        ),
    ]
