"""Least-squares coefficient fits and the focus history's plain form."""

from __future__ import annotations

from datetime import UTC, datetime

import numpy as np
import pytest

from nightcrew.focus import Expression, ExpressionError, FocusRecord, fit_coefficients, records_from_plain


def test_four_coefficients_from_three_temperatures_with_noise() -> None:
    rng = np.random.default_rng(1)
    truth = {"a": -0.03, "b": -0.02, "c": 0.01, "d": 25.0}
    samples = [{"T1": t1, "T2": t2, "temp": t3} for t1, t2, t3 in rng.uniform(-5, 20, size=(30, 3))]
    a, b, c, d = truth.values()
    focus = [a * s["T1"] + b * s["T2"] + c * s["temp"] + d for s in samples]
    noisy = np.asarray(focus) + rng.normal(0, 0.002, len(focus))
    model = Expression("a*T1 + b*T2 + c*temp + d")
    fit = fit_coefficients(model, ["a", "b", "c", "d"], samples, list(noisy), [0.002] * len(focus))
    for name, value in truth.items():
        assert fit.coefficients[name] == pytest.approx(value, abs=4 * fit.uncertainties[name] + 1e-6)
    assert fit.rms == pytest.approx(0.002, rel=0.4)
    assert fit.count == 30


def test_terms_may_be_any_function_of_the_variables() -> None:
    samples = [{"T": t} for t in (0.0, 5.0, 10.0, 15.0)]
    values = [2.0 * np.exp(t / 10) - 1.0 for t in (0.0, 5.0, 10.0, 15.0)]
    fit = fit_coefficients(Expression("a*exp(T/10) - b"), ["a", "b"], samples, values)
    assert fit.coefficients == pytest.approx({"a": 2.0, "b": 1.0})


def test_a_non_linear_model_is_refused_for_fitting() -> None:
    with pytest.raises(ExpressionError, match=r"not linear in its coefficients \(a, b\).*sum of terms"):
        fit_coefficients(Expression("exp(a*T) + b"), ["a", "b"], [{"T": 1.0}] * 3, [1.0] * 3)


def test_too_few_or_degenerate_measurements() -> None:
    model = Expression("a*T + b")
    with pytest.raises(ValueError, match="need at least 2 measurements"):
        fit_coefficients(model, ["a", "b"], [{"T": 1.0}], [1.0])
    with pytest.raises(ValueError, match="do not determine all of a, b"):
        fit_coefficients(model, ["a", "b"], [{"T": 1.0}] * 3, [1.0, 1.1, 0.9])


def test_history_records_round_trip_and_damaged_entries_are_skipped() -> None:
    record = FocusRecord(datetime(2024, 1, 15, 22, tzinfo=UTC), 25.1, 0.01, "V", {"T": 3.5})
    entries = [record.to_plain(), {"time": "yesterday", "focus": 1, "error": 1}, "junk", {"focus": 2}]
    records, problems = records_from_plain(entries)
    assert records == [record]
    assert len(problems) == 3
    assert problems[0].startswith("record 1: ValueError")
    assert records_from_plain({"not": "a list"})[1] == ["expected a list of records, got dict"]
