"""Fitting the free coefficients of a focus model by weighted linear least squares.

Only models that are linear in their coefficients can be fitted: a sum of terms, each multiplied
by at most one coefficient, e.g. ``a*T_mirror + b*T_tube + c*temp + d`` or ``a*(T1 - T2) + b``
(checked with :func:`~nightcrew.focus.expression.coefficient_degree`). Such a model is
``f(x; c) = f(x; 0) + sum_i c_i * (f(x; e_i) - f(x; 0))`` exactly, so the design matrix comes from
evaluating the model itself with unit coefficient vectors — no symbolic algebra needed.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from nightcrew.focus.expression import Expression, ExpressionError, coefficient_degree

__all__ = ["CoefficientFit", "check_linear", "fit_coefficients"]

#: Focus errors below this (mm) are raised to it, so one over-confident point cannot dominate.
MIN_ERROR = 1e-4


@dataclass(frozen=True)
class CoefficientFit:
    """Result of a fit: coefficient values and uncertainties, the weighted RMS residual (mm)."""

    coefficients: dict[str, float]
    uncertainties: dict[str, float]
    rms: float
    count: int


def check_linear(model: Expression, coefficients: Sequence[str]) -> None:
    """Raise ExpressionError unless ``model`` is linear in ``coefficients`` (see module docstring)."""
    if coefficient_degree(model, set(coefficients)) > 1:
        raise ExpressionError(
            f"model {model.text!r} is not linear in its coefficients ({', '.join(coefficients)}): "
            "only a sum of terms each multiplied by at most one coefficient can be refitted, "
            "e.g. 'a*T1 + b*T2 + c'; give fixed coefficients or rewrite the model"
        )


def fit_coefficients(
    model: Expression,
    coefficients: Sequence[str],
    samples: Sequence[Mapping[str, float]],
    values: Sequence[float],
    errors: Sequence[float] | None = None,
) -> CoefficientFit:
    """Coefficients minimising ``sum(((value - model(sample)) / error)^2)``.

    Args:
        model: The model; every name not in ``coefficients`` must be in each sample.
        coefficients: Names of the free coefficients.
        samples: Variable values of each measurement (e.g. temperatures).
        values: Measured values (e.g. best focus in mm), one per sample.
        errors: One-sigma errors of ``values``; equal weights if None.

    Raises:
        ExpressionError: The model is not linear in the coefficients, or cannot be evaluated.
        ValueError: Too few measurements, mismatched lengths, or coefficients not determined by the
            data (e.g. a temperature that never changed).
    """
    check_linear(model, coefficients)
    names = list(coefficients)
    n = len(samples)
    if len(values) != n or (errors is not None and len(errors) != n):
        raise ValueError(f"got {n} samples, {len(values)} values and {len(errors or [])} errors")
    if n < len(names):
        raise ValueError(f"need at least {len(names)} measurements to fit {', '.join(names)}, got {n}")
    zero = dict.fromkeys(names, 0.0)
    design = np.empty((n, len(names)))
    offset = np.empty(n)
    for row, sample in enumerate(samples):
        base = model.evaluate({**sample, **zero})
        offset[row] = base
        for column, name in enumerate(names):
            design[row, column] = model.evaluate({**sample, **zero, name: 1.0}) - base
    sigma = np.ones(n) if errors is None else np.maximum(np.asarray(errors, dtype=float), MIN_ERROR)
    if not np.all(np.isfinite(sigma)):
        raise ValueError("focus errors must be finite")
    weighted = design / sigma[:, None]
    target = (np.asarray(values, dtype=float) - offset) / sigma
    solution, _, rank, _ = np.linalg.lstsq(weighted, target, rcond=None)
    if rank < len(names):
        raise ValueError(
            f"the measurements do not determine all of {', '.join(names)} "
            "(a variable that never changed, or two that always change together?)"
        )
    residuals = target - weighted @ solution
    dof = max(1, n - len(names))
    covariance = np.linalg.inv(weighted.T @ weighted) * max(1.0, float(residuals @ residuals) / dof)
    fitted = {name: float(value) for name, value in zip(names, solution, strict=True)}
    return CoefficientFit(
        coefficients=fitted,
        uncertainties={name: math.sqrt(float(covariance[i, i])) for i, name in enumerate(names)},
        rms=float(np.sqrt(np.mean((residuals * sigma) ** 2))),
        count=n,
    )
