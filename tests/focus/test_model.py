"""FocusModel on the simulated observatory: learns SimFocuser's temperature drift from FocusFoundEvents."""

from __future__ import annotations

import asyncio
import logging
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from nightcrew.errors import ConfigError, ModuleError
from nightcrew.events import FocusFoundEvent
from nightcrew.modules import Module
from nightcrew.modules.focus import FocusModel
from nightcrew.modules.sim import SimFilterWheel, SimFocuser, SimWeatherStation
from nightcrew.testing import Observatory
from nightcrew.vfs import LocalFile, VirtualFileSystem

#: Ambient temperatures of the simulated night, one plateau of PLATEAU seconds each.
TEMPERATURES = [18.0, 4.0, 12.0, -3.0, 9.0, 15.0, 0.0, 6.0, -6.0, 11.0]
PLATEAU = 600.0
NOISE_MM = 0.004  # scatter of the focus series' results

MODEL: dict[str, Any] = {
    "focuser": "focuser",
    "model": "a*temp + b",
    "coefficients": {"a": 0.0, "b": 20.0},  # deliberately wrong: the refit must find the truth
    "temperatures": {"temp": {"module": "weather", "weather_sensor": "temperature"}},
    "interval": None,
}


def plateau_scenario() -> list[dict[str, float]]:
    """Constant temperature for most of each plateau, so the station's polled reading is exact."""
    states: list[dict[str, float]] = []
    for index, temperature in enumerate(TEMPERATURES):
        states += [
            {"at": index * PLATEAU, "temperature": temperature},
            {"at": index * PLATEAU + 0.8 * PLATEAU, "temperature": temperature},
        ]
    return states


async def start_night(observatory: Observatory) -> tuple[SimFocuser, Module]:
    # Readings go stale after 3 polls (180 clock s, 90 ms of wall time at 2000x): ample margin.
    await observatory.start(SimWeatherStation, "weather", scenario=plateau_scenario(), interval=60.0)
    focuser = await observatory.start(
        SimFocuser, "focuser", weather_station="weather", best_focus=25.0, temperature_coefficient=-0.05,
        reference_temperature=10.0, speed=5.0, focus=24.0,
    )  # fmt: skip
    series = await observatory.start(Module, "focus-series")  # stands in for a focus series
    return focuser, series


async def until(condition: Any, seconds: float = 5.0) -> None:
    async with asyncio.timeout(seconds):
        while not condition():  # noqa: ASYNC110 - polling a module's state from outside
            await asyncio.sleep(0.005)


async def report_focus_series(
    observatory: Observatory,
    focuser: SimFocuser,
    series: Module,
    model: FocusModel,
    count: int,
    filter_name: str = "V",
    filter_offset: float = 0.0,
) -> None:
    """At the middle of each plateau, a 'focus series' reports the true best focus plus noise."""
    weather = next(m for m in observatory.modules if isinstance(m, SimWeatherStation))
    rng = np.random.default_rng(7)
    start = observatory.clock.time()
    for index in range(count):
        await observatory.clock.sleep(start + (index + 0.4) * PLATEAU - observatory.clock.time())
        await weather.read_now()  # a fresh reading, as the plateau's temperature
        truth = await focuser.get_best_focus()
        known = len(model.history)
        focus = truth + filter_offset + float(rng.normal(0, NOISE_MM))
        event = FocusFoundEvent(focus=focus, error=NOISE_MM, filter_name=filter_name)
        await series.comm.send_event(event)
        await until(lambda known=known: len(model.history) > known)


async def test_refit_from_ten_events_predicts_focus_within_one_percent_of_the_range(
    observatory: Observatory,
) -> None:
    focuser, series = await start_night(observatory)
    model = await observatory.start(FocusModel, "focusmodel", **MODEL)
    await report_focus_series(observatory, focuser, series, model, len(TEMPERATURES))

    assert [r.temperatures["temp"] for r in model.history] == pytest.approx(TEMPERATURES)
    assert model.coefficients["a"] == pytest.approx(-0.05, abs=0.002)
    assert model.coefficients["b"] == pytest.approx(25.5, abs=0.02)  # 25 + 0.05 * 10 °C
    # Prediction vs truth across the whole temperature range seen, on fresh plateaus.
    focus_range = 0.05 * (max(TEMPERATURES) - min(TEMPERATURES))  # 1.2 mm of best-focus drift
    errors = []
    for temperature in (-5.0, 2.5, 10.0, 17.0):
        values = {"temp": temperature, **model.coefficients}
        predicted = model._model.evaluate(values)
        truth = 25.0 - 0.05 * (temperature - 10.0)
        errors.append(abs(predicted - truth) / focus_range)
    assert max(errors) < 0.01, f"worst prediction error {100 * max(errors):.2f} % of the range"

    # Through the interface: predict now (last plateau, 11 °C) and move the focuser there.
    predicted = await model.get_optimal_focus()
    assert abs(predicted - await focuser.get_best_focus()) < 0.01 * focus_range
    await model.set_optimal_focus()
    assert await focuser.get_focus() == pytest.approx(predicted)


async def test_history_survives_a_restart(observatory: Observatory, tmp_path: Path) -> None:
    focuser, series = await start_night(observatory)
    vfs = VirtualFileSystem({"data": LocalFile(str(tmp_path))})
    options = {**MODEL, "history_file": "/data/focus/history.yaml", "vfs": vfs}
    first = await observatory.start(FocusModel, "focusmodel", **options)
    await report_focus_series(observatory, focuser, series, first, 6)
    fitted = first.coefficients
    await first.close()
    assert (tmp_path / "focus" / "history.yaml").is_file()

    second = await observatory.start(FocusModel, "focusmodel2", **options)
    assert second.history == first.history
    assert second.coefficients == pytest.approx(fitted)  # refitted from the loaded history
    assert second.history[0].filter_name == "V"
    assert second.history[0].time.tzinfo is not None


async def test_filter_offsets_apply_to_prediction_and_measurements(observatory: Observatory) -> None:
    focuser, series = await start_night(observatory)
    wheel = await observatory.start(SimFilterWheel, "filters", filters=["V", "R"], filter_name="R")
    options = {**MODEL, "filter_offsets": {"R": 0.3}, "filter_wheel": "filters", "min_measurements": 3}
    model = await observatory.start(FocusModel, "focusmodel", **options)
    # Focus series in R find the best focus 0.3 mm further out; the model learns the filter-free part.
    await report_focus_series(observatory, focuser, series, model, 3, filter_name="R", filter_offset=0.3)
    assert model.coefficients == pytest.approx({"a": -0.05, "b": 25.5}, abs=0.01)
    in_r = await model.get_optimal_focus()
    await wheel.set_filter("V")
    in_v = await model.get_optimal_focus()
    assert in_r - in_v == pytest.approx(0.3)
    assert in_v == pytest.approx(await focuser.get_best_focus(), abs=0.01)


async def test_missing_temperature_leaves_the_focuser_alone(
    observatory: Observatory, caplog: pytest.LogCaptureFixture
) -> None:
    focuser, _ = await start_night(observatory)
    options = {**MODEL, "temperatures": {"temp": {"module": "focuser", "sensor": "mirror"}}}
    model = await observatory.start(FocusModel, "focusmodel", **options)
    with pytest.raises(
        ModuleError,
        match=r"no value for temp \(focuser: temperature mirror: no such sensor \(it has: ambient\)\)",
    ):
        await model.set_optimal_focus()
    assert await focuser.get_focus() == 24.0
    with caplog.at_level(logging.WARNING):
        await model.on_focus_found(FocusFoundEvent(focus=25.0, error=0.01), "series")
    assert model.history == []
    assert "not stored" in caplog.text


@pytest.mark.parametrize(
    ("changes", "message"),
    [
        ({"model": "a*temp + b + c"}, r"key 'model': c in the model is neither in 'coefficients'"),
        ({"model": "exp(a*temp) + b"}, r"key 'model': model 'exp\(a\*temp\) \+ b' is not linear"),
        ({"model": "a*temp + __import__('os')"}, r"key 'model': calling '__import__' is not allowed"),
        ({"coefficients": {"a": 1.0, "b": 2.0, "z": 3.0}}, r"key 'coefficients.z': .*does not appear"),
        ({"temperatures": {"temp": {"module": "weather", "weather_sensor": "warmth"}}}, r"temperatures.temp"),
        ({"temperatures": {"temp": {"module": "weather"}}}, r"temperatures.temp.*exactly one of"),
        ({"min_measurements": 1}, r"key 'min_measurements'"),
        ({"filter_offsets": {"R": 0.1}}, r"key 'filter_wheel'"),
        ({"interval": 0}, r"key 'interval'"),
    ],
)
def test_bad_configuration_names_the_key(changes: dict[str, Any], message: str) -> None:
    with pytest.raises(ConfigError, match=message):
        FocusModel(name="focusmodel", **{**MODEL, **changes})


def test_a_non_linear_model_is_fine_without_refitting() -> None:
    model = FocusModel(name="m", **{**MODEL, "model": "exp(a*temp) + b", "refit": False})
    assert model.coefficients == {"a": 0.0, "b": 20.0}
