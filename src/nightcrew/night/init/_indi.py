"""INDI devices for ``nightcrew init``: ``getProperties`` on one indiserver, each device by role.

A driver says what it is in ``DRIVER_INFO.DRIVER_INTERFACE`` (a bit mask: 1 telescope, 2 CCD,
8 focuser, 16 filter wheel, 32 dome, 128 weather, 512 dust cap, 1024 light box, 4096 rotator,
...). One device may set several bits (a CCD with a built-in wheel); it takes the first role of
:data:`_BITS` it has, so a camera stays a camera; a light box or dust cap is a ``cover``.
A DOME device is a ``dome`` (IndiDome: shutter and azimuth), or a ``roof``
(IndiRoof: opened by unparking) when its driver calls itself a roll-off or a roof in
``DRIVER_EXEC`` or ``DRIVER_NAME``: before a client connects the device, that name is all a
driver says to tell the two apart (``indi_rolloff_dome``: "RollOff Simulator").

INDI has no "that was all" message: the server forwards ``getProperties`` to its drivers, each
answers when it does. So the list is complete once every device seen has defined ``DRIVER_INFO``
and no new definition came for ``quiet`` wall seconds (bounded by ``within``). Running drivers
answer within milliseconds; the 2 s default leaves room for a busy machine.
"""

from __future__ import annotations

import asyncio
import time

from nightcrew.bridges.indi.client import IndiClient, IndiUpdate
from nightcrew.bridges.indi.protocol import IndiError
from nightcrew.errors import NightcrewError
from nightcrew.night.init._found import FoundDevice

__all__ = ["find_indi_devices"]

#: A DOME driver whose DRIVER_EXEC or DRIVER_NAME holds one of these (lower case) drives a roof.
_ROOF_WORDS = ("rolloff", "roll-off", "roll off", "roof")
_ROOF = ("roof", "nightcrew.modules.indi.IndiRoof")

#: DRIVER_INTERFACE bit → role and module class, in the order a device with several bits is judged.
_BITS: tuple[tuple[int, str, str], ...] = (
    (1, "telescope", "nightcrew.modules.indi.IndiTelescope"),
    (2, "camera", "nightcrew.modules.indi.IndiCamera"),
    (32, "dome", "nightcrew.modules.indi.IndiDome"),
    (8, "focuser", "nightcrew.modules.indi.IndiFocuser"),
    (16, "filters", "nightcrew.modules.indi.IndiFilterWheel"),
    (4096, "rotator", "nightcrew.modules.indi.IndiRotator"),
    (128, "conditions", "nightcrew.modules.indi.IndiWeather"),
    (1024, "cover", "nightcrew.modules.indi.IndiCoverCalibrator"),  # light box (flat panel)
    (512, "cover", "nightcrew.modules.indi.IndiCoverCalibrator"),  # dust cap
)


async def find_indi_devices(
    host: str, port: int = 7624, *, within: float = 15.0, quiet: float = 2.0
) -> list[FoundDevice]:
    """The devices of the indiserver at ``host:port`` that nightcrew drives.

    Raises:
        NightcrewError: The server cannot be reached, or defined no device within ``within`` s.
    """
    client = IndiClient(host, port)
    last_definition = time.monotonic()

    def on_update(update: IndiUpdate) -> None:
        nonlocal last_definition
        if update.vector is not None:
            last_definition = time.monotonic()

    client.add_listener(on_update)
    await client.open()
    try:
        try:
            await client.wait_connected(min(within, 10.0))
        except IndiError as exc:
            raise NightcrewError(f"INDI server {host}:{port}: {exc}") from None
        deadline = time.monotonic() + within
        while time.monotonic() < deadline:
            devices = {device for device, _ in client.properties}
            described = {device for device, name in client.properties if name == "DRIVER_INFO"}
            if devices and devices == described and time.monotonic() - last_definition >= quiet:
                break
            await asyncio.sleep(0.05)  # bounded by the deadline; definitions arrive meanwhile
        return _found(client, host, port)
    finally:
        await client.close()


def _found(client: IndiClient, host: str, port: int) -> list[FoundDevice]:
    found = []
    for (device, name), vector in sorted(client.properties.items()):
        if name != "DRIVER_INFO":
            continue
        try:
            interface = int(str(vector.members.get("DRIVER_INTERFACE", "0")))
        except ValueError:
            interface = 0
        kind = next(((role, cls) for bit, role, cls in _BITS if interface & bit), None)
        if kind is None:
            continue
        role, cls = kind
        named = " ".join(str(vector.members.get(key, "")) for key in ("DRIVER_EXEC", "DRIVER_NAME")).lower()
        if role == "dome" and any(word in named for word in _ROOF_WORDS):
            role, cls = _ROOF
        filters: tuple[str, ...] = ()
        names = client.properties.get((device, "FILTER_NAME"))
        if role == "filters" and names is not None:
            filters = tuple(str(value) for value in names.members.values())
        found.append(
            FoundDevice(
                role=role,
                config={"class": cls, "host": host, "port": port, "device": device},
                description=f"INDI device '{device}' on {host}:{port} (DRIVER_INTERFACE {interface})",
                filter_names=filters,
            )
        )
    if not found:
        raise NightcrewError(f"INDI server {host}:{port}: no telescope, camera, dome, focuser, ... defined")
    return found
