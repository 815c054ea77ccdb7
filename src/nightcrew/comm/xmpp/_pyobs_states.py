"""The pyobs-core 2.x states a nightcrew module publishes, derived from its own events (pure).

pyobs modules and GUIs read another module's live state from a PubSub node per interface,
``pyobs:state:<module>:<Interface>:1``, whose one item is ``<state xmlns='urn:pyobs:state:<I>:1'>``
with a child per field of that interface's state dataclass (pyobs-core 2.19). A module in the
pyobs dialect publishes the states its own events already say, as it sends them:

======================================  =========  ===============================================
nightcrew event                         interface  pyobs state fields
======================================  =========  ===============================================
MotionStatusChangedEvent                IMotion    status; devices as ``[{name, status}]``; time
FilterChangedEvent                      IFilters   filter; time
ExposureStatusChangedEvent              IExposure  status; progress and exposure_time_left 0; time
======================================  =========  ===============================================

nightcrew's ``moving`` (a focuser or rotator on its way) is pyobs' ``slewing``. ``time`` is the
moment the state is published, UTC, as pyobs' ``Time`` reads it.
"""

from __future__ import annotations

from datetime import UTC, datetime
from typing import Any

from nightcrew.comm.xmpp._pyobs_values import PyobsState

__all__ = ["STATE_INTERFACES", "pyobs_state", "state_namespace", "state_node"]

#: nightcrew event → the pyobs interface whose state it tells.
STATE_INTERFACES = {
    "MotionStatusChangedEvent": "IMotion",
    "FilterChangedEvent": "IFilters",
    "ExposureStatusChangedEvent": "IExposure",
}
_MOTION_STATUS = {"moving": "slewing"}  # the only status pyobs lacks


def state_node(module: str, interface: str) -> str:
    return f"pyobs:state:{module}:{interface}:1"


def state_namespace(interface: str) -> str:
    return f"urn:pyobs:state:{interface}:1"


def pyobs_state(event: str, payload: dict[str, Any], now: datetime | None = None) -> dict[str, Any] | None:
    """The pyobs state fields event ``event`` (wire ``payload``) tells, or None if it tells none."""
    # astropy's Time reads ISO without an offset (as UTC), not with one.
    time = (now or datetime.now(UTC)).astimezone(UTC).replace(tzinfo=None).isoformat()
    if event == "MotionStatusChangedEvent":
        devices = payload.get("devices") or {}
        return {
            "status": _motion(payload["status"]),
            "devices": [PyobsState({"name": name, "status": _motion(s)}) for name, s in devices.items()],
            "time": time,
        }
    if event == "FilterChangedEvent":
        return {"filter": payload["filter_name"], "time": time}
    if event == "ExposureStatusChangedEvent":
        return {"status": payload["current"], "progress": 0.0, "exposure_time_left": 0.0, "time": time}
    return None


def _motion(status: str) -> str:
    return _MOTION_STATUS.get(status, status)
