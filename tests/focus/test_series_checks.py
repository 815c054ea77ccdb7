"""A focus series must form a V before its minimum is believed; raw-frame defects must not count."""

from __future__ import annotations

import math

import numpy as np
import pytest

from nightcrew.focus.series import (
    FocusSeriesError,
    fit_focus_hyperbola,
    photometry_width,
    point_defects,
)
from nightcrew.images.processors._shared import estimate_background
from nightcrew.images.processors.detection import detect_sources_sep

#: The dusk series of a simulated night (filter R, 15 s frames) that was accepted at 24.49 ± 0.52 mm:
#: hot pixels measured as stars made the out-of-focus widths garbage.
GARBAGE_FOCUS = [24.1, 24.4, 24.7, 25.0, 25.3, 25.6, 25.9]
GARBAGE_WIDTHS = [2.85, 5.89, 6.47, 3.27, 3.86, 7.23, 10.68]


def test_the_garbage_dusk_series_is_refused_as_too_uncertain() -> None:
    with pytest.raises(
        FocusSeriesError, match=r"best focus 24\.\d+ ± 0\.\d+ is too uncertain \(accepted: ± 0\.1500\)"
    ):
        fit_focus_hyperbola(GARBAGE_FOCUS, GARBAGE_WIDTHS)


def test_widths_that_scatter_about_a_shallow_v_are_refused() -> None:
    # The series this night accepted at 25.008 ± 0.102 mm, 0.1 mm off the truth: certain enough, but
    # the V does not describe the widths (24.1 is sharper than 24.4).
    widths = [7.76, 10.09, 6.46, 3.29, 3.96, 7.54, 11.40]
    with pytest.raises(FocusSeriesError, match=r"widths scatter by 1\.\d+ about a fitted V only 6\.\d+ deep"):
        fit_focus_hyperbola(GARBAGE_FOCUS, widths)


def test_a_noisy_but_clear_v_is_accepted() -> None:
    rng = np.random.default_rng(3)
    focus = np.array(GARBAGE_FOCUS)
    truth = 25.12
    widths = np.hypot(1.5, 13.0 * (focus - truth)) * (1.0 + rng.normal(0.0, 0.05, focus.size))
    fit = fit_focus_hyperbola(focus.tolist(), widths.tolist())
    assert fit.focus == pytest.approx(truth, abs=0.03)
    assert fit.error < 0.5 * 0.3


def test_an_explicit_error_limit_replaces_the_step_based_one() -> None:
    focus = np.linspace(24.8, 25.2, 9)
    widths = np.hypot(2.0, 25.0 * (focus - 25.0)) + np.random.default_rng(4).normal(0.0, 0.1, focus.size)
    fit = fit_focus_hyperbola(focus.tolist(), widths.tolist())
    with pytest.raises(FocusSeriesError, match="too uncertain"):
        fit_focus_hyperbola(focus.tolist(), widths.tolist(), max_error=fit.error / 2)


def _frame_with_stars_and_hot_pixels(fwhm: float) -> tuple[np.ndarray, np.ndarray]:
    """A twilight sky (2400 ± 35) with 12 Gaussian stars of ``fwhm`` px and 20 hot pixels; star (x, y)s."""
    rng = np.random.default_rng(5)
    data = rng.normal(2400.0, 35.0, (256, 256))
    yy, xx = np.indices(data.shape, dtype=np.float64)
    sigma = fwhm / (2.0 * math.sqrt(2.0 * math.log(2.0)))
    stars = rng.uniform(30, 226, (12, 2))
    for x, y in stars:
        data += (
            600_000.0 / (2 * math.pi * sigma**2) * np.exp(-((xx - x) ** 2 + (yy - y) ** 2) / (2 * sigma**2))
        )
    rows, cols = rng.integers(0, 256, (2, 20))
    data[rows, cols] += rng.uniform(1000.0, 3000.0, 20)
    return data, stars


def _median_width(data: np.ndarray, *, leave_out_defects: bool) -> float:
    """What PhotometryFocusMeasure does with a frame: median FWHM of stars with a 10-sigma peak."""
    background = estimate_background(data.copy())
    catalog = detect_sources_sep(data.copy(), threshold=5.0)
    defects = point_defects(data - background.level, catalog["x"], catalog["y"], catalog["peak"])
    return photometry_width(
        catalog["fwhm"],
        catalog["flags"],
        catalog["peak"],
        noise=background.global_rms,
        defects=defects if leave_out_defects else None,
    )


@pytest.mark.parametrize("fwhm", [3.0, 10.0])
def test_hot_pixels_are_left_out_of_the_median_width(fwhm: float) -> None:
    data, stars = _frame_with_stars_and_hot_pixels(fwhm)
    # With them, the hot pixels outnumber the stars and the median is a hot pixel's width.
    assert _median_width(data, leave_out_defects=False) < 0.9 * fwhm
    raw = detect_sources_sep(data.copy(), threshold=5.0)
    xy = np.column_stack([raw["x"], raw["y"]])
    on_star = np.min(np.hypot(*(xy[:, None, :] - stars[None, :, :]).transpose(2, 0, 1)), axis=1) < 2.0
    assert _median_width(data, leave_out_defects=True) == pytest.approx(
        np.median(raw["fwhm"][on_star]), rel=0.02
    )
