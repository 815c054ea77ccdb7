"""pyobs-core 2.x's value vocabulary (``urn:pyobs:rpc:1``) ↔ nightcrew wire values.

pyobs wraps every XML-RPC ``<value>`` in ``<value xmlns='urn:pyobs:rpc:1'>`` holding its own
elements (learned from pyobs-core 2.19 on the wire; see docs/pyobs.md):

=================  ==============================================================
wire value         pyobs element
=================  ==============================================================
None               ``<nil/>``
bool               ``<boolean>true|false</boolean>``
int / float / str  ``<int>``, ``<double>``, ``<string>``
list               ``<items><item>…</item>…</items>`` (``<tuple>`` is read as a list)
dict               ``<dict><entry><key>…</key><val>…</val></entry>…</dict>``
dataclass          read only: ``<state><field_name>…</field_name>…</state>`` → dict
=================  ==============================================================

One result differs in shape, not only in format: a FITS card is ``[value, comment]`` in
nightcrew and pyobs' ``FitsHeaderEntry`` dataclass (``<state>`` with ``value`` and ``comment``)
in pyobs; :func:`result_to_pyobs` and :func:`result_from_pyobs` turn one into the other.

Children arrive in pyobs' namespace or none (servers re-serialise them), so only local names
count. Anything else — bytes, dates, an element pyobs does not define — is a
:class:`~nightcrew.errors.CodecError` naming where it sits.
"""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET
from datetime import datetime
from typing import Any

from nightcrew.comm.rpc import Fault
from nightcrew.errors import CodecError, NightcrewError, error_class

__all__ = [
    "NS_PYOBS_RPC",
    "PYOBS_ERRORS",
    "PyobsState",
    "build_pyobs_fault",
    "build_pyobs_params",
    "is_pyobs_call",
    "parse_pyobs_fault",
    "parse_pyobs_params",
    "result_from_pyobs",
    "result_to_pyobs",
    "state_element",
]

NS_PYOBS_RPC = "urn:pyobs:rpc:1"
_RPC = "{jabber:iq:rpc}"
_MAX_DEPTH = 32
#: pyobs-core's exception classes (pyobs.utils.exceptions) that share a name and meaning with ours.
PYOBS_ERRORS = frozenset(
    {
        "AbortedError",
        "DeviceBusyError",
        "GrabImageError",
        "ImageError",
        "InitError",
        "InvalidArgumentError",
        "ModuleError",
        "MotionError",
        "MoveError",
        "NotSupportedError",
        "ParkError",
        "RemoteError",
        "RemoteTimeoutError",
        "ForbiddenError",
    }
)
_PYOBS_EXCEPTIONS = "pyobs.utils.exceptions."
#: Methods returning ``{keyword: card}``: pyobs' card is FitsHeaderEntry(value, comment).
_FITS_HEADER_METHODS = frozenset({"get_fits_header_before", "get_fits_header_after"})


class PyobsState:
    """A value pyobs reads as one of its dataclasses: ``<state>`` with one child per field."""

    __slots__ = ("fields",)

    def __init__(self, fields: dict[str, Any]) -> None:
        self.fields = fields


def result_to_pyobs(method: str, result: Any) -> Any:
    """A nightcrew result in the shape pyobs' method of that name returns (FITS cards as states)."""
    if method in _FITS_HEADER_METHODS and isinstance(result, dict):
        return {
            key: PyobsState({"value": card[0], "comment": card[1]})
            if isinstance(card, list | tuple) and len(card) == 2
            else card
            for key, card in result.items()
        }
    return result


def result_from_pyobs(method: str, result: Any) -> Any:
    """A pyobs result in the shape nightcrew's method of that name returns (FITS cards as pairs)."""
    if method in _FITS_HEADER_METHODS and isinstance(result, dict):
        return {
            key: [card.get("value"), card.get("comment", "")]
            if isinstance(card, dict) and "value" in card
            else card
            for key, card in result.items()
        }
    return result


def _local(tag: str) -> str:
    return tag.rpartition("}")[2]


def value_element(value: Any, path: str) -> ET.Element:
    """The pyobs element for wire ``value``; CodecError if pyobs has no element for it."""
    kind = type(value)
    if value is None:
        return ET.Element("nil")
    if kind is bool:
        return _text("boolean", "true" if value else "false")
    if kind is int:
        return _text("int", str(value))
    if kind is float:
        return _text("double", repr(value) if math.isfinite(value) else str(value))
    if kind is str:
        return _text("string", value)
    if kind is list:
        items = ET.Element("items")
        for i, item in enumerate(value):
            ET.SubElement(items, "item").append(value_element(item, f"{path}[{i}]"))
        return items
    if kind is dict:
        mapping = ET.Element("dict")
        for key, item in value.items():
            entry = ET.SubElement(mapping, "entry")
            ET.SubElement(entry, "key").append(value_element(key, path))
            ET.SubElement(entry, "val").append(value_element(item, f"{path}[{key!r}]"))
        return mapping
    if isinstance(value, datetime):
        return _text("string", value.isoformat())  # pyobs reads times as ISO strings
    if isinstance(value, PyobsState):
        return state_element(NS_PYOBS_RPC, value.fields, path)
    raise CodecError(f"{path}: a {kind.__name__} cannot travel to pyobs (no such value in urn:pyobs:rpc:1)")


def state_element(namespace: str, fields: dict[str, Any], path: str) -> ET.Element:
    """``<state xmlns=namespace>`` with one child per field holding its pyobs element (a dataclass
    as pyobs writes it, in calls and in its PubSub states alike)."""
    state = ET.Element(f"{{{namespace}}}state")
    for name, item in fields.items():
        ET.SubElement(state, f"{{{namespace}}}{name}").append(value_element(item, f"{path}.{name}"))
    return state


def _text(tag: str, text: str) -> ET.Element:
    element = ET.Element(tag)
    element.text = text
    return element


def element_value(element: ET.Element, path: str, depth: int = 0) -> Any:
    """The wire value of one pyobs element; CodecError for what nightcrew cannot map."""
    if depth > _MAX_DEPTH:
        raise CodecError(f"{path}: nested deeper than {_MAX_DEPTH}")
    tag, text = _local(element.tag), element.text or ""
    try:
        if tag == "nil":
            return None
        if tag == "boolean":
            if text not in ("true", "false"):
                raise ValueError(text)
            return text == "true"
        if tag == "int":
            return int(text)
        if tag == "double":
            return float(text)
        if tag == "string":
            return text
    except ValueError:
        raise CodecError(f"{path}: '{text}' is not a valid pyobs <{tag}>") from None
    if tag in ("items", "tuple"):
        items = [child for child in element if _local(child.tag) == "item"]
        return [_only_child(item, f"{path}[{i}]", depth) for i, item in enumerate(items)]
    if tag == "dict":
        result = {}
        for entry in element:
            parts = {_local(child.tag): child for child in entry}
            if "key" not in parts or "val" not in parts:
                raise CodecError(f"{path}: a pyobs <dict> entry without <key> and <val>")
            key = _only_child(parts["key"], path, depth)
            if not isinstance(key, str | int):
                raise CodecError(f"{path}: a pyobs <dict> key must be a string or integer")
            result[key] = _only_child(parts["val"], f"{path}[{key!r}]", depth)
        return result
    if tag == "state":  # a dataclass: one child per field, named as the field
        return {_local(f.tag): _only_child(f, f"{path}.{_local(f.tag)}", depth) for f in element}
    raise CodecError(f"{path}: pyobs value <{tag}> has no nightcrew equivalent")


def _only_child(holder: ET.Element, path: str, depth: int) -> Any:
    children = list(holder)
    return element_value(children[0], path, depth + 1) if children else None


def is_pyobs_call(query: ET.Element) -> bool:
    """Whether a ``jabber:iq:rpc`` query holds a pyobs call (its values wrapped in pyobs' namespace)."""
    params = query.find(f"{_RPC}methodCall/{_RPC}params")
    if params is None:
        return False
    return any(p.find(f"{_RPC}value/{{{NS_PYOBS_RPC}}}value") is not None for p in params)


def build_pyobs_params(values: list[Any], what: str) -> ET.Element:
    """``<params>`` with each value wrapped the pyobs way (an empty ``<params/>`` for no values)."""
    params = ET.Element(f"{_RPC}params")
    for i, value in enumerate(values):
        wrapper = ET.SubElement(
            ET.SubElement(ET.SubElement(params, f"{_RPC}param"), f"{_RPC}value"), f"{{{NS_PYOBS_RPC}}}value"
        )
        wrapper.append(value_element(value, f"{what} {i + 1}"))
    return params


def parse_pyobs_params(params: ET.Element | None, what: str) -> list[Any]:
    """The wire values of a pyobs ``<params>``; CodecError for a value nightcrew cannot map."""
    values = []
    for i, param in enumerate(params.findall(f"{_RPC}param") if params is not None else []):
        wrapper = param.find(f"{_RPC}value/{{{NS_PYOBS_RPC}}}value")
        if wrapper is None:
            raise CodecError(f"{what} {i + 1}: not wrapped in <value xmlns='{NS_PYOBS_RPC}'>")
        values.append(_only_child(wrapper, f"{what} {i + 1}", 0))
    return values


def build_pyobs_fault(fault: Fault) -> ET.Element:
    """A pyobs ``<fault>``: pyobs' own class where one has the same name, else ours by name.

    pyobs raises the class it finds by the qualified name, else the nearest of ``<bases>`` it
    knows; our NightcrewError tree is not theirs, so the nearest shared name goes in ``<bases>``.
    """
    element = ET.Element(f"{_RPC}fault")
    body = ET.SubElement(ET.SubElement(element, f"{_RPC}value"), f"{{{NS_PYOBS_RPC}}}fault")
    shared = fault.error_class in PYOBS_ERRORS
    name = f"{_PYOBS_EXCEPTIONS if shared else 'nightcrew.errors.'}{fault.error_class}"
    ET.SubElement(body, "exception").text = name
    ET.SubElement(body, "message").text = fault.message
    bases = ET.SubElement(body, "bases")
    for base in _shared_bases(fault.error_class):
        ET.SubElement(bases, "base").text = f"{_PYOBS_EXCEPTIONS}{base}"
    return element


def _shared_bases(error_class_name: str) -> list[str]:
    mro = error_class(error_class_name).__mro__[1:]
    return [c.__name__ for c in mro if issubclass(c, NightcrewError) and c.__name__ in PYOBS_ERRORS]


def parse_pyobs_fault(fault: ET.Element) -> Fault:
    """Our Fault for a pyobs ``<fault>``: the class by its last name (nightcrew raises those it knows)."""
    body = fault.find(f"{_RPC}value/{{{NS_PYOBS_RPC}}}fault")
    if body is None:
        return Fault("RemoteError", "pyobs fault without details")
    name = (body.findtext("exception") or "RemoteError").rpartition(".")[2]
    return Fault(name, body.findtext("message") or "")
