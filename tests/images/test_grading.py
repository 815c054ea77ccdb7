"""Frame quality from the pixels, and grading against the night's running medians (pure)."""

from __future__ import annotations

import math

import pytest

from nightcrew.images.grading import FrameGrader, GradingPolicy
from nightcrew.images.quality import FrameQuality, measure_frame_quality
from nightcrew.sim.render import Conditions

from .frames import as_image, random_field, render

GOOD = FrameQuality(fwhm=2.0, ellipticity=0.05, stars=100, sky=1000.0)
SETUP = ("V", 1, 60.0)


def test_the_measured_quality_follows_the_seeing_and_the_stars_in_the_frame() -> None:
    field = random_field(256, 60, seed=1)
    sharp = measure_frame_quality(
        as_image(render(field, 256, seed=2, conditions=Conditions(seeing_arcsec=2.5)))
    )
    blurred = measure_frame_quality(
        as_image(render(field, 256, seed=2, conditions=Conditions(seeing_arcsec=5.0)))
    )
    assert sharp.stars >= 10 and sharp.ellipticity < 0.15
    assert sharp.fwhm == pytest.approx(2.5, rel=0.25)  # arcsec (the frame has a WCS)
    assert blurred.fwhm / sharp.fwhm == pytest.approx(2.0, rel=0.2)
    assert blurred.sky == pytest.approx(sharp.sky, rel=0.02)


def test_a_frame_is_compared_with_its_setups_median_once_there_is_history() -> None:
    grader = FrameGrader(GradingPolicy(min_history=3))
    bad = FrameQuality(fwhm=4.0, ellipticity=0.4, stars=20, sky=5000.0)
    assert grader.grade(bad, SETUP, 0.0).passed  # no history yet: nothing to compare with
    for minute in range(1, 4):
        assert grader.grade(GOOD, SETUP, 60.0 * minute).passed
    grade = grader.grade(bad, SETUP, 300.0)
    assert not grade.passed and grade.label == "FAIL"
    assert grade.why == (
        "FWHM 4.00 > 1.5 x median 2.00; ellipticity 0.40 > median 0.05 + 0.15; "
        "20 stars < 0.5 x median 100; sky 5e+03 > 2 x median 1e+03"
    )
    assert grader.grade(bad, ("R", 1, 60.0), 360.0).passed  # another setup has its own history
    assert grader.median_fwhm(SETUP) == 2.0


def test_a_frame_without_stars_always_fails_and_a_lasting_change_becomes_the_norm() -> None:
    grader = FrameGrader(GradingPolicy(min_history=1, history=5))
    empty = FrameQuality(math.nan, math.nan, 0, 900.0)
    assert [grader.grade(empty, SETUP, 0.0).why, grader.grade(GOOD, SETUP, 1.0).why] == ["no stars", ""]
    assert grader.grade(empty, SETUP, 2.0).why == "no stars"  # the setup has stars
    starless = FrameGrader(GradingPolicy(min_history=2))
    verdicts = [starless.grade(empty, SETUP, float(k)).passed for k in range(4)]
    assert verdicts == [False, False, True, True]  # a field without stars: its frames pass then
    grader = FrameGrader(GradingPolicy(min_history=1, history=5))
    for minute in range(3):
        grader.grade(GOOD, SETUP, 60.0 * minute)
    worse = FrameQuality(fwhm=3.5, ellipticity=0.05, stars=100, sky=1000.0)  # the seeing went bad
    verdicts = [grader.grade(worse, SETUP, 60.0 * k).passed for k in range(3, 7)]
    assert verdicts == [False, False, False, True]  # failed frames join the history: the new norm


def test_a_new_night_starts_a_new_history() -> None:
    grader = FrameGrader(GradingPolicy(min_history=1))
    grader.grade(GOOD, SETUP, 0.0)
    wide = FrameQuality(fwhm=4.0, ellipticity=0.05, stars=100, sky=1000.0)
    assert not grader.grade(wide, SETUP, 3600.0).passed
    assert grader.grade(wide, SETUP, 3600.0 + 9 * 3600.0).passed  # after the day: no history


@pytest.mark.parametrize(
    ("options", "message"),
    [
        ({"max_fwhm_ratio": 0.9}, r"max_fwhm_ratio must be > 1, got 0.9"),
        ({"max_retakes": -1}, r"max_retakes must be an integer >= 0, got -1"),
        ({"history": 2, "min_history": 3}, r"history must be an integer >= min_history, got 2"),
        ({"retakes": 3}, r"retakes is not an option; known: history, max_ellipticity_rise, "),
    ],
)
def test_grading_options_that_make_no_sense_are_refused(options: dict[str, object], message: str) -> None:
    with pytest.raises(ValueError, match=message):
        GradingPolicy.from_options(options)
