"""Devices found on Alpaca and INDI servers, and the module names they get by role.

Pure: what discovery found goes in, module names come out. A role with one device is named after
the role (``camera``); a role with several numbers them in the order found (``camera1``,
``camera2``), so the robotic modules' defaults (``camera``, ``telescope``, ``roof``) fit the usual
observatory without edits.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass, field
from typing import Any

__all__ = ["ROLES", "FoundDevice", "name_by_role"]

#: The roles init knows, in the order their files are written and listed.
ROLES = (
    "telescope",
    "camera",
    "roof",
    "dome",
    "focuser",
    "filters",
    "rotator",
    "safetymonitor",
    "conditions",
    "cover",
    "switch",
)


@dataclass(frozen=True)
class FoundDevice:
    """One device a server offers, as the module driving it.

    Args:
        role: One of :data:`ROLES`.
        config: The module's class and how to reach the device (server, device number or name).
        description: One line saying what and where it is (written into the file's header).
        filter_names: A filter wheel's filter names, when it told them.
    """

    role: str
    config: dict[str, Any]
    description: str
    filter_names: tuple[str, ...] = field(default=())

    def __post_init__(self) -> None:
        if self.role not in ROLES:
            raise ValueError(f"unknown role {self.role!r}; known: {', '.join(ROLES)}")


def name_by_role(devices: Iterable[FoundDevice]) -> dict[str, FoundDevice]:
    """Module name → device, in :data:`ROLES` order: the role alone, or numbered where it repeats."""
    by_role: dict[str, list[FoundDevice]] = {role: [] for role in ROLES}
    for device in devices:
        by_role[device.role].append(device)
    named: dict[str, FoundDevice] = {}
    for role, found in by_role.items():
        if len(found) == 1:
            named[role] = found[0]
        else:
            for number, device in enumerate(found, start=1):
                named[f"{role}{number}"] = device
    return named
