"""The pointing model: terms, fit with uncertainties and outlier rejection, application, files, refit rule."""

from __future__ import annotations

import numpy as np
import pytest

from nightcrew.astro.pointing import (
    DEFAULT_TERMS,
    PointingModel,
    PointingModelError,
    PointingPair,
    fit_pointing_model,
    from_hadec,
    to_hadec,
)
from nightcrew.astro.pointing_refit import RefitRule, model_rms, refit_decision

LATITUDE = 51.5
#: Tens of arcminutes, as a roughly set-up mount has them (arcsec).
TRUTH = {
    "IH": 1500.0,
    "ID": -1200.0,
    "CH": 900.0,
    "NP": -420.0,
    "MA": 1800.0,
    "ME": -1300.0,
    "TF": 240.0,
    "FO": 180.0,
    "HHSH": 60.0,
    "HHCH": -90.0,
}


def measured_pairs(
    count: int, *, noise: float = 1.0, seed: int = 1, truth: dict[str, float] = TRUTH
) -> list[PointingPair]:
    """Pairs of a mount with the true terms over the sky in view, solved with ``noise`` arcsec RMS."""
    rng = np.random.default_rng(seed)
    model = PointingModel("mount", LATITUDE, truth)
    pairs = []
    for _ in range(count):
        ha, dec = rng.uniform(-85.0, 85.0), rng.uniform(-15.0, 80.0)
        true_ha, true_dec = model.to_sky(ha, dec)
        east, north = rng.normal(0.0, noise / 3600.0, size=2)
        pairs.append(PointingPair(ha, dec, true_ha + east / np.cos(np.radians(true_dec)), true_dec + north))
    return pairs


def test_a_40_star_series_recovers_every_term_within_3_sigma() -> None:
    model = fit_pointing_model(measured_pairs(40), mount="mount", latitude=LATITUDE)
    assert tuple(model.terms) == DEFAULT_TERMS
    for name, value in TRUTH.items():
        assert abs(model.terms[name] - value) < 3.0 * model.sigmas[name], name
        assert 0.0 < model.sigmas[name] < 5.0, name
    assert model.statistics is not None
    assert model.statistics.rms_before > 1000.0
    assert model.statistics.rms_after < 2.0


def test_outliers_are_rejected_and_do_not_pull_the_fit() -> None:
    pairs = measured_pairs(40)
    wrong = [
        PointingPair(p.ha_commanded, p.dec_commanded, p.ha_solved + 0.2, p.dec_solved) for p in pairs[:3]
    ]
    model = fit_pointing_model(wrong + pairs[3:], mount="mount", latitude=LATITUDE)
    assert model.statistics is not None
    assert model.statistics.rejected == 3
    assert model.statistics.rms_after < 2.0
    assert abs(model.terms["IH"] - TRUTH["IH"]) < 3.0 * model.sigmas["IH"]


def test_to_mount_sends_the_mount_where_it_then_points_at_the_request() -> None:
    model = PointingModel("mount", LATITUDE, TRUTH)
    for ha, dec in [(0.0, 0.0), (-60.0, 75.0), (80.0, -20.0), (179.0, 40.0)]:
        commanded = model.to_mount(ha, dec)
        assert model.to_sky(*commanded) == pytest.approx((ha, dec), abs=1e-8)
        assert abs(commanded[0] - ha) > 0.1  # the terms are large
    assert PointingModel("mount", LATITUDE, {}).to_mount(10.0, 20.0) == (10.0, 20.0)


def test_hour_angles_round_trip_to_icrs() -> None:
    ha, dec = to_hadec(83.6, 22.0, 13.4, 1_700_000_000.0)
    assert from_hadec(ha, dec, 13.4, 1_700_000_000.0) == pytest.approx((83.6, 22.0), abs=1e-8)


def test_the_file_data_round_trips_and_names_its_mount() -> None:
    model = fit_pointing_model(measured_pairs(30), mount="telescope", latitude=LATITUDE)
    again = PointingModel.from_dict(model.to_dict(), mount="telescope")
    assert again.terms == pytest.approx({k: round(v, 4) for k, v in model.terms.items()})
    assert again.statistics is not None and again.statistics.points == 30
    with pytest.raises(PointingModelError, match="is for mount 'telescope', not 'other'"):
        PointingModel.from_dict(model.to_dict(), mount="other")


@pytest.mark.parametrize(
    ("data", "message"),
    [
        ({"mount": "m", "latitude": 50, "terms": {"IH": 1, "XX": 2}}, "unknown pointing term.*XX"),
        ({"mount": "m", "latitude": 50, "terms": {"HQSH": 1}}, "unknown pointing term.*HQSH"),
        ({"latitude": 50, "terms": {}}, "names no mount"),
        ({"mount": "m", "terms": {}}, "malformed pointing model"),
        ({"mount": "m", "latitude": 50, "terms": {}, "colour": 1}, "unknown key.*colour"),
        (["IH"], "must be a mapping"),
    ],
)
def test_bad_model_data_is_one_clear_error(data: object, message: str) -> None:
    with pytest.raises(PointingModelError, match=message):
        PointingModel.from_dict(data, mount="m")


def test_unknown_terms_and_too_few_points_are_refused_before_fitting() -> None:
    with pytest.raises(PointingModelError, match=r"unknown pointing term.*BOGUS"):
        fit_pointing_model(measured_pairs(40), mount="m", latitude=LATITUDE, terms=("IH", "BOGUS"))
    with pytest.raises(PointingModelError, match="4 points are too few to fit 10 terms"):
        fit_pointing_model(measured_pairs(4), mount="m", latitude=LATITUDE)


def test_a_refit_replaces_the_model_only_by_the_rule() -> None:
    rule = RefitRule(min_pairs=30)
    pairs = measured_pairs(60, seed=3)
    assert refit_decision(pairs[:20], None, rule, mount="m", latitude=LATITUDE).model is None
    first = refit_decision(pairs, None, rule, mount="m", latitude=LATITUDE)
    assert first.model is not None and "->" in first.reason
    # The same sky again is no 25 % better: the model stays.
    again = refit_decision(measured_pairs(60, seed=4), first.model, rule, mount="m", latitude=LATITUDE)
    assert again.model is None and "not 25% better" in again.reason
    # Twice the pairs pin the terms down better: the refit wins unless its RMS is worse.
    doubled = refit_decision(measured_pairs(120, seed=6), first.model, rule, mount="m", latitude=LATITUDE)
    assert doubled.model is not None and "120 pairs against 60" in doubled.reason
    # The mount changed (its polar axis was moved): the refit wins.
    moved = dict(TRUTH, MA=TRUTH["MA"] + 600.0)
    changed = measured_pairs(60, seed=5, truth=moved)
    assert model_rms(first.model, changed) > 100.0
    replaced = refit_decision(changed, first.model, rule, mount="m", latitude=LATITUDE)
    assert replaced.model is not None and replaced.model.terms["MA"] == pytest.approx(moved["MA"], abs=5.0)
    # Terms beyond the bounds keep the model.
    strict = RefitRule(min_pairs=30, max_term=1000.0)
    assert "out of bounds" in refit_decision(pairs, None, strict, mount="m", latitude=LATITUDE).reason


def test_a_bad_rule_is_refused() -> None:
    with pytest.raises(PointingModelError, match="too few"):
        RefitRule(min_pairs=3)
    with pytest.raises(PointingModelError, match="unknown pointing term"):
        RefitRule(terms=("IH", "QQ"))
