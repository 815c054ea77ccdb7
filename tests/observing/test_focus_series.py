"""AutoFocusSeries on the simulated observatory: the true focus comes from SimFocuser's truth."""

from __future__ import annotations

import asyncio
import math

import numpy as np
import pytest

from nightcrew.errors import AbortedError, InvalidArgumentError
from nightcrew.events import FocusFoundEvent
from nightcrew.focus.series import (
    FocusOutsideSeriesError,
    FocusSeriesError,
    fit_focus_hyperbola,
    projection_width,
    series_positions,
)
from nightcrew.modules.focus.series import AutoFocusSeries, ProjectionFocusMeasure
from nightcrew.modules.sim import SimCamera, SimFocuser, SimRoof
from nightcrew.testing import Observatory
from tests.modules.sim_observatory import start_observatory

from .conftest import ObservatoryFactory

#: 100x: a 9-frame series of 2 s exposures takes ~25 s of clock time, well under a second of wall time.


async def focus_setup(
    obs: Observatory, start_focus: float, **options: object
) -> tuple[SimCamera, SimFocuser]:
    camera = await start_observatory(obs)
    # A 512² window of the 1.16"/px chip: sharp stars sampled well enough, a quarter of the pixels.
    await camera.set_window(256, 256, 512, 512)
    focuser = obs.module("focuser", SimFocuser)
    await focuser.set_focus(start_focus)
    await obs.start(AutoFocusSeries, "autofocus", camera="camera", focuser="focuser", **options)
    return camera, focuser


# --- pure analysis ---------------------------------------------------------------------------------


def test_hyperbola_fit_recovers_the_minimum_with_an_honest_error() -> None:
    rng = np.random.default_rng(1)
    focus = np.linspace(24.8, 25.2, 9)
    truth = 25.037
    width = np.hypot(2.0, 25.0 * (focus - truth)) + rng.normal(0.0, 0.05, focus.size)
    fit = fit_focus_hyperbola(focus.tolist(), width.tolist())
    assert fit.focus == pytest.approx(truth, abs=3 * fit.error)
    assert 0 < fit.error < 0.01
    assert fit.min_width == pytest.approx(2.0, abs=0.2)


def test_hyperbola_fit_refuses_a_minimum_outside_the_series() -> None:
    focus = [25.2, 25.25, 25.3, 25.35, 25.4]
    width = [math.hypot(2.0, 25.0 * (f - 25.0)) for f in focus]
    with pytest.raises(
        FocusOutsideSeriesError, match=r"best focus 25\.0.* outside the series 25\.2000\.\.25\.4000"
    ):
        fit_focus_hyperbola(focus, width)


def test_hyperbola_fit_needs_enough_frames() -> None:
    with pytest.raises(FocusSeriesError, match="only 3 usable frames, need at least 4"):
        fit_focus_hyperbola([1.0, 2.0, 3.0, 4.0], [2.0, 1.0, 2.0, math.nan])


def test_projection_width_follows_the_star_width_of_a_field() -> None:
    rng = np.random.default_rng(2)
    yy, xx = np.indices((256, 256), dtype=np.float64)
    widths = []
    for fwhm in (3.0, 8.0):
        sigma = fwhm / 2.3548
        image = rng.normal(100.0, 3.0, (256, 256))
        for x, y in rng.uniform(20, 236, (15, 2)):
            image += 2000.0 * np.exp(-((xx - x) ** 2 + (yy - y) ** 2) / (2 * sigma**2))
        widths.append(projection_width(image))
    # Stars sharing a row or column widen the autocorrelation peak somewhat (more so when wide).
    assert widths[0] == pytest.approx(3.0, rel=0.25)
    assert widths[1] == pytest.approx(8.0, rel=0.4)


# --- on the simulated observatory ------------------------------------------------------------------


def test_a_series_near_an_end_of_the_range_is_shifted_inside_it_whole() -> None:
    assert series_positions(25.0, 5, 0.1) == pytest.approx([24.8, 24.9, 25.0, 25.1, 25.2])
    assert series_positions(25.0, 5, 0.1, (0.0, 50.0)) == pytest.approx([24.8, 24.9, 25.0, 25.1, 25.2])
    top = series_positions(50.0, 7, 0.05, (0.0, 50.0))
    assert top == pytest.approx([49.7, 49.75, 49.8, 49.85, 49.9, 49.95, 50.0]) and max(top) <= 50.0
    assert series_positions(0.05, 3, 0.1, (0.0, 50.0)) == pytest.approx([0.0, 0.1, 0.2])
    with pytest.raises(FocusSeriesError, match=r"spans 0\.8 mm, more than the focuser's range 0\.\.0\.5 mm"):
        series_positions(0.25, 9, 0.1, (0.0, 0.5))


async def test_a_focuser_resting_at_its_end_gets_a_full_series_and_the_focus(
    observatory_at: ObservatoryFactory,
) -> None:
    async with observatory_at() as obs:
        camera = await start_observatory(obs, focuser="edge")
        await camera.set_window(256, 256, 512, 512)
        # A focuser that stops 0.1 mm past best focus and rests there: the series shifts down whole.
        edge = await obs.start(SimFocuser, "edge", focus=25.1, best_focus=25.0, max_focus=25.1)
        autofocus = await obs.start(AutoFocusSeries, "autofocus", camera="camera", focuser="edge")
        focus, _ = await autofocus.auto_focus(9, 0.04, 2.0)
        positions = [position for position, _ in (await autofocus.auto_focus_status())["measurements"]]
        assert positions == pytest.approx([24.78 + 0.04 * i for i in range(9)]) and max(positions) <= 25.1
        assert focus == pytest.approx(await edge.get_best_focus(), abs=0.02 * 0.32)


async def test_nine_frames_find_the_true_focus_within_two_percent_of_the_range(
    observatory_at: ObservatoryFactory,
) -> None:
    async with observatory_at() as obs:
        _, focuser = await focus_setup(obs, 25.07)
        found: list[FocusFoundEvent] = []

        async def on_focus(event: FocusFoundEvent, sender: str) -> bool:
            found.append(event)
            return True

        await focuser.comm.register_event(FocusFoundEvent, on_focus)
        autofocus = obs.module("autofocus", AutoFocusSeries)
        count, step = 9, 0.04
        focus, error = await autofocus.auto_focus(count, step, 2.0)
        truth = await focuser.get_best_focus()
        series_range = (count - 1) * step
        deviation = abs(focus - truth) / series_range
        print(
            f"auto-focus: {focus:.4f} ± {error:.4f} mm, true {truth:.4f} mm: {100 * deviation:.2f} % of range"
        )
        assert deviation < 0.02
        assert 0 < error < 0.02
        assert await focuser.get_focus() == pytest.approx(focus, abs=1e-6)  # moved to best focus
        for _ in range(20):
            if found:
                break
            await asyncio.sleep(0.01)
        assert found and found[0].focus == pytest.approx(focus) and found[0].filter_name == "V"
        status = await autofocus.auto_focus_status()
        assert status["done"] == count and not status["running"]


async def test_projection_measure_finds_focus_too(observatory_at: ObservatoryFactory) -> None:
    async with observatory_at() as obs:
        _, focuser = await focus_setup(obs, 24.95, measure=ProjectionFocusMeasure())
        autofocus = obs.module("autofocus", AutoFocusSeries)
        focus, _ = await autofocus.auto_focus(9, 0.04, 2.0)
        deviation = abs(focus - await focuser.get_best_focus()) / 0.32
        print(f"auto-focus (projection): {100 * deviation:.2f} % of range")
        assert deviation < 0.03


async def test_a_series_beside_focus_is_refused_and_the_focus_restored(
    observatory_at: ObservatoryFactory,
) -> None:
    async with observatory_at() as obs:
        _, focuser = await focus_setup(obs, 25.3)
        autofocus = obs.module("autofocus", AutoFocusSeries)
        # The far frames of 1 s show too few stars to measure: the usable series ends before 25.38.
        with pytest.raises(FocusOutsideSeriesError, match=r"outside the series 25\.2200\.\.25\.3[0-8]00"):
            await autofocus.auto_focus(9, 0.02, 1.0)
        assert await focuser.get_focus() == pytest.approx(25.3)


async def test_a_series_without_stars_ends_early_and_says_why_its_frames_gave_no_width(
    observatory_at: ObservatoryFactory,
) -> None:
    async with observatory_at() as obs:
        _, focuser = await focus_setup(obs, 25.0)
        await obs.module("roof", SimRoof).close_roof()  # dark frames: nothing to measure
        autofocus = obs.module("autofocus", AutoFocusSeries)
        # 4 of 7 frames without a width leave fewer than the fit's 4: the last 3 are not taken.
        reason = r"4 of 4 frames gave no width: fewer than 4 of 7 can \(frames without a width: 4 x .*stars"
        with pytest.raises(FocusSeriesError, match=reason):
            await autofocus.auto_focus(7, 0.05, 1.0)
        assert (await autofocus.auto_focus_status())["done"] == 4
        assert await focuser.get_focus() == pytest.approx(25.0)


async def test_abort_ends_the_series_and_restores_the_focus(observatory_at: ObservatoryFactory) -> None:
    async with observatory_at() as obs:
        _, focuser = await focus_setup(obs, 25.05)
        autofocus = obs.module("autofocus", AutoFocusSeries)
        series = asyncio.ensure_future(autofocus.auto_focus(9, 0.04, 5.0))
        for _ in range(500):  # two frames of 5 s: about 0.1 s of wall time
            if (await autofocus.auto_focus_status()).get("done", 0) >= 2:
                break
            await asyncio.sleep(0.01)
        await autofocus.abort()
        with pytest.raises(AbortedError, match="aborted on request"):
            await series
        assert await focuser.get_focus() == pytest.approx(25.05)


@pytest.mark.parametrize(("count", "step", "exposure"), [(3, 0.1, 1.0), (9, 0.0, 1.0), (9, 0.1, -1.0)])
async def test_bad_arguments_are_refused(
    observatory: Observatory, count: int, step: float, exposure: float
) -> None:
    autofocus = await observatory.start(AutoFocusSeries, "autofocus", camera="camera", focuser="focuser")
    with pytest.raises(InvalidArgumentError, match="must be"):
        await autofocus.auto_focus(count, step, exposure)
