"""Asking the other modules for FITS header cards, all at once and each within a short timeout.

:class:`MissingHeaders` knows the providers a camera expects (configured as ``expect_headers_from``)
and remembers which others ever answered, so that a frame taken while one of them is down (killed,
restarting, offline) says so in its header instead of silently lacking its cards. The configured
ones matter after a restart of the camera itself: it has not yet heard from anybody, and a
provider that is down then would otherwise go unnoticed.
"""

from __future__ import annotations

import asyncio
import logging
import math
import re
from dataclasses import dataclass, field

from nightcrew.comm.base import Comm
from nightcrew.errors import NightcrewError
from nightcrew.interfaces import FitsCard, IFitsHeaderAfter, IFitsHeaderBefore

__all__ = ["HeaderReplies", "MissingHeaders", "ask_header_providers", "clean_cards", "collect_headers"]

log = logging.getLogger(__name__)

_KEYWORD = re.compile(r"^[A-Z0-9_-]{1,8}$")
_VALUE_TYPES = (bool, int, float, str, type(None))
#: The card naming header providers whose cards a frame lacks.
MISSING_KEYWORD = "HDRMISS"


@dataclass
class HeaderReplies:
    """One round of asking: the merged cards and who answered."""

    cards: dict[str, FitsCard] = field(default_factory=dict)
    answered: set[str] = field(default_factory=set)


class MissingHeaders:
    """Who is missing from a frame's header rounds: an ``expected`` provider that answered in
    neither round, or one that answered a round (``before``/``after``) for an earlier frame but
    not this time."""

    def __init__(self, expected: set[str] | None = None) -> None:
        self._expected = set(expected or ())
        self._known: dict[str, set[str]] = {"before": set(), "after": set()}

    def missing(self, before: HeaderReplies, after: HeaderReplies) -> set[str]:
        """The providers this frame lacks (and learn those that answered for the first time)."""
        absent = self._expected - before.answered - after.answered
        for when, replies in (("before", before), ("after", after)):
            known = self._known[when]
            known |= replies.answered
            absent |= known - replies.answered
        return absent

    @staticmethod
    def card(missing: set[str]) -> dict[str, FitsCard]:
        """``HDRMISS`` naming the missing providers, or nothing."""
        if not missing:
            return {}
        return {MISSING_KEYWORD: (",".join(sorted(missing)), "header providers that did not answer")}


async def collect_headers(
    comm: Comm, when: str, wait_limit: float, namespaces: list[str] | None = None
) -> dict[str, FitsCard]:
    """The cards of :func:`ask_header_providers`."""
    return (await ask_header_providers(comm, when, wait_limit, namespaces)).cards


async def ask_header_providers(
    comm: Comm, when: str, wait_limit: float, namespaces: list[str] | None = None
) -> HeaderReplies:
    """Cards from every other module offering IFitsHeaderBefore (``when="before"``) or ...After.

    Providers are asked concurrently; one that fails or takes longer than ``wait_limit`` clock
    seconds (plus the comm's network allowance) is logged and left out, so a slow or broken peer
    never stalls an exposure. When two providers give the same keyword, the one whose name sorts
    last wins (deterministic).
    """
    interface = IFitsHeaderBefore if when == "before" else IFitsHeaderAfter
    offered = sorted(n for n in await comm.clients_with_interface(interface) if n != comm.name)
    names = [name for name in offered if comm.trusts_headers_from(name)]
    for name in sorted(set(offered) - set(names)):
        # A forged OBJECT/RA/DEC in a frame is worse than a missing one.
        log.warning("refused FITS headers from %s: not a header provider in the access policy", name)
    results = await asyncio.gather(*(_ask(comm, name, when, wait_limit, namespaces) for name in names))
    replies = HeaderReplies()
    for name, cards in zip(names, results, strict=True):
        if cards is not None:
            replies.cards.update(cards)
            replies.answered.add(name)
    return replies


async def _ask(
    comm: Comm, name: str, when: str, wait_limit: float, namespaces: list[str] | None
) -> dict[str, FitsCard] | None:
    try:
        # Across processes the network adds wall time that a fast simulated clock does not shrink.
        async with comm.timeout(wait_limit):
            if when == "before":
                cards = await (await comm.proxy(name, IFitsHeaderBefore)).get_fits_header_before(namespaces)
            else:
                cards = await (await comm.proxy(name, IFitsHeaderAfter)).get_fits_header_after(namespaces)
    except TimeoutError:
        log.warning("no FITS header from %s within %g s; leaving its cards out", name, wait_limit)
        return None
    except NightcrewError as exc:
        log.warning("FITS header from %s failed: %s", name, exc)
        return None
    return clean_cards(cards, name)


def clean_cards(cards: dict[str, FitsCard], source: str) -> dict[str, FitsCard]:
    """The cards that can be written: valid keyword, plain value, printable ASCII comment."""
    clean: dict[str, FitsCard] = {}
    for keyword, card in cards.items():
        value, comment = card
        bad_number = isinstance(value, float) and not math.isfinite(value)
        if not _KEYWORD.match(keyword) or not isinstance(value, _VALUE_TYPES) or bad_number:
            log.warning("ignoring invalid FITS card %r=%r from %s", keyword, value, source)
            continue
        if isinstance(value, str):
            value = value.encode("ascii", "replace").decode()
        comment = re.sub(r"[^ -~]", "?", str(comment))
        clean[keyword] = (value, comment)
    return clean
