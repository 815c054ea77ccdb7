"""The INDI XML protocol as values: property vectors, what a server sends, what a client sends.

Pure: parsing takes an ``xml.etree`` element and returns a message (or raises
:class:`IndiProtocolError` naming the device and property); building returns bytes. No sockets.

Members hold Python values by kind: Number → float, Switch → bool (On), Text → str,
Light → :class:`PropertyState`, BLOB → :class:`Blob` (decoded, decompressed for ``.z`` formats,
its length checked against the announced ``size``).
"""

from __future__ import annotations

import math
import zlib
from collections.abc import Mapping
from dataclasses import dataclass, field
from enum import StrEnum
from xml.etree.ElementTree import Element
from xml.sax.saxutils import escape, quoteattr

import pybase64

__all__ = [
    "Blob",
    "DefVector",
    "DelProperty",
    "IndiError",
    "IndiMessage",
    "IndiProtocolError",
    "MemberValue",
    "PropertyState",
    "ServerMessage",
    "SetVector",
    "Vector",
    "VectorKind",
    "enable_blob",
    "format_number",
    "get_properties",
    "new_vector",
    "parse_element",
    "parse_number",
]


class IndiError(Exception):
    """Base of the INDI bridge's errors; names the device and property it concerns.

    Not a NightcrewError on purpose: the device bases translate it into the error of the action
    that failed (MoveError, GrabImageError ...), keeping this message.
    """

    def __init__(self, message: str, *, device: str = "", name: str = "") -> None:
        where = ".".join(part for part in (device, name) if part)
        super().__init__(f"{where}: {message}" if where else message)
        self.device = device
        self.name = name


class IndiProtocolError(IndiError):
    """The server sent something that is not INDI: malformed or truncated XML, bad values, a BLOB
    whose length differs from the one announced."""


class PropertyState(StrEnum):
    IDLE = "Idle"
    OK = "Ok"
    BUSY = "Busy"
    ALERT = "Alert"


class VectorKind(StrEnum):
    NUMBER = "Number"
    SWITCH = "Switch"
    TEXT = "Text"
    LIGHT = "Light"
    BLOB = "BLOB"


@dataclass(frozen=True)
class Blob:
    """A BLOB's bytes (decoded; decompressed when the format ended in ``.z``) and format (``.fits``)."""

    data: bytes
    format: str


MemberValue = float | bool | str | PropertyState | Blob


@dataclass
class Vector:
    """A property vector as the client knows it; ``generation`` counts the updates received,
    ``busy_generation`` is the last of them that reported Busy."""

    device: str
    name: str
    kind: VectorKind
    state: PropertyState
    members: dict[str, MemberValue]
    label: str = ""
    group: str = ""
    perm: str = "ro"
    rule: str = ""
    timeout: float = 0.0
    message: str = ""
    generation: int = 0
    busy_generation: int = 0
    limits: dict[str, tuple[float, float, float]] = field(default_factory=dict)

    @property
    def key(self) -> tuple[str, str]:
        return self.device, self.name

    def number(self, member: str) -> float:
        value = self._member(member)
        if not isinstance(value, float):
            raise IndiProtocolError(f"member {member} is not a number", device=self.device, name=self.name)
        return value

    def text(self, member: str) -> str:
        value = self._member(member)
        if not isinstance(value, str):
            raise IndiProtocolError(f"member {member} is not text", device=self.device, name=self.name)
        return str(value)

    def switch(self, member: str) -> bool:
        value = self._member(member)
        if not isinstance(value, bool):
            raise IndiProtocolError(f"member {member} is not a switch", device=self.device, name=self.name)
        return value

    def on_switches(self) -> list[str]:
        """Names of the switches that are On."""
        return [name for name, value in self.members.items() if value is True]

    def _member(self, member: str) -> MemberValue:
        try:
            return self.members[member]
        except KeyError:
            have = ", ".join(self.members)
            raise IndiProtocolError(
                f"has no member {member} (it has: {have})", device=self.device, name=self.name
            ) from None


@dataclass(frozen=True)
class DefVector:
    vector: Vector


@dataclass(frozen=True)
class SetVector:
    device: str
    name: str
    kind: VectorKind
    state: PropertyState | None
    members: dict[str, MemberValue]
    timeout: float | None
    message: str


@dataclass(frozen=True)
class DelProperty:
    device: str
    name: str  # "" deletes the whole device
    message: str


@dataclass(frozen=True)
class IndiMessage:
    device: str  # "" for a message of the server itself
    message: str


ServerMessage = DefVector | SetVector | DelProperty | IndiMessage

_KINDS = {kind.value: kind for kind in VectorKind}


def parse_number(text: str) -> float:
    """An INDI number: decimal, or sexagesimal ``-12:30:15.5`` / ``12 30 15``."""
    text = text.strip()
    try:
        return float(text)
    except ValueError:
        pass
    parts = text.replace(":", " ").replace(";", " ").split()
    if not 1 <= len(parts) <= 3:
        raise ValueError(f"not a number: {text!r}")
    sign = -1.0 if parts[0].startswith("-") else 1.0
    value = 0.0
    for scale, part in zip((1.0, 60.0, 3600.0), parts, strict=False):
        try:
            value += abs(float(part)) / scale
        except ValueError:
            raise ValueError(f"not a number: {text!r}") from None
    return sign * value


def format_number(value: float) -> str:
    """A number as INDI text (repr keeps every digit)."""
    if not math.isfinite(value):
        raise ValueError(f"INDI numbers must be finite, got {value}")
    return repr(float(value))


def _state(text: str | None, device: str, name: str) -> PropertyState | None:
    if text is None:
        return None
    try:
        return PropertyState(text.strip())
    except ValueError:
        raise IndiProtocolError(f"unknown state {text!r}", device=device, name=name) from None


def _member_value(
    kind: VectorKind, member: Element, device: str, name: str, payloads: Mapping[Element, bytes]
) -> MemberValue:
    text = member.text or ""
    member_name = member.get("name", "")
    try:
        if kind is VectorKind.NUMBER:
            return parse_number(text)
        if kind is VectorKind.SWITCH:
            if text.strip() not in ("On", "Off"):
                raise ValueError(f"switch value must be On or Off, got {text.strip()!r}")
            return text.strip() == "On"
        if kind is VectorKind.LIGHT:
            return PropertyState(text.strip())
        if kind is VectorKind.BLOB:
            return _blob(member, payloads.get(member), text, device, name)
        return text.strip()  # libindi wraps values in newlines and indentation
    except ValueError as exc:
        raise IndiProtocolError(f"member {member_name}: {exc}", device=device, name=name) from None


def _blob(member: Element, decoded: bytes | None, text: str, device: str, name: str) -> Blob:
    """``decoded``: the bytes the stream parser already decoded from the base64 text, if it did."""
    member_name = member.get("name", "")
    fmt = member.get("format", "")
    try:
        announced = int(member.get("size", "0"))
    except ValueError:
        raise IndiProtocolError(
            f"BLOB {member_name}: size is not an integer", device=device, name=name
        ) from None
    try:
        data = pybase64.b64decode(text) if decoded is None else decoded  # ~40x faster than binascii
        if fmt.endswith(".z"):
            data, fmt = zlib.decompress(data), fmt[:-2]
    except (ValueError, zlib.error) as exc:  # binascii.Error is a ValueError
        raise IndiProtocolError(
            f"BLOB {member_name} cannot be decoded: {exc}", device=device, name=name
        ) from None
    if len(data) != announced:
        which = "larger" if len(data) > announced else "smaller"
        raise IndiProtocolError(
            f"BLOB {member_name} holds {len(data)} bytes, {which} than the {announced} announced",
            device=device,
            name=name,
        )
    return Blob(data, fmt)


def _members(
    element: Element,
    prefix: str,
    kind: VectorKind,
    device: str,
    name: str,
    payloads: Mapping[Element, bytes],
) -> dict[str, MemberValue]:
    members: dict[str, MemberValue] = {}
    tag = f"{'def' if prefix == 'def' else 'one'}{kind.value}"
    for member in element:
        if member.tag != tag:
            raise IndiProtocolError(f"unexpected <{member.tag}> in <{element.tag}>", device=device, name=name)
        member_name = member.get("name")
        if not member_name:
            raise IndiProtocolError(f"<{member.tag}> without a name", device=device, name=name)
        if kind is VectorKind.BLOB and prefix == "def":
            members[member_name] = Blob(b"", "")
        else:
            members[member_name] = _member_value(kind, member, device, name, payloads)
    return members


def _timeout(text: str | None, device: str, name: str) -> float | None:
    if text is None:
        return None
    try:
        return float(text)
    except ValueError:
        raise IndiProtocolError(f"timeout {text!r} is not a number", device=device, name=name) from None


def parse_element(element: Element, payloads: Mapping[Element, bytes] | None = None) -> ServerMessage | None:
    """The message a top-level element from a server carries; None for what a client ignores
    (another client's new*Vector, enableBLOB, getProperties snooping). ``payloads`` holds the
    decoded bytes of ``oneBLOB`` elements whose base64 text the stream parser kept out of the tree."""
    tag = element.tag
    device = element.get("device", "")
    name = element.get("name", "")
    if tag == "message":
        return IndiMessage(device, element.get("message", ""))
    if tag == "delProperty":
        return DelProperty(device, name, element.get("message", ""))
    for prefix in ("def", "set"):
        if tag.startswith(prefix) and tag.endswith("Vector") and tag[len(prefix) : -6] in _KINDS:
            kind = _KINDS[tag[len(prefix) : -6]]
            if not device or not name:
                raise IndiProtocolError(f"<{tag}> without device or name", device=device, name=name)
            state = _state(element.get("state"), device, name)
            members = _members(element, prefix, kind, device, name, payloads or {})
            timeout = _timeout(element.get("timeout"), device, name)
            message = element.get("message", "")
            if prefix == "set":
                return SetVector(device, name, kind, state, members, timeout, message)
            vector = Vector(
                device=device,
                name=name,
                kind=kind,
                state=state or PropertyState.IDLE,
                members=members,
                label=element.get("label", name),
                group=element.get("group", ""),
                perm=element.get("perm", "ro"),
                rule=element.get("rule", ""),
                timeout=timeout or 0.0,
                message=message,
                limits=_limits(element) if kind is VectorKind.NUMBER else {},
            )
            return DefVector(vector)
    return None


def _limits(element: Element) -> dict[str, tuple[float, float, float]]:
    limits = {}
    for member in element:
        try:
            limits[member.get("name", "")] = (
                parse_number(member.get("min", "0")),
                parse_number(member.get("max", "0")),
                parse_number(member.get("step", "0")),
            )
        except ValueError:
            continue  # limits are advisory; the value itself was checked
    return limits


def _attributes(**attributes: str | None) -> str:
    return "".join(f" {key}={quoteattr(value)}" for key, value in attributes.items() if value is not None)


def get_properties(device: str | None = None, name: str | None = None) -> bytes:
    """``<getProperties>`` for everything, one device, or one property."""
    return f'<getProperties version="1.7"{_attributes(device=device, name=name)}/>\n'.encode()


def enable_blob(device: str, mode: str = "Also", name: str | None = None) -> bytes:
    """``<enableBLOB>``: Never, Also (BLOBs with everything else) or Only."""
    if mode not in ("Never", "Also", "Only"):
        raise ValueError(f"enableBLOB mode must be Never, Also or Only, got {mode!r}")
    return f"<enableBLOB{_attributes(device=device, name=name)}>{mode}</enableBLOB>\n".encode()


def new_vector(device: str, name: str, kind: VectorKind, members: dict[str, float | bool | str]) -> bytes:
    """``<new*Vector>`` setting ``members`` (numbers, switches as bools, texts)."""
    if kind in (VectorKind.LIGHT, VectorKind.BLOB):
        raise ValueError(f"a client cannot send {kind.value} vectors here")
    parts = [f"<new{kind.value}Vector{_attributes(device=device, name=name)}>"]
    for member, value in members.items():
        if kind is VectorKind.NUMBER:
            if isinstance(value, bool) or not isinstance(value, int | float):
                raise ValueError(f"{device}.{name}.{member}: expected a number, got {value!r}")
            text = format_number(float(value))
        elif kind is VectorKind.SWITCH:
            text = "On" if value is True else "Off"
        else:
            text = escape(str(value))
        parts.append(f"<one{kind.value}{_attributes(name=member)}>{text}</one{kind.value}>")
    parts.append(f"</new{kind.value}Vector>\n")
    return "".join(parts).encode()
