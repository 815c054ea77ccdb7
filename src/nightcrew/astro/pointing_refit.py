"""When a pointing model refitted from routine plate solves replaces the one in use (pure).

The passive refit (:mod:`nightcrew.modules.pointing.refit`) keeps the latest pairs of commanded and
solved positions and, every ``every`` new pairs, fits the model again (with outlier rejection) and
asks :func:`refit_decision` whether the new model replaces the current one. It does when all of:

* at least ``min_pairs`` pairs are kept after the rejection;
* its RMS on those pairs is below ``max_rms`` arcsec and below the current model's RMS on the same
  pairs times ``1 - min_improvement`` (no current model: any RMS below ``max_rms``), or, resting on
  at least ``grow`` times the pairs of the current model's fit, not above that model's RMS (more
  pairs pin the terms down better);
* every term is within ``max_term`` arcsec and known better than ``max_sigma`` arcsec (a term the
  pairs cannot pin down, e.g. all from one part of the sky, keeps the old model).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

from nightcrew.astro.pointing import (
    DEFAULT_TERMS,
    PointingModel,
    PointingModelError,
    PointingPair,
    check_term_names,
    fit_pointing_model,
)

__all__ = ["RefitDecision", "RefitRule", "model_rms", "refit_decision"]


@dataclass(frozen=True)
class RefitRule:
    """The rule (see the module docstring); angles in arcsec."""

    terms: tuple[str, ...] = DEFAULT_TERMS
    min_pairs: int = 30
    max_pairs: int = 500
    every: int = 10
    min_improvement: float = 0.25
    grow: float = 2.0
    max_rms: float = 60.0
    max_term: float = 7200.0
    max_sigma: float = 60.0
    clip: float = 3.0

    def __post_init__(self) -> None:
        check_term_names(list(self.terms))
        if not 2 * self.min_pairs > len(self.terms):
            raise PointingModelError(f"min_pairs {self.min_pairs} is too few to fit {len(self.terms)} terms")
        if not (self.max_pairs >= self.min_pairs and self.every >= 1):
            raise PointingModelError("need max_pairs >= min_pairs and every >= 1")
        if not 0.0 <= self.min_improvement < 1.0:
            raise PointingModelError(f"min_improvement must be within 0..1, got {self.min_improvement}")
        if not self.grow > 1.0:
            raise PointingModelError(f"grow must be > 1, got {self.grow}")
        if not (self.max_rms > 0 and self.max_term > 0 and self.max_sigma > 0 and self.clip > 1):
            raise PointingModelError("max_rms, max_term and max_sigma must be > 0 and clip > 1")


@dataclass(frozen=True)
class RefitDecision:
    """A refit's outcome: the new model (None: keep the current one) and why, in words."""

    model: PointingModel | None
    fitted: PointingModel | None
    reason: str


def model_rms(model: PointingModel, pairs: Sequence[PointingPair]) -> float:
    """On-sky RMS in arcsec of the pairs' solved positions from where the model says they point."""
    if not pairs:
        return 0.0
    total = 0.0
    for pair in pairs:
        ha, dec = model.to_sky(pair.ha_commanded, pair.dec_commanded)
        dh = ((pair.ha_solved - ha + 180.0) % 360.0 - 180.0) * math.cos(math.radians(dec))
        total += (dh * 3600.0) ** 2 + ((pair.dec_solved - dec) * 3600.0) ** 2
    return math.sqrt(total / len(pairs))


def refit_decision(
    pairs: Sequence[PointingPair],
    current: PointingModel | None,
    rule: RefitRule,
    *,
    mount: str,
    latitude: float,
) -> RefitDecision:
    """Fit the pairs and decide whether the fit replaces ``current`` (see the module docstring)."""
    if len(pairs) < rule.min_pairs:
        return RefitDecision(None, None, f"{len(pairs)} pairs, {rule.min_pairs} needed")
    try:
        fitted = fit_pointing_model(pairs, mount=mount, latitude=latitude, terms=rule.terms, clip=rule.clip)
    except PointingModelError as exc:
        return RefitDecision(None, None, f"no fit: {exc}")
    statistics = fitted.statistics
    assert statistics is not None  # a fit has them
    if statistics.points < rule.min_pairs:
        return RefitDecision(
            None, fitted, f"{statistics.points} pairs left after rejection, {rule.min_pairs} needed"
        )
    wild = [name for name, value in fitted.terms.items() if abs(value) > rule.max_term]
    vague = [name for name, sigma in fitted.sigmas.items() if sigma > rule.max_sigma]
    if wild or vague:
        return RefitDecision(None, fitted, f"terms out of bounds: {', '.join(wild + vague)}")
    if statistics.rms_after > rule.max_rms:
        return RefitDecision(None, fitted, f'RMS {statistics.rms_after:.1f}" above {rule.max_rms:g}"')
    if current is not None:
        kept = _kept_pairs(pairs, fitted, rule.clip)
        current_rms = model_rms(current, kept)
        before = current.statistics.points if current.statistics is not None else None
        grown = before is not None and statistics.points >= rule.grow * before
        if grown and statistics.rms_after <= current_rms:
            return RefitDecision(
                fitted, fitted, f'{statistics.points} pairs against {before}: RMS {statistics.rms_after:.1f}"'
            )
        if statistics.rms_after > current_rms * (1.0 - rule.min_improvement):
            return RefitDecision(
                None,
                fitted,
                f'RMS {statistics.rms_after:.1f}" not {rule.min_improvement:.0%} better than the '
                f"current model's {current_rms:.1f}\"",
            )
    return RefitDecision(fitted, fitted, f'RMS {statistics.rms_before:.1f}" -> {statistics.rms_after:.1f}"')


def _kept_pairs(pairs: Sequence[PointingPair], fitted: PointingModel, clip: float) -> list[PointingPair]:
    """The pairs the fit kept (within ``clip`` times its RMS), to compare models on the same points."""
    statistics = fitted.statistics
    assert statistics is not None
    limit = clip * statistics.rms_after
    return [pair for pair in pairs if model_rms(fitted, [pair]) <= limit] or list(pairs)
