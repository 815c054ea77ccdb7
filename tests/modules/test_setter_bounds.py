"""Every setter of the simulated devices, called over the comm with values beyond physics.

For each method of an interface that takes a number (``set_*``, ``move_*``, ``auto_focus`` ...),
each numeric argument in turn gets each hostile value below while the others stay sensible. Every
call must end at once with a result or a nightcrew error naming the argument, never hang, crash the
module or be obeyed: a value beyond physics (1e308 s, 2**70, a 1e-320 interval) is refused.
"""

from __future__ import annotations

import enum
import inspect
import logging
import typing
from typing import Any

import pytest

from nightcrew.comm.codec import method_parameters
from nightcrew.errors import InvalidArgumentError, NightcrewError
from nightcrew.interfaces import ICamera, IExposureTime, ModuleState
from nightcrew.interfaces.base import interface_methods, interfaces_of
from nightcrew.modules import Module
from nightcrew.modules.sim import (
    SimCamera,
    SimCoverCalibrator,
    SimDome,
    SimFilterWheel,
    SimFocuser,
    SimRotator,
    SimSwitch,
    SimTelescope,
)
from nightcrew.modules.test import StandAlone
from nightcrew.testing import EventRecorder, Observatory

#: Numbers no setting means: an exposure of 10^308 s, 2^70 as an int and as a float, infinities.
BEYOND_PHYSICS: tuple[object, ...] = (1e308, -1e308, 2**70, float(2**70), -(2**70), 1e300, -1e300)
#: Numbers that are wrong for some settings only (a negative exposure, a tiny interval).
DOUBTFUL: tuple[object, ...] = (-1.0, 0.0, 1e-320, 1e6, -1e6)

DEVICES: tuple[tuple[type[Module], str, dict[str, Any]], ...] = (
    (SimCamera, "camera", {"detector": {"chip_width": 64, "chip_height": 64}}),
    (SimTelescope, "telescope", {"init_time": 0.0}),
    (SimFocuser, "focuser", {}),
    (SimFilterWheel, "filters", {"filters": ["V", "R"], "filter_name": "V"}),
    (SimDome, "dome", {}),
    (SimRotator, "rotator", {}),
    (SimSwitch, "switch", {"switches": [{"name": "Heater", "max_value": 100, "step": 1}]}),
    (SimCoverCalibrator, "flats", {}),
    (StandAlone, "standalone", {"interval": 10.0}),  # a module with a changeable config option
)


async def numeric_setters(module: Module) -> list[tuple[str, list[Any], list[int]]]:
    """(method, sensible arguments, indexes of its numeric parameters) for every method taking a
    number, and ``set_config_value`` for every option that can be changed."""
    found = [
        ("set_config_value", [name, 1.0], [1])
        for name, (_, settable, _) in (await module.get_config_caps()).items()
        if settable
    ]
    for name, declaration in sorted(interface_methods(interfaces_of(type(module))).items()):
        if name.startswith(("get_", "list_", "is_")):
            continue
        params, _ = method_parameters(declaration)
        kinds = [_base(p.hint) for p in params]
        numeric = [i for i, kind in enumerate(kinds) if kind in (int, float)]
        if numeric:
            found.append(
                (name, [_sensible(kind, p.default) for kind, p in zip(kinds, params, strict=True)], numeric)
            )
    return found


def _base(hint: Any) -> Any:
    while typing.get_origin(hint) is typing.Annotated:
        hint = typing.get_args(hint)[0]
    members = [m for m in typing.get_args(hint) if m is not type(None)] if typing.get_origin(hint) else []
    return members[0] if len(members) == 1 else hint


def _sensible(kind: Any, default: Any) -> Any:
    if default is not inspect.Parameter.empty:
        return default
    if isinstance(kind, type) and issubclass(kind, enum.Enum):
        return next(iter(kind)).value
    return {float: 1.0, int: 1, bool: True, str: "V"}.get(kind)


async def test_every_numeric_setter_refuses_values_beyond_physics(
    observatory: Observatory, caplog: pytest.LogCaptureFixture
) -> None:
    caplog.set_level(logging.WARNING)
    probe = await observatory.start(EventRecorder, "probe", types=[])
    modules = [await observatory.start(cls, name, **options) for cls, name, options in DEVICES]
    outcomes: dict[str, int] = {}
    obeyed: list[str] = []
    for module in modules:
        for method, sensible, numeric in await numeric_setters(module):
            for index in numeric:
                for value in BEYOND_PHYSICS + DOUBTFUL:
                    args = list(sensible)
                    args[index] = value
                    call = f"{module.name}.{method}({', '.join(map(repr, args))})"
                    try:
                        # A call that never ends runs into the timeout the comm waits (clock time).
                        await probe.comm.execute(module.name, method, args)
                        outcome = "obeyed"
                        if value in BEYOND_PHYSICS:
                            obeyed.append(call)
                    except NightcrewError as exc:
                        outcome = type(exc).__name__
                    outcomes[outcome] = outcomes.get(outcome, 0) + 1
            assert await probe.comm.execute(module.name, "get_state", []) != ModuleState.ERROR.value, method
    print(f"{sum(outcomes.values())} hostile setter calls: {outcomes}")
    assert sum(outcomes.values()) >= 300, outcomes  # the closing note of issue 26 counts them
    assert not obeyed, "\n".join(obeyed)
    assert "TimeoutError" not in outcomes, outcomes
    assert not [r for r in caplog.records if r.exc_info], "a call ended in a traceback"


async def test_an_exposure_time_is_refused_beyond_the_declared_and_the_configured_maximum(
    observatory: Observatory,
) -> None:
    probe = await observatory.start(EventRecorder, "probe", types=[])
    await observatory.start(
        SimCamera, "camera", detector={"chip_width": 32, "chip_height": 32}, max_exposure_time=10
    )
    camera = await probe.comm.proxy("camera", ICamera)
    assert isinstance(camera, IExposureTime)
    with pytest.raises(
        InvalidArgumentError,
        match=r"argument 'exposure_time': 1e\+308 is out of range \(must be <= 86400.0 s\)",
    ):
        await camera.set_exposure_time(1e308)
    with pytest.raises(
        InvalidArgumentError, match=r"11.0 s is out of range for camera: 0..10 s \(the maximum is max_"
    ):
        await camera.set_exposure_time(11.0)
    await camera.set_exposure_time(10.0)
    assert await camera.get_exposure_time() == 10.0
    assert (await camera.grab_data()).endswith(".fits")  # the refusals left nothing behind
