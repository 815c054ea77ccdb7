"""astrometry.net's solver with its index files loaded once, behind one blocking call.

The ``astrometry`` package (PyPI) wraps astrometry.net's engine as a library: its index files are
memory-mapped when the solver is built, so a solve pays only for the search itself (solve-field
loads them again for every frame). Debian's ``astrometry-data-tycho2`` provides the indexes.
"""

from __future__ import annotations

import logging
import math
import threading
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from astropy.io import fits  # type: ignore[import-untyped]

from nightcrew.services.solver._request import SolveRequest, SolveRequestError

__all__ = ["DEFAULT_INDEX_DIR", "IndexScale", "IndexSolver", "SolveOutcome", "find_index_files"]

log = logging.getLogger(__name__)

DEFAULT_INDEX_DIR = Path("/usr/share/astrometry")
"""Where Debian's ``astrometry-data-*`` packages (and solve-field's default config) put the indexes."""

_QUAD_FRACTION = 0.1  # smallest quad searched, as a fraction of the frame's extent (the package's default)


@dataclass(frozen=True)
class IndexScale:
    """An index file and the quad diameters it holds (arcsec)."""

    path: Path
    smallest_arcsec: float
    largest_arcsec: float


@dataclass(frozen=True)
class SolveOutcome:
    """A solve's result: WCS cards (FITS convention) or why there are none."""

    cards: dict[str, str | int | float] | None
    message: str = ""
    log_odds: float = math.nan


def find_index_files(directory: Path = DEFAULT_INDEX_DIR) -> list[IndexScale]:
    """The astrometry.net index files in ``directory`` with their quad scales, smallest first.

    Raises:
        FileNotFoundError: there are none (the message says what to install).
    """
    scales = []
    for path in sorted(directory.glob("index-*.fits")):
        header = fits.getheader(path)
        low, high = header.get("SCALE_L"), header.get("SCALE_U")  # radians
        if isinstance(low, float) and isinstance(high, float):
            scales.append(IndexScale(path, math.degrees(low) * 3600.0, math.degrees(high) * 3600.0))
    if not scales:
        raise FileNotFoundError(
            f"no astrometry.net index files (index-*.fits) in {directory} "
            "(Debian: apt-get install astrometry-data-tycho2)"
        )
    return sorted(scales, key=lambda s: s.smallest_arcsec)


class IndexSolver:
    """Solves star lists against index files kept in memory; thread-safe, one solve at a time each.

    Args:
        indexes: Index files (from :func:`find_index_files`).
        sip_order: Order of the SIP distortion fitted after the match; 0 for a pure TAN WCS.
        log_odds_threshold: Log-odds above which a match is accepted (astrometry.net's default 21).
        max_quads: Field quads tried before giving up (bounds the time of a hopeless solve);
            0 for no limit.
    """

    def __init__(
        self,
        indexes: Sequence[IndexScale],
        *,
        sip_order: int = 2,
        log_odds_threshold: float = 21.0,
        max_quads: int = 0,
    ) -> None:
        if not indexes:
            raise ValueError("indexes must name at least one index file")
        if sip_order < 0:
            raise ValueError(f"sip_order must be >= 0, got {sip_order}")
        if max_quads < 0:
            raise ValueError(f"max_quads must be >= 0, got {max_quads}")
        self.indexes = list(indexes)
        self.sip_order = sip_order
        self.log_odds_threshold = log_odds_threshold
        self.max_quads = max_quads
        self._solver: Any = None
        self._lock = threading.Lock()

    def blocking_open(self) -> None:
        """Load (memory-map) the index files."""
        try:
            import astrometry  # type: ignore[import-untyped]  # GPL wrapper, imported only by the service
        except ImportError:
            raise RuntimeError(
                "nightcrew solver needs the 'astrometry' package (GPL-3): pip install 'nightcrew[solver]'"
            ) from None
        if self._solver is None:
            self._solver = astrometry.Solver([scale.path for scale in self.indexes])
            log.info("loaded %d index files", len(self.indexes))

    def close(self) -> None:
        with self._lock:
            if self._solver is not None:
                self._solver.close()
                self._solver = None

    def check_scale(self, request: SolveRequest) -> None:
        """Raise :class:`SolveRequestError` when no index holds quads of the size this frame shows."""
        scale_range = request.scale_range_arcsec
        if scale_range is None:
            return
        smallest = _QUAD_FRACTION * min(request.width, request.height) * scale_range[0]
        largest = math.hypot(request.width, request.height) * scale_range[1]
        if any(i.smallest_arcsec <= largest and i.largest_arcsec >= smallest for i in self.indexes):
            return
        raise SolveRequestError(
            f'hints.pixel_scale: at {request.pixel_scale_arcsec:g}"/px a {request.width}x{request.height} '
            f"frame shows quads of {smallest / 60:.3g}'..{largest / 60:.3g}', but the index files hold "
            f"{self.indexes[0].smallest_arcsec / 60:.3g}'..{self.indexes[-1].largest_arcsec / 60:.3g}'"
        )

    def blocking_solve(self, request: SolveRequest) -> SolveOutcome:
        """Solve ``request`` (blocking: run it in a worker thread)."""
        import astrometry

        self.check_scale(request)
        scale_range = request.scale_range_arcsec
        size = None if scale_range is None else astrometry.SizeHint(*scale_range)
        position = (
            None
            if request.ra_deg is None or request.dec_deg is None
            else astrometry.PositionHint(request.ra_deg, request.dec_deg, request.radius_deg)
        )
        threshold = self.log_odds_threshold
        parameters = astrometry.SolutionParameters(
            sip_order=self.sip_order,
            tune_up_logodds_threshold=None if self.sip_order == 0 else 14.0,
            output_logodds_threshold=threshold,
            maximum_quads=self.max_quads,
            # The first match above the threshold is the answer; searching on only costs time.
            logodds_callback=lambda log_odds: (
                astrometry.Action.STOP if max(log_odds) >= threshold else astrometry.Action.CONTINUE
            ),
        )
        # astrometry.net takes the positions as given into CRPIX: 1-based makes the cards FITS ones.
        stars = list(zip((request.x + 1.0).tolist(), (request.y + 1.0).tolist(), strict=True))
        with self._lock:
            if self._solver is None:
                raise RuntimeError("the index files are not loaded: call blocking_open() first")
            solution = self._solver.solve(stars, size, position, parameters)
        if not solution.has_match():
            return SolveOutcome(None, _no_match_message(request))
        match = solution.best_match()
        cards: dict[str, str | int | float] = {}
        for keyword, (value, _comment) in match.wcs_fields.items():
            if isinstance(value, str | int | float) and not isinstance(value, bool):
                cards[keyword] = value
        return SolveOutcome(cards, log_odds=float(match.logodds))


def _no_match_message(request: SolveRequest) -> str:
    hints = []
    if request.ra_deg is not None:
        hints.append(f"within {request.radius_deg:g} deg of ({request.ra_deg:.4f}, {request.dec_deg:.4f})")
    if request.pixel_scale_arcsec is not None:
        hints.append(f'at {request.pixel_scale_arcsec:g}"/px +-{100 * request.scale_tolerance:g}%')
    where = " ".join(hints) or "anywhere (blind)"
    return f"no match for {len(request.x)} stars {where}"
