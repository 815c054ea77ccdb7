"""INDI properties as the server side holds them: vectors of members, their XML, and client requests.

Pure and synchronous (no sockets, no clock): :class:`Property` holds one property (a number, switch,
text, light or BLOB vector of a device) with its state; :func:`def_element` and
:func:`set_element` write the ``def*Vector``/``set*Vector`` a client receives, :func:`blob_message`
the ``setBLOBVector`` carrying a file, and :func:`parse_new` checks a client's ``new*Vector``
against the property it names, returning the values or raising one InvalidArgumentError that
names the device, the property and what is wrong (unknown member, read-only property, a number out
of range or unreadable, a switch rule broken). Element and attribute names follow the INDI
protocol 1.7.
"""

from __future__ import annotations

import base64
import math
import xml.etree.ElementTree as ET
from dataclasses import dataclass, field
from datetime import UTC, datetime
from enum import StrEnum
from typing import Generic, TypeVar
from xml.sax.saxutils import quoteattr

from nightcrew.bridges.indi.protocol import PropertyState, format_number, parse_number
from nightcrew.errors import InvalidArgumentError

__all__ = [
    "BlobMember",
    "LightMember",
    "NumberMember",
    "Permission",
    "Property",
    "PropertyState",
    "SwitchMember",
    "SwitchRule",
    "TextMember",
    "blob_message",
    "def_element",
    "indi_timestamp",
    "message_element",
    "parse_new",
    "set_element",
]


class Permission(StrEnum):
    READ_ONLY = "ro"
    WRITE_ONLY = "wo"
    READ_WRITE = "rw"


class SwitchRule(StrEnum):
    ONE_OF_MANY = "OneOfMany"
    AT_MOST_ONE = "AtMostOne"
    ANY_OF_MANY = "AnyOfMany"


@dataclass
class NumberMember:
    """A number member; ``minimum < maximum`` bounds what clients may set (equal: unbounded)."""

    name: str
    label: str
    value: float = 0.0
    minimum: float = 0.0
    maximum: float = 0.0
    step: float = 0.0
    format: str = "%g"


@dataclass
class SwitchMember:
    name: str
    label: str
    on: bool = False


@dataclass
class TextMember:
    name: str
    label: str
    value: str = ""


@dataclass
class LightMember:
    name: str
    label: str
    state: PropertyState = PropertyState.IDLE


@dataclass
class BlobMember:
    """A BLOB member; its data travels only in :func:`blob_message`, never stored here."""

    name: str
    label: str


M = TypeVar("M", NumberMember, SwitchMember, TextMember, LightMember, BlobMember)

_KINDS: dict[type, str] = {
    NumberMember: "Number",
    SwitchMember: "Switch",
    TextMember: "Text",
    LightMember: "Light",
    BlobMember: "BLOB",
}


@dataclass(eq=False)
class Property(Generic[M]):
    """One INDI property of a device: a named vector of members of one kind."""

    device: str
    name: str
    label: str
    group: str
    members: list[M]
    perm: Permission = Permission.READ_WRITE
    state: PropertyState = PropertyState.IDLE
    rule: SwitchRule = SwitchRule.ONE_OF_MANY  # switches only
    timeout: float = 60.0  # seconds a client may wait for a change it asked for
    message: str = ""  # sent once with the next definition or update, then cleared
    by_name: dict[str, M] = field(init=False, repr=False)

    def __post_init__(self) -> None:
        if not self.members:
            raise ValueError(f"{self.device}.{self.name} needs at least one member")
        kinds = {type(m) for m in self.members}
        if len(kinds) != 1:
            raise ValueError(f"{self.device}.{self.name} mixes member kinds")
        self.by_name = {m.name: m for m in self.members}

    @property
    def kind(self) -> str:
        """Number, Switch, Text, Light or BLOB (as in the element names)."""
        return _KINDS[type(self.members[0])]

    @property
    def where(self) -> str:
        """``device.property``, for messages."""
        return f"{self.device}.{self.name}"

    def snapshot(self) -> tuple[object, ...]:
        """What a client sees of the vector, to tell whether an update needs sending."""
        return (self.state, *(_member_value(m) for m in self.members))


def indi_timestamp(when: datetime | None = None) -> str:
    """An INDI timestamp: UTC, ISO 8601 without a zone, to the second."""
    moment = (when or datetime.now(UTC)).astimezone(UTC)
    return moment.strftime("%Y-%m-%dT%H:%M:%S")


def _member_value(member: NumberMember | SwitchMember | TextMember | LightMember | BlobMember) -> object:
    if isinstance(member, NumberMember):
        return member.value
    if isinstance(member, SwitchMember):
        return member.on
    if isinstance(member, TextMember):
        return member.value
    if isinstance(member, LightMember):
        return member.state
    return None


def _number_text(value: float) -> str:
    return format_number(value) if math.isfinite(value) else "0"


def _vector_element(tag: str, vector: Property[M], timestamp: str) -> ET.Element:
    element = ET.Element(tag, device=vector.device, name=vector.name, state=vector.state.value)
    element.set("timestamp", timestamp)
    if vector.kind != "Light" and vector.perm is not Permission.READ_ONLY:
        element.set("timeout", f"{vector.timeout:g}")
    if vector.message:
        element.set("message", vector.message)
    return element


def def_element(vector: Property[M], timestamp: str | None = None) -> ET.Element:
    """The ``def<Kind>Vector`` defining ``vector`` to a client."""
    element = _vector_element(f"def{vector.kind}Vector", vector, timestamp or indi_timestamp())
    element.set("label", vector.label)
    element.set("group", vector.group)
    if vector.kind != "Light":
        element.set("perm", vector.perm.value)
    if vector.kind == "Switch":
        element.set("rule", vector.rule.value)
    for member in vector.members:
        child = ET.SubElement(element, f"def{vector.kind}", name=member.name, label=member.label)
        if isinstance(member, NumberMember):
            child.set("format", member.format)
            child.set("min", _number_text(member.minimum))
            child.set("max", _number_text(member.maximum))
            child.set("step", _number_text(member.step))
            child.text = _number_text(member.value)
        elif isinstance(member, SwitchMember):
            child.text = "On" if member.on else "Off"
        elif isinstance(member, TextMember):
            child.text = member.value
        elif isinstance(member, LightMember):
            child.text = member.state.value
    vector.message = ""
    return element


def set_element(vector: Property[M], timestamp: str | None = None) -> ET.Element:
    """The ``set<Kind>Vector`` with the current values and state (a BLOB vector: its state only)."""
    element = _vector_element(f"set{vector.kind}Vector", vector, timestamp or indi_timestamp())
    if vector.kind != "BLOB":
        for member in vector.members:
            child = ET.SubElement(element, f"one{vector.kind}", name=member.name)
            value = _member_value(member)
            if isinstance(member, NumberMember):
                child.text = _number_text(member.value)
            elif isinstance(member, SwitchMember):
                child.text = "On" if member.on else "Off"
            else:
                child.text = str(value)
    vector.message = ""
    return element


def blob_message(
    vector: Property[BlobMember], member: str, data: bytes, fmt: str, timestamp: str | None = None
) -> bytes:
    """The ``setBLOBVector`` carrying ``data`` (e.g. a FITS file, ``fmt=".fits"``) in ``member``.

    Written directly as bytes: an 8-MB frame is 11 MB of base64, which an element tree would copy
    several times over.
    """
    if member not in vector.by_name:
        raise ValueError(f"{vector.where} has no member {member}")
    head = (
        f"<setBLOBVector device={quoteattr(vector.device)} name={quoteattr(vector.name)} "
        f"state={quoteattr(vector.state.value)} timestamp={quoteattr(timestamp or indi_timestamp())}>"
        f"<oneBLOB name={quoteattr(member)} size={quoteattr(str(len(data)))} format={quoteattr(fmt)}>"
    )
    return head.encode() + base64.b64encode(data) + b"</oneBLOB></setBLOBVector>\n"


def message_element(device: str | None, text: str, timestamp: str | None = None) -> ET.Element:
    """A ``message`` for the client's log (of a device, or of the server when None)."""
    element = ET.Element("message", timestamp=timestamp or indi_timestamp(), message=text)
    if device is not None:
        element.set("device", device)
    return element


_NEW_TAGS = {f"new{kind}Vector": kind for kind in ("Number", "Switch", "Text", "BLOB")}


def parse_new(element: ET.Element, vector: Property[M]) -> dict[str, float | bool | str]:
    """The member values a client's ``new*Vector`` asks ``vector`` to take.

    Only the members the client names are returned (a switch vector with rule OneOfMany: all of
    them, the one switched on and the others off). Nothing in ``vector`` changes.

    Raises:
        InvalidArgumentError: naming ``device.property`` and what is wrong.
    """
    kind = _NEW_TAGS.get(element.tag)
    where = vector.where
    if kind is None:
        raise InvalidArgumentError(f"{where}: {element.tag} is not a request a client may send")
    if kind != vector.kind:
        raise InvalidArgumentError(f"{where} is a {vector.kind} property, not a {kind} one")
    if vector.perm is Permission.READ_ONLY:
        raise InvalidArgumentError(f"{where} is read-only")
    values: dict[str, float | bool | str] = {}
    for child in element:
        name = child.get("name")
        if child.tag != f"one{kind}" or name is None:
            raise InvalidArgumentError(f"{where}: expected <one{kind} name=...>, got <{child.tag}>")
        member = vector.by_name.get(name)
        if member is None:
            known = ", ".join(vector.by_name)
            raise InvalidArgumentError(f"{where} has no member {name!r} (members: {known})")
        values[name] = _member_request(where, member, (child.text or "").strip())
    if not values:
        raise InvalidArgumentError(f"{where}: the request names no member")
    if isinstance(vector.members[0], SwitchMember):
        return _apply_rule(where, vector.rule, [m.name for m in vector.members], values)
    return values


def _member_request(
    where: str, member: NumberMember | SwitchMember | TextMember | LightMember | BlobMember, text: str
) -> float | bool | str:
    if isinstance(member, NumberMember):
        try:
            number = parse_number(text)
        except ValueError:
            raise InvalidArgumentError(f"{where}.{member.name}: not a number: {text!r}") from None
        if not math.isfinite(number):
            raise InvalidArgumentError(f"{where}.{member.name}: not a finite number: {text!r}")
        if member.minimum < member.maximum and not member.minimum <= number <= member.maximum:
            raise InvalidArgumentError(
                f"{where}.{member.name}={number:g} is outside {member.minimum:g}..{member.maximum:g}"
            )
        return number
    if isinstance(member, SwitchMember):
        if text not in ("On", "Off"):
            raise InvalidArgumentError(f"{where}.{member.name}: a switch is On or Off, got {text!r}")
        return text == "On"
    if isinstance(member, TextMember):
        return text
    raise InvalidArgumentError(f"{where}.{member.name} cannot be set by a client")


def _apply_rule(
    where: str, rule: SwitchRule, names: list[str], values: dict[str, float | bool | str]
) -> dict[str, float | bool | str]:
    on = [name for name, value in values.items() if value is True]
    if rule is SwitchRule.ANY_OF_MANY:
        return values
    if len(on) > 1:
        raise InvalidArgumentError(f"{where}: only one switch may be On ({rule.value}), got {', '.join(on)}")
    if rule is SwitchRule.ONE_OF_MANY:
        if not on:
            raise InvalidArgumentError(f"{where}: one switch must be On ({rule.value})")
        return {name: name == on[0] for name in names}
    return values
