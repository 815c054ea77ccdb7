"""The interface catalogue: every interface is registered, exported and composed as documented."""

from __future__ import annotations

import inspect

import pytest

import nightcrew.interfaces as interfaces_package
from nightcrew.interfaces import (
    IAbortable,
    ICamera,
    IData,
    IDome,
    IExposure,
    IMotion,
    IPointingAltAz,
    IPointingRaDec,
    IReady,
    IRoof,
    IRotator,
    ITelescope,
    interface_by_name,
    interfaces_of,
)
from nightcrew.interfaces.base import Interface

from .catalogue import ALL_INTERFACES


def test_catalogue_is_not_empty() -> None:
    # Guards the walk itself: an empty catalogue would make every per-interface test vacuous.
    assert len(ALL_INTERFACES) >= 40


@pytest.mark.parametrize("iface", ALL_INTERFACES, ids=lambda cls: cls.__name__)
def test_interface_is_registered_by_name(iface: type[Interface]) -> None:
    assert interface_by_name(iface.__name__) is iface


@pytest.mark.parametrize("iface", ALL_INTERFACES, ids=lambda cls: cls.__name__)
def test_interface_is_exported(iface: type[Interface]) -> None:
    assert iface.__name__ in interfaces_package.__all__
    assert getattr(interfaces_package, iface.__name__) is iface


@pytest.mark.parametrize("iface", ALL_INTERFACES, ids=lambda cls: cls.__name__)
def test_interface_is_abstract_and_documented(iface: type[Interface]) -> None:
    assert inspect.isabstract(iface), "an interface without abstract methods offers nothing"
    assert iface.__doc__ and iface.__doc__.strip()
    assert iface.__name__.startswith("I")


def test_all_names_exist_once() -> None:
    names = interfaces_package.__all__
    assert len(names) == len(set(names))
    for name in names:
        assert hasattr(interfaces_package, name), name


def test_unknown_name_is_none() -> None:
    assert interface_by_name("INoSuchThing") is None


def test_duplicate_interface_name_is_refused() -> None:
    with pytest.raises(TypeError, match="interface name IMotion is already taken"):
        type("IMotion", (Interface,), {})


@pytest.mark.parametrize(
    ("iface", "parts"),
    [
        (IMotion, {IReady}),
        (ITelescope, {IMotion, IReady, IPointingRaDec, IPointingAltAz}),
        (ICamera, {IData, IAbortable, IExposure}),
        (IDome, {IRoof, IMotion, IReady}),
        # A rotator is halted, initialised and parked like every moving device.
        (IRotator, {IMotion, IReady}),
    ],
    ids=lambda v: getattr(v, "__name__", ""),
)
def test_composition(iface: type[Interface], parts: set[type[Interface]]) -> None:
    assert parts <= set(interfaces_of(iface))
