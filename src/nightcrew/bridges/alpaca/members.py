"""The members of each Alpaca device interface (ASCOM Platform 7), as they appear in URLs.

The server needs them to tell two kinds of request apart, as the Alpaca API reference and ConformU
do: a member of the device's interface that nightcrew does not implement is a well-formed request
answered with NotImplemented (0x400), while a name that is no member at all (``descrip``) is a bad
URL, answered with HTTP 400. Names from the ASCOM interface definitions (ITelescopeV4, ICameraV4,
IDomeV3, IFocuserV4, IFilterWheelV3, ISafetyMonitorV3, IObservingConditionsV2, IRotatorV4,
ISwitchV3, ICoverCalibratorV2), lower-cased as in URLs.
"""

from __future__ import annotations

__all__ = ["DEVICE_MEMBERS", "INFORMATIONAL_MEMBERS", "has_method", "is_member"]

#: Members of every device (IAscomDeviceV2): read with GET, written or called with PUT.
_COMMON_GET = "connected connecting description devicestate driverinfo driverversion interfaceversion name "
_COMMON_PUT = "action commandblind commandbool commandstring connect connected disconnect "

#: Members that answer without a connection (what a client reads to choose and connect a device).
INFORMATIONAL_MEMBERS = frozenset(
    {
        "connected",
        "connecting",
        "connect",
        "disconnect",
        "description",
        "driverinfo",
        "driverversion",
        "interfaceversion",
        "name",
        "supportedactions",
    }
)

#: Per device type: (members read with GET, members written or called with PUT); a read-write
#: property is in both.
_TYPES = {
    "camera": (
        "bayeroffsetx bayeroffsety binx biny camerastate cameraxsize cameraysize canabortexposure "
        "canasymmetricbin canfastreadout cangetcoolerpower canpulseguide cansetccdtemperature "
        "canstopexposure ccdtemperature cooleron coolerpower electronsperadu exposuremax exposuremin "
        "exposureresolution fastreadout fullwellcapacity gain gainmax gainmin gains hasshutter "
        "heatsinktemperature imagearray imagearrayvariant imageready ispulseguiding "
        "lastexposureduration lastexposurestarttime maxadu maxbinx maxbiny numx numy offset offsetmax "
        "offsetmin offsets percentcompleted pixelsizex pixelsizey readoutmode readoutmodes sensorname "
        "sensortype setccdtemperature startx starty subexposureduration",
        "binx biny cooleron fastreadout gain numx numy offset readoutmode setccdtemperature startx "
        "starty subexposureduration abortexposure pulseguide startexposure stopexposure",
    ),
    "covercalibrator": (
        "brightness calibratorchanging calibratorstate covermoving coverstate maxbrightness",
        "calibratoroff calibratoron closecover haltcover opencover",
    ),
    "dome": (
        "altitude athome atpark azimuth canfindhome canpark cansetaltitude cansetazimuth cansetpark "
        "cansetshutter canslave cansyncazimuth shutterstatus slaved slewing",
        "slaved abortslew closeshutter findhome openshutter park setpark slewtoaltitude slewtoazimuth "
        "synctoazimuth",
    ),
    "filterwheel": ("focusoffsets names position", "position"),
    "focuser": (
        "absolute ismoving maxincrement maxstep position stepsize tempcomp tempcompavailable temperature",
        "tempcomp halt move",
    ),
    "observingconditions": (
        "averageperiod cloudcover dewpoint humidity pressure rainrate skybrightness skyquality "
        "skytemperature starfwhm temperature winddirection windgust windspeed sensordescription "
        "timesincelastupdate",
        "averageperiod refresh",
    ),
    "rotator": (
        "canreverse ismoving mechanicalposition position reverse stepsize targetposition",
        "reverse halt move moveabsolute movemechanical sync",
    ),
    "safetymonitor": ("issafe", ""),
    "switch": (
        "maxswitch canasync canwrite getswitch getswitchdescription getswitchname getswitchvalue "
        "maxswitchvalue minswitchvalue switchstep statechangecomplete",
        "setswitch setswitchname setswitchvalue setasync setasyncvalue cancelasync",
    ),
    "telescope": (
        "alignmentmode altitude aperturearea aperturediameter athome atpark azimuth canfindhome canpark "
        "canpulseguide cansetdeclinationrate cansetguiderates cansetpark cansetpierside "
        "cansetrightascensionrate cansettracking canslew canslewaltaz canslewaltazasync canslewasync "
        "cansync cansyncaltaz canunpark declination declinationrate doesrefraction equatorialsystem "
        "focallength guideratedeclination guideraterightascension ispulseguiding rightascension "
        "rightascensionrate sideofpier siderealtime siteelevation sitelatitude sitelongitude slewing "
        "slewsettletime targetdeclination targetrightascension tracking trackingrate trackingrates "
        "utcdate axisrates canmoveaxis destinationsideofpier",
        "declinationrate doesrefraction guideratedeclination guideraterightascension "
        "rightascensionrate sideofpier siteelevation sitelatitude sitelongitude slewsettletime "
        "targetdeclination targetrightascension tracking trackingrate utcdate abortslew findhome "
        "moveaxis park pulseguide setpark slewtoaltaz slewtoaltazasync slewtocoordinates "
        "slewtocoordinatesasync slewtotarget slewtotargetasync synctoaltaz synctocoordinates "
        "synctotarget unpark",
    ),
}

#: Per device type and HTTP method (``get``, ``put``): the members of its interface.
DEVICE_MEMBERS: dict[str, dict[str, frozenset[str]]] = {
    device_type: {
        "get": frozenset((_COMMON_GET + "supportedactions " + gets).split()),
        "put": frozenset((_COMMON_PUT + puts).split()),
    }
    for device_type, (gets, puts) in _TYPES.items()
}


def is_member(device_type: str, member: str) -> bool:
    """Whether ``member`` (lower case) belongs to the Alpaca interface of ``device_type``."""
    members = DEVICE_MEMBERS[device_type]
    return member in members["get"] or member in members["put"]


def has_method(device_type: str, method: str, member: str) -> bool:
    """Whether the interface of ``device_type`` has ``member`` for ``method`` (``get``, ``put``)."""
    return member in DEVICE_MEMBERS[device_type][method]
