"""Grading science frames against the night so far, pure: a frame passes or fails, and says why.

Every graded frame's :class:`~nightcrew.images.quality.FrameQuality` joins the night's history of
its setup (filter, binning and exposure time: star count and sky depend on them); a frame is
compared with the running medians of that history *before* it joins:

* FWHM above ``max_fwhm_ratio`` times the median (defocus, bad seeing, wind shake);
* ellipticity above the median plus ``max_ellipticity_rise`` (trailing: guiding or tracking lost);
* fewer stars than ``min_stars_ratio`` times the median (clouds, a closed dome);
* sky above ``max_sky_ratio`` times the median (Moon, twilight, clouds lit from below);
* no star at all (unless the setup's frames have none: a field without stars).

Until a setup has ``min_history`` frames, only the last rule applies. Failed frames join the
history too, so the medians follow a lasting change of the night instead of failing every frame
after it. A frame more than ``night_gap`` seconds after the previous one starts a new night.
"""

from __future__ import annotations

import math
import statistics
from collections import deque
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from nightcrew.config.options import dataclass_from_options
from nightcrew.images.quality import FrameQuality

__all__ = ["FrameGrade", "FrameGrader", "GradingPolicy"]


@dataclass(frozen=True)
class GradingPolicy:
    """The limits of :mod:`~nightcrew.images.grading`, and how often a failed frame is taken again.

    Attributes:
        max_fwhm_ratio: A frame fails with a FWHM above this times the median, > 1.
        max_ellipticity_rise: ... an ellipticity above the median plus this, > 0.
        min_stars_ratio: ... fewer stars than this times the median, 0..1.
        max_sky_ratio: ... a sky above this times the median, > 1.
        min_history: Frames of a setup before its medians count, >= 1.
        history: Frames of a setup the medians are taken over, >= ``min_history``.
        max_retakes: Times a failed frame is taken again before it is kept as it is, >= 0.
        night_gap: Seconds between two frames that start a new night's history.
    """

    max_fwhm_ratio: float = 1.5
    max_ellipticity_rise: float = 0.15
    min_stars_ratio: float = 0.5
    max_sky_ratio: float = 2.0
    min_history: int = 3
    history: int = 50
    max_retakes: int = 2
    night_gap: float = 8 * 3600.0

    def __post_init__(self) -> None:
        problems = [
            ("max_fwhm_ratio", self.max_fwhm_ratio > 1, "> 1"),
            ("max_ellipticity_rise", self.max_ellipticity_rise > 0, "> 0"),
            ("min_stars_ratio", 0 <= self.min_stars_ratio <= 1, "within 0..1"),
            ("max_sky_ratio", self.max_sky_ratio > 1, "> 1"),
            ("min_history", self.min_history >= 1, "an integer >= 1"),
            ("history", self.history >= self.min_history, "an integer >= min_history"),
            ("max_retakes", self.max_retakes >= 0, "an integer >= 0"),
            ("night_gap", self.night_gap > 0, "> 0"),
        ]
        for name, valid, rule in problems:
            value = getattr(self, name)
            integer = name in ("min_history", "history", "max_retakes")
            kind_ok = isinstance(value, int) if integer else isinstance(value, int | float)
            if isinstance(value, bool) or not kind_ok or not math.isfinite(value) or not valid:
                raise ValueError(f"{name} must be {rule}, got {value!r}")

    @classmethod
    def from_options(cls, options: Mapping[str, Any]) -> GradingPolicy:
        """From a script's ``grading`` mapping; ValueError naming an unknown key first."""
        return dataclass_from_options(cls, options)


@dataclass(frozen=True)
class FrameGrade:
    """The verdict on one frame; ``why`` names every failed rule ("" when it passed)."""

    passed: bool
    why: str = ""

    @property
    def label(self) -> str:
        """``PASS`` or ``FAIL``, for the log and the archive."""
        return "PASS" if self.passed else "FAIL"


class FrameGrader:
    """Grades frames against the night's running medians per setup (see the module docstring)."""

    def __init__(self, policy: GradingPolicy) -> None:
        self.policy = policy
        self._history: dict[object, deque[FrameQuality]] = {}
        self._last_time: float | None = None

    def grade(self, quality: FrameQuality, setup: object, time: float) -> FrameGrade:
        """Grade ``quality`` (a frame of ``setup`` taken at clock ``time``), then add it to the history."""
        if self._last_time is not None and time - self._last_time > self.policy.night_gap:
            self._history.clear()
        self._last_time = time
        history = self._history.setdefault(setup, deque(maxlen=self.policy.history))
        reasons = self._failures(quality, history)
        history.append(quality)
        return FrameGrade(not reasons, "; ".join(reasons))

    def median_fwhm(self, setup: object) -> float | None:
        """The running median FWHM of ``setup``'s frames; None before ``min_history`` of them."""
        values = [q.fwhm for q in self._history.get(setup, ()) if math.isfinite(q.fwhm)]
        return statistics.median(values) if len(values) >= self.policy.min_history else None

    def _failures(self, quality: FrameQuality, history: deque[FrameQuality]) -> list[str]:
        policy = self.policy
        if len(history) < policy.min_history:
            return ["no stars"] if quality.stars == 0 else []
        stars = statistics.median(q.stars for q in history)
        if quality.stars == 0:
            return ["no stars"] if stars > 0 else []  # a field without stars (none in the history)
        reasons = []
        fwhm = _median([q.fwhm for q in history])
        if fwhm is not None and quality.fwhm > policy.max_fwhm_ratio * fwhm:
            reasons.append(f"FWHM {quality.fwhm:.2f} > {policy.max_fwhm_ratio:g} x median {fwhm:.2f}")
        ellipticity = _median([q.ellipticity for q in history])
        if ellipticity is not None and quality.ellipticity > ellipticity + policy.max_ellipticity_rise:
            rise = policy.max_ellipticity_rise
            reasons.append(f"ellipticity {quality.ellipticity:.2f} > median {ellipticity:.2f} + {rise:g}")
        if quality.stars < policy.min_stars_ratio * stars:
            reasons.append(f"{quality.stars} stars < {policy.min_stars_ratio:g} x median {stars:g}")
        sky = _median([q.sky for q in history])
        if sky is not None and sky > 0 and quality.sky > policy.max_sky_ratio * sky:
            reasons.append(f"sky {quality.sky:.3g} > {policy.max_sky_ratio:g} x median {sky:.3g}")
        return reasons


def _median(values: list[float]) -> float | None:
    finite = [value for value in values if math.isfinite(value)]
    return statistics.median(finite) if finite else None
