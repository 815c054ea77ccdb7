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

__all__ = ["BAD_REQUEST", "Check", "Current", "Outcome", "calls", "common_checks", "ids"]

CLIENT_ID, TRANSACTION_ID, BAD_VALUE = "123456", "67890", "asduio6fghZZ"
_OK = frozenset({200})
BAD_REQUEST = frozenset({400})
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


def ids(client: str = "ClientID", transaction: str = "ClientTransactionID") -> tuple[tuple[str, Value], ...]:
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
        Check(f"{label}: good casing", method, path, ids() + params, **expect),
        Check(
            f"{label}: extra parameter",
            method,
            path,
            (*ids(), ("ExtraParameter", "ExtraValue"), *params),
            **expect,
        ),
        Check(f"{label}: clientid lower case", method, path, ids(client="clientid") + params, **expect),
        Check(
            f"{label}: clienttransactionid lower case",
            method,
            path,
            ids(transaction="clienttransactionid") + params,
            miscased_transaction=method == "PUT",
            **expect,
        ),
    ]
    wait = {"wait_while": expect["wait_while"]} if "wait_while" in expect else {}
    for index, (name, value) in enumerate(params):
        others = params[:index] + params[index + 1 :]
        inverted = (*others[:index], (_invert(name), value), *others[index:])
        casing = BAD_REQUEST if method == "PUT" else _OK
        checks.append(
            Check(f"{label}: {name} mis-cased", method, path, ids() + inverted, statuses=casing, **wait)
        )
        if bad_values is None or name in bad_values:
            worse = (*others[:index], (name, BAD_VALUE), *others[index:])
            checks.append(
                Check(
                    f"{label}: {name} meaningless",
                    method,
                    path,
                    ids() + worse,
                    statuses=BAD_REQUEST,
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
        Check("GET description: /apx/ (any answer)", "GET", f"/apx/v1/{other}", ids(), statuses=_ANY),
        Check("GET description: /api/1/ (any answer)", "GET", f"/api/1/{other}", ids(), statuses=_ANY),
        Check("GET description: /api/V1/ (any answer)", "GET", f"/api/V1/{other}", ids(), statuses=_ANY),
        Check("GET description: /api/v2/ (any answer)", "GET", f"/api/v2/{other}", ids(), statuses=_ANY),
        Check(
            "POST connected (any answer)",
            "POST",
            f"{base}/connected",
            (*ids(), ("Connected", "True")),
            statuses=_ANY,
        ),
        Check("DELETE connected (any answer)", "DELETE", f"{base}/connected", ids(), statuses=_ANY),
        Check(
            "upper-case device type",
            "GET",
            f"/api/v1/{device_type.upper()}/{number}/description",
            ids(),
            statuses=_4XX,
        ),
        Check("unknown device type", "GET", "/api/v1/baddevicetype/0/description", ids(), statuses=_4XX),
        Check("device number -1", "GET", f"/api/v1/{device_type}/-1/description", ids(), statuses=_4XX),
        Check("device number 99999", "GET", f"/api/v1/{device_type}/99999/description", ids(), statuses=_4XX),
        Check("device number A", "GET", f"/api/v1/{device_type}/A/description", ids(), statuses=_4XX),
        Check("unknown member descrip", "GET", f"{base}/descrip", ids(), statuses=_4XX),
        Check("upper-case member", "GET", f"{base}/DESCRIPTION", ids(), statuses=_4XX),
    ]
    checks += calls(base, "GET", "Connected", bad_ids=True)
    for value in ("", "123456", "asdqwe"):
        params = (*ids(), ("Connected", value))
        checks.append(
            Check(
                f"PUT Connected={value!r}",
                "PUT",
                f"{base}/connected",
                params,
                statuses=BAD_REQUEST,
                invalid_value_ok=True,
            )
        )
    checks += calls(base, "PUT", "Connected", (("Connected", "True"),), bad_values=(), bad_ids=True)
    # The Alpaca API: a PUT's parameters are in its form; one in the query string is not there.
    in_query = (("Connected", "True"),)
    checks.append(
        Check(
            "PUT Connected in the query string",
            "PUT",
            f"{base}/connected",
            ids(),
            BAD_REQUEST,
            query=in_query,
        )
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
            ids() + unknown,
            errors=frozenset({ACTION_NOT_IMPLEMENTED}),
        )
    )
    if interface_version >= PLATFORM7[device_type]:
        checks += calls(base, "GET", "DeviceState", device_state=True)
        checks += calls(base, "PUT", "Disconnect", wait_while=("Connecting", True))
        checks += calls(base, "PUT", "Connect", wait_while=("Connecting", True))
        checks += calls(base, "GET", "Connecting")
    return checks
