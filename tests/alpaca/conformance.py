"""The Alpaca protocol checks ASCOM's ConformU makes, as raw HTTP requests to any Alpaca server.

Built from ConformU's check list (its Alpaca protocol tester, in its default tolerant mode), not
from its code: the same requests, and the same rule for each answer.

* Bad URLs (upper-case device type, an unknown type, device number -1, 99999 or ``A``, an unknown
  member): any HTTP 4xx. Other URL mistakes (``/apx/``, ``/api/v2/``, POST, DELETE) only need an
  answer.
* Every member read or written with ``ClientID``/``ClientTransactionID`` as the spec spells them,
  with an extra parameter, and with either name in lower case: HTTP 200, the four reply keys spelled
  exactly, ``Value`` in every GET reply without error, ``ClientTransactionID`` echoed (a mis-cased
  one in a PUT form may come back as 0) and ``ServerTransactionID`` >= 1... (tolerated as 0).
* ``ClientID``/``ClientTransactionID`` empty, blank, negative or not a number: HTTP 200 or 400.
* A parameter with a meaningless value, and a PUT parameter whose name is mis-cased (form names are
  case sensitive): HTTP 400, or 200 with InvalidValue (0x401); for a 400-only check a member that
  is NotImplemented (0x400) is tolerated.
* A PUT whose parameter is in the query string instead of the form: HTTP 400 (the API reference).
* Platform 7 interfaces: ``DeviceState`` is a list of ``{"Name", "Value"}``; ``Connect``,
  ``Disconnect`` and ``Connecting`` answer.

Added from the interface definitions, which ConformU's device tests check: an unknown ``Action``
is ActionNotImplemented (0x40C), ``LastExposureDuration`` before any exposure is InvalidOperation
(0x40B), ``TargetRightAscension``/``TargetDeclination`` before they are set are ValueNotSet (0x402).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

__all__ = ["Check", "Current", "Outcome", "common_checks", "device_checks"]

CLIENT_ID, TRANSACTION_ID, BAD_VALUE = "123456", "67890", "asduio6fghZZ"
_OK = frozenset({200})
_BAD = frozenset({400})
_EITHER = frozenset({200, 400})
_4XX = frozenset(range(400, 411))
_ANY: frozenset[int] = frozenset()
NOT_IMPLEMENTED, INVALID_VALUE, VALUE_NOT_SET = 0x400, 0x401, 0x402
INVALID_OPERATION, ACTION_NOT_IMPLEMENTED = 0x40B, 0x40C
#: ConformU's DeviceCapabilities: the first interface version of each type that is Platform 7.
PLATFORM7 = {
    "camera": 4,
    "covercalibrator": 2,
    "dome": 3,
    "filterwheel": 3,
    "focuser": 4,
    "observingconditions": 2,
    "rotator": 4,
    "safetymonitor": 3,
    "switch": 3,
    "telescope": 4,
}


@dataclass(frozen=True)
class Current:
    """A parameter value read from the device just before the check (ConformU writes back what
    it reads), ``fallback`` when the read fails."""

    member: str
    fallback: str
    params: tuple[tuple[str, str], ...] = ()


Value = str | Current


@dataclass(frozen=True)
class Check:
    """One request and the answers that conform."""

    name: str
    method: str
    path: str
    params: tuple[tuple[str, Value], ...] = ()
    statuses: frozenset[int] = _OK
    invalid_value_ok: bool = False
    miscased_transaction: bool = False
    errors: frozenset[int] | None = None
    device_state: bool = False
    image_array: bool = False
    #: Parameters of a PUT sent in the query string instead of the form.
    query: tuple[tuple[str, str], ...] = ()
    wait_while: tuple[str, Any] | None = None


@dataclass(frozen=True)
class Outcome:
    check: Check
    problem: str = ""
    detail: dict[str, Any] = field(default_factory=dict)


def _ids(client: str = "ClientID", transaction: str = "ClientTransactionID") -> tuple[tuple[str, Value], ...]:
    return ((client, CLIENT_ID), (transaction, TRANSACTION_ID))


_BAD_IDS = (
    ("ClientID is empty", (("ClientID", ""), ("ClientTransactionID", TRANSACTION_ID))),
    ("ClientID is blank", (("ClientID", "     "), ("ClientTransactionID", TRANSACTION_ID))),
    ("ClientID is negative", (("ClientID", "-12345"), ("ClientTransactionID", TRANSACTION_ID))),
    ("ClientID is not a number", (("ClientID", "NASDAQ"), ("ClientTransactionID", TRANSACTION_ID))),
    ("ClientTransactionID is empty", (("ClientID", CLIENT_ID), ("ClientTransactionID", ""))),
    ("ClientTransactionID is blank", (("ClientID", CLIENT_ID), ("ClientTransactionID", "     "))),
    ("ClientTransactionID is negative", (("ClientID", CLIENT_ID), ("ClientTransactionID", "-67890"))),
    ("ClientTransactionID is text", (("ClientID", CLIENT_ID), ("ClientTransactionID", "qweqwe"))),
)


def _invert(name: str) -> str:
    return name.swapcase()


def calls(
    base: str,
    method: str,
    member: str,
    params: tuple[tuple[str, Value], ...] = (),
    *,
    bad_values: tuple[str, ...] | None = None,
    bad_ids: bool = False,
    **expect: Any,
) -> list[Check]:
    """ConformU's variations of one call (GetNoParameters ... PutTwoParameters): good names, an
    extra parameter, lower-case ID names, each parameter mis-cased and (``bad_values``: those
    named) meaningless, and with ``bad_ids`` the eight bad ID values."""
    path = f"{base}/{member.lower()}"
    label = f"{method} {member}"
    checks = [
        Check(f"{label}: good casing", method, path, _ids() + params, **expect),
        Check(
            f"{label}: extra parameter",
            method,
            path,
            (*_ids(), ("ExtraParameter", "ExtraValue"), *params),
            **expect,
        ),
        Check(f"{label}: clientid lower case", method, path, _ids(client="clientid") + params, **expect),
        Check(
            f"{label}: clienttransactionid lower case",
            method,
            path,
            _ids(transaction="clienttransactionid") + params,
            miscased_transaction=method == "PUT",
            **expect,
        ),
    ]
    wait = {"wait_while": expect["wait_while"]} if "wait_while" in expect else {}
    for index, (name, value) in enumerate(params):
        others = params[:index] + params[index + 1 :]
        inverted = (*others[:index], (_invert(name), value), *others[index:])
        casing = _BAD if method == "PUT" else _OK
        checks.append(
            Check(f"{label}: {name} mis-cased", method, path, _ids() + inverted, statuses=casing, **wait)
        )
        if bad_values is None or name in bad_values:
            worse = (*others[:index], (name, BAD_VALUE), *others[index:])
            checks.append(
                Check(
                    f"{label}: {name} meaningless",
                    method,
                    path,
                    _ids() + worse,
                    statuses=_BAD,
                    invalid_value_ok=True,
                )
            )
    if bad_ids:
        checks += [
            Check(
                f"{label}: {what}",
                method,
                path,
                ids + params,
                statuses=_EITHER,
                invalid_value_ok=True,
                **wait,
            )
            for what, ids in _BAD_IDS
        ]
    return checks


def common_checks(device_type: str, number: int, interface_version: int) -> list[Check]:
    """What TestCommon and TestConnect check, plus Action."""
    base = f"/api/v1/{device_type}/{number}"
    other = f"{device_type}/{number}/description"
    checks = [
        Check("GET description: /apx/ (any answer)", "GET", f"/apx/v1/{other}", _ids(), statuses=_ANY),
        Check("GET description: /api/1/ (any answer)", "GET", f"/api/1/{other}", _ids(), statuses=_ANY),
        Check("GET description: /api/V1/ (any answer)", "GET", f"/api/V1/{other}", _ids(), statuses=_ANY),
        Check("GET description: /api/v2/ (any answer)", "GET", f"/api/v2/{other}", _ids(), statuses=_ANY),
        Check(
            "POST connected (any answer)",
            "POST",
            f"{base}/connected",
            (*_ids(), ("Connected", "True")),
            statuses=_ANY,
        ),
        Check("DELETE connected (any answer)", "DELETE", f"{base}/connected", _ids(), statuses=_ANY),
        Check(
            "upper-case device type",
            "GET",
            f"/api/v1/{device_type.upper()}/{number}/description",
            _ids(),
            statuses=_4XX,
        ),
        Check("unknown device type", "GET", "/api/v1/baddevicetype/0/description", _ids(), statuses=_4XX),
        Check("device number -1", "GET", f"/api/v1/{device_type}/-1/description", _ids(), statuses=_4XX),
        Check(
            "device number 99999", "GET", f"/api/v1/{device_type}/99999/description", _ids(), statuses=_4XX
        ),
        Check("device number A", "GET", f"/api/v1/{device_type}/A/description", _ids(), statuses=_4XX),
        Check("unknown member descrip", "GET", f"{base}/descrip", _ids(), statuses=_4XX),
        Check("upper-case member", "GET", f"{base}/DESCRIPTION", _ids(), statuses=_4XX),
    ]
    checks += calls(base, "GET", "Connected", bad_ids=True)
    for value in ("", "123456", "asdqwe"):
        params = (*_ids(), ("Connected", value))
        checks.append(
            Check(
                f"PUT Connected={value!r}",
                "PUT",
                f"{base}/connected",
                params,
                statuses=_BAD,
                invalid_value_ok=True,
            )
        )
    checks += calls(base, "PUT", "Connected", (("Connected", "True"),), bad_values=(), bad_ids=True)
    # The Alpaca API: a PUT's parameters are in its form; one in the query string is not there.
    in_query = (("Connected", "True"),)
    checks.append(
        Check("PUT Connected in the query string", "PUT", f"{base}/connected", _ids(), _BAD, query=in_query)
    )
    for member in (
        "Description",
        "DriverInfo",
        "DriverVersion",
        "InterfaceVersion",
        "Name",
        "SupportedActions",
    ):
        checks += calls(base, "GET", member, bad_ids=member == "Description")
    unknown = (("Action", "NoSuchActionNightcrewConformance"), ("Parameters", ""))
    checks.append(
        Check(
            "PUT Action unknown",
            "PUT",
            f"{base}/action",
            _ids() + unknown,
            errors=frozenset({ACTION_NOT_IMPLEMENTED}),
        )
    )
    if interface_version >= PLATFORM7[device_type]:
        checks += calls(base, "GET", "DeviceState", device_state=True)
        checks += calls(base, "PUT", "Disconnect", wait_while=("Connecting", True))
        checks += calls(base, "PUT", "Connect", wait_while=("Connecting", True))
        checks += calls(base, "GET", "Connecting")
    return checks


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
                _ids(),
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
                    _ids(),
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
    ids, expose = _ids(), f"{base}/startexposure"
    window = [Check(f"PUT {n}=64", "PUT", f"{base}/{n.lower()}", (*ids, (n, "64"))) for n in ("NumX", "NumY")]
    good = (*ids, ("Duration", "0.1"), ("Light", "True"))
    return [
        *window,
        Check("PUT StartExposure", "PUT", expose, good, wait_while=("ImageReady", False)),
        *calls(base, "GET", "ImageArray", image_array=True),
        *calls(base, "GET", "LastExposureDuration"),
        *calls(base, "GET", "LastExposureStartTime"),
        Check(
            "PUT StartExposure: Duration meaningless",
            "PUT",
            expose,
            (*ids, ("Duration", BAD_VALUE), ("Light", "True")),
            statuses=_BAD,
            invalid_value_ok=True,
        ),
        Check(
            "PUT StartExposure: Light meaningless",
            "PUT",
            expose,
            (*ids, ("Duration", "0.1"), ("Light", BAD_VALUE)),
            statuses=_BAD,
            invalid_value_ok=True,
        ),
        Check(
            "PUT StartExposure: Duration mis-cased",
            "PUT",
            expose,
            (*ids, ("dURATION", "0.1"), ("Light", "True")),
            statuses=_BAD,
        ),
    ]
