"""nightcrew's test kit: device contract suites and the helpers tests share.

Every telescope, camera, roof, dome, focuser, filter-wheel, rotator, switch, cover-calibrator and
weather-station module — simulated, Alpaca, INDI or a user's own driver — proves the same behaviour
by subclassing a contract suite. Needs pytest and pytest-asyncio (``pip install nightcrew[testing]``).

Contract suites
---------------
:class:`TelescopeContract`, :class:`CameraContract`, :class:`RoofContract`, :class:`DomeContract`,
:class:`FocuserContract`, :class:`FilterWheelContract`, :class:`RotatorContract`,
:class:`SwitchContract`, :class:`CoverCalibratorContract`, :class:`WeatherStationContract` are
pytest classes full of ``test_*`` methods. They are not collected themselves (their names do not
start with ``Test``); a subclass called ``Test...`` is, and it provides one thing: an async fixture
named ``contract`` that yields a :class:`ContractSetup` — the started device module and a
:class:`ContractProbe` on the same network (started first, so it hears every event)::

    from collections.abc import AsyncIterator
    from typing import Any

    import pytest

    from nightcrew.clock import RealClock
    from nightcrew.testing import ContractProbe, ContractSetup, Observatory, TelescopeContract
    from mydriver import MyTelescope


    class TestMyTelescope(TelescopeContract):
        pointing_tolerance = 2.0 / 60.0  # degrees; a parameter of the suite (see its class)

        @pytest.fixture
        async def contract(self) -> AsyncIterator[ContractSetup[Any]]:
            async with Observatory(clock=RealClock()) as obs:  # a real device: real time
                probe = await obs.start(ContractProbe, "probe")
                telescope = await obs.start(MyTelescope, "telescope", port="/dev/ttyUSB0")
                yield ContractSetup(telescope, probe)

The fixture runs for every test: leave the device in a state the suite can start from (READY; a
telescope parked or not, a roof open or closed — each test first drives it where it needs it).
Simulated devices use the virtual clock (``Observatory()``, the default); the suites wait on
conditions with bounded timeouts on the module's own clock and never sleep a fixed time to
synchronise, so they pass on a real-time device and on a loaded machine alike.

What the suites check, through a proxy from the probe (as any other module would call): state
changes and their events (MotionStatusChangedEvent, MoveRaDecEvent, MoveAltAzEvent,
OffsetsRaDecEvent, FilterChangedEvent, NewImageEvent, ExposureStatusChangedEvent, roof events),
refusals with the right error class (InvalidArgumentError out of range, MoveError below the
horizon or while parked or in bad weather, DeviceBusyError while moving or exposing), abort,
stop_motion and park interrupting a motion (the caller gets AbortedError), get_* consistent after
set_*, FITS header cards, and that every motion and exposure ends within the timeout it announces.

Parameters are class attributes a subclass may override, documented on each suite: ``timeout``
(clock seconds any single wait may take, all suites), tolerances (``pointing_tolerance``,
``focus_tolerance``, ``azimuth_tolerance``), and the sizes of moves and exposures — small ones
that run to the end, long ones the suite interrupts (``long_step``, ``long_focus_move``,
``long_exposure_time``). A long motion that ends before the suite could interrupt it fails with
a message saying so: make it longer (or the device slower). A test that cannot apply to a device
is best replaced in the subclass by an override that states why.

Helpers
-------
:class:`Observatory` builds modules on one in-process network with one clock, site and in-memory
VFS and closes them afterwards; :func:`wait_for` waits for a condition on a clock, bounded
(:func:`modules_ready`: every module named is on the network and ready);
:class:`EventRecorder` is a module that records the events it hears.
"""

from nightcrew.testing.contracts import (
    CameraContract,
    ContractProbe,
    ContractSetup,
    CoverCalibratorContract,
    DeviceContract,
    DomeContract,
    FilterWheelContract,
    FocuserContract,
    RoofContract,
    RotatorContract,
    SwitchContract,
    TelescopeContract,
    WeatherStationContract,
    timed_call,
)
from nightcrew.testing.observatory import EPOCH, SITE, Observatory
from nightcrew.testing.recording import EventRecorder
from nightcrew.testing.waiting import Condition, modules_ready, wait_for

__all__ = [
    "EPOCH",
    "SITE",
    "CameraContract",
    "Condition",
    "ContractProbe",
    "ContractSetup",
    "CoverCalibratorContract",
    "DeviceContract",
    "DomeContract",
    "EventRecorder",
    "FilterWheelContract",
    "FocuserContract",
    "Observatory",
    "RoofContract",
    "RotatorContract",
    "SwitchContract",
    "TelescopeContract",
    "WeatherStationContract",
    "modules_ready",
    "timed_call",
    "wait_for",
]
