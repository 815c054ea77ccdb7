"""Reading a VOEvent notice (IVOA VOEvent 2.0, as GCN and other brokers send them) into a :class:`Notice`.

Only what turning a notice into a request needs: its IVORN and role, its type (the ``Packet_Type``
parameter GCN sets, else the IVORN's stream), the trigger id, the position and its error radius
(``WhereWhen``), and the events it cites. A citation (``Citations/EventIVORN``) must say how it
cites, ``followup``, ``supersedes`` or ``retraction`` (VOEvent 2.0, section 3.7.1: required, no
default). Anything malformed is a :class:`NoticeError` naming what is wrong. Pure: bytes in, a value out.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from datetime import UTC, datetime

from lxml import etree  # type: ignore[import-untyped]

from nightcrew.errors import InvalidArgumentError

__all__ = ["Notice", "NoticeError", "parse_notice"]

#: How a VOEvent 2.0 citation relates a notice to the cited one.
CITE_KINDS = ("followup", "supersedes", "retraction")
_VOEVENT_TAGS = (
    "{http://www.ivoa.net/xml/VOEvent/v2.0}VOEvent",
    "{http://www.ivoa.net/xml/VOEvent/v1.1}VOEvent",
)


class NoticeError(InvalidArgumentError):
    """A notice that cannot be read (not a VOEvent, no position, coordinates out of range ...)."""


@dataclass(frozen=True)
class Notice:
    """What a notice says.

    Args:
        ivorn: Its identifier.
        role: ``observation``, ``test``, ``utility`` or ``prediction``.
        notice_type: GCN's ``Packet_Type`` (e.g. ``"61"``), else the IVORN's stream (``SWIFT``).
        trigger: GCN's ``TrigID``, if given (the same burst in every notice of its stream).
        ra, dec, error_radius: ICRS position and its error radius in degrees; None in a notice
            without a position (a retraction may have none).
        time: When the event happened (``ISOTime``), if given.
        cites: ``(cite, ivorn)`` of the events it refers to.
        withdrawn: GCN's ``Retraction`` parameter is true: it withdraws its trigger's event.
    """

    ivorn: str
    role: str
    notice_type: str
    trigger: str | None = None
    ra: float | None = None
    dec: float | None = None
    error_radius: float | None = None
    time: datetime | None = None
    cites: tuple[tuple[str, str], ...] = ()
    withdrawn: bool = False

    @property
    def retraction(self) -> bool:
        """Whether it withdraws an earlier notice (a ``retraction`` citation or GCN's ``Retraction``)."""
        return self.withdrawn or self.cites_as("retraction")

    def cites_as(self, kind: str) -> bool:
        """Whether it cites an event as ``kind`` (one of :data:`CITE_KINDS`)."""
        return any(cite == kind for cite, _ in self.cites)

    @property
    def stream(self) -> str:
        """The stream it belongs to: its IVORN before ``#`` (GCN's trigger ids are unique only within
        one stream, e.g. ``ivo://nasa.gsfc.gcn/SWIFT``)."""
        return self.ivorn.split("#", 1)[0]

    @property
    def cited(self) -> tuple[str, ...]:
        """IVORNs of the events it refers to."""
        return tuple(ivorn for _, ivorn in self.cites)


def parse_notice(payload: bytes) -> Notice:
    """The notice in ``payload`` (the VOEvent's XML).

    Raises:
        NoticeError: Not well-formed XML, not a VOEvent, no IVORN, or a position that is missing
            parts or out of range (a retraction needs none).
    """
    try:
        root = etree.fromstring(payload, parser=etree.XMLParser(resolve_entities=False, no_network=True))
    except etree.XMLSyntaxError as exc:
        raise NoticeError(f"not well-formed XML ({exc})") from None
    if root.tag not in _VOEVENT_TAGS:
        raise NoticeError(f"not a VOEvent (root element {etree.QName(root).localname!r})")
    ivorn = (root.get("ivorn") or "").strip()
    if not ivorn:
        raise NoticeError("a VOEvent without an ivorn")
    params = {p.get("name"): (p.get("value") or "").strip() for p in root.iterfind(".//What//Param")}
    cites = _citations(root, ivorn)
    withdrawn = params.get("Retraction", "").lower() == "true"
    stream = ivorn.split("#", 1)[0].rsplit("/", 1)[-1]
    retraction = withdrawn or any(cite == "retraction" for cite, _ in cites)
    ra, dec, radius = _position(root, ivorn, required=not retraction)
    return Notice(
        ivorn=ivorn,
        role=(root.get("role") or "observation").strip(),
        notice_type=params.get("Packet_Type") or stream,
        trigger=params.get("TrigID") or None,
        ra=ra,
        dec=dec,
        error_radius=radius,
        time=_time(root),
        cites=cites,
        withdrawn=withdrawn,
    )


def _citations(root: etree._Element, ivorn: str) -> tuple[tuple[str, str], ...]:
    cites = []
    for element in root.iterfind("Citations/EventIVORN"):
        cited, cite = (element.text or "").strip(), (element.get("cite") or "").strip()
        if not cited:
            raise NoticeError(f"{ivorn}: a citation (Citations/EventIVORN) without an IVORN")
        if cite not in CITE_KINDS:
            raise NoticeError(
                f"{ivorn}: the citation of {cited} has cite={cite!r}; expected {', '.join(CITE_KINDS)}"
            )
        cites.append((cite, cited))
    return tuple(cites)


def _position(
    root: etree._Element, ivorn: str, *, required: bool
) -> tuple[float | None, float | None, float | None]:
    position = root.find("WhereWhen//Position2D")
    if position is None:
        if required:
            raise NoticeError(f"{ivorn}: no position (WhereWhen/.../Position2D)")
        return None, None, None
    values = [position.findtext(path) for path in ("Value2/C1", "Value2/C2", "Error2Radius")]
    try:
        ra, dec, radius = (float(v) for v in values)
    except (TypeError, ValueError):
        raise NoticeError(f"{ivorn}: position needs numbers C1, C2 and Error2Radius, got {values}") from None
    if not (math.isfinite(ra) and 0.0 <= ra < 360.0 and math.isfinite(dec) and -90.0 <= dec <= 90.0):
        raise NoticeError(f"{ivorn}: coordinates out of range (ra {ra:g}, dec {dec:g})")
    if not (math.isfinite(radius) and 0.0 <= radius <= 180.0):
        raise NoticeError(f"{ivorn}: error radius out of range ({radius:g} deg)")
    return ra, dec, radius


def _time(root: etree._Element) -> datetime | None:
    text = root.findtext("WhereWhen//TimeInstant/ISOTime")
    if not text:
        return None
    try:
        value = datetime.fromisoformat(text.strip())
    except ValueError:
        return None
    return value.replace(tzinfo=UTC) if value.tzinfo is None else value.astimezone(UTC)
