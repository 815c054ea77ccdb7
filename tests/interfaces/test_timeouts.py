"""Interfaces announce long timeouts where a call obviously takes long, and only there."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import pytest

from nightcrew.interfaces import (
    IAutoFocus,
    ICoverCalibrator,
    IData,
    IFilters,
    IFlatField,
    IModule,
    IMotion,
    IPointingRaDec,
    IRoof,
    IRotator,
    ISwitch,
    ITelescope,
    interface_methods,
    interfaces_of,
)
from nightcrew.interfaces.base import Interface
from nightcrew.timeout import DEFAULT_TIMEOUT, method_timeout

from .catalogue import declared_methods, method_id

METHODS = declared_methods()


@pytest.mark.parametrize(
    ("func", "seconds"),
    [
        (IMotion.init, 300),
        (IMotion.park, 300),
        (IPointingRaDec.move_radec, 300),
        (IRoof.open_roof, 300),
        (IFilters.set_filter, 120),
        (IData.grab_data, 3600),
        (IAutoFocus.auto_focus, 1800),
        (IFlatField.flat_field, 3600),
        (IModule.get_label, DEFAULT_TIMEOUT),
        (IMotion.get_motion_status, DEFAULT_TIMEOUT),
        (IRotator.move_position_angle, 300),
        (IRotator.move_position_angle_by, 300),
        (IRotator.move_mechanical, 300),
        (IRotator.get_position_angle, DEFAULT_TIMEOUT),
        (ICoverCalibrator.open_cover, 120),
        (ICoverCalibrator.close_cover, 120),
        (ICoverCalibrator.calibrator_on, 120),
        (ICoverCalibrator.calibrator_off, 60),
        (ICoverCalibrator.halt_cover, DEFAULT_TIMEOUT),
        (ISwitch.set_switch_value, DEFAULT_TIMEOUT),
    ],
    ids=lambda v: getattr(v, "__qualname__", str(v)),
)
def test_timeout(func: Callable[..., Any], seconds: float) -> None:
    assert method_timeout(func, {}) == seconds


def test_composed_interface_keeps_inherited_timeouts() -> None:
    methods = interface_methods(interfaces_of(ITelescope))
    assert method_timeout(methods["init"], {}) == 300
    assert method_timeout(methods["move_altaz"], {}) == 300


def test_rotator_halts_through_stop_motion() -> None:
    # Halting a rotator is IMotion's stop_motion, so a mastermind's "stop everything" reaches it.
    methods = interface_methods(interfaces_of(IRotator))
    assert methods["stop_motion"] is IMotion.stop_motion
    assert method_timeout(methods["park"], {}) == 300


@pytest.mark.parametrize("item", METHODS, ids=method_id)
def test_declared_timeouts_are_long(item: tuple[type[Interface], str, Callable[..., Any]]) -> None:
    # Declaring a timeout at or below the default would only add noise to the interface.
    seconds = method_timeout(item[2], {})
    assert seconds == DEFAULT_TIMEOUT or seconds > DEFAULT_TIMEOUT * 2
