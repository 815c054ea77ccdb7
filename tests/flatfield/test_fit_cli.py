"""``nightcrew flats fit`` recovers the simulator's twilight from a simulated dusk's flats."""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pytest

from nightcrew.cli.main import main
from nightcrew.flatfield.fit import FlatSample, fit_exposure_function
from nightcrew.sim.sky import sky_brightness_mag, sky_electrons_per_pixel_per_second

from .sim import BIAS, BINNING, DUSK, TARGET, THROUGHPUTS, TwilightObservatory, start_flat_observatory

GAIN = 1.5  # the simulated camera's default
PIXEL_SCALE = 206264.806 * 9e-3 / 1600  # arcsec per unbinned pixel of the default optics


def true_exposure_time(h: float, throughput: float) -> float:
    """Seconds to reach the target in the middle of a 2x2-binned frame of the simulated sky."""
    sky = sky_brightness_mag(h)  # twilight and dark sky; the Moon is far fainter than twilight here
    rate = sky_electrons_per_pixel_per_second(
        sky, zero_point_mag=21.5, pixel_area_arcsec2=PIXEL_SCALE**2 * 4, throughput=throughput
    )
    return (TARGET - BIAS) * GAIN / rate


def test_the_fit_finds_a_known_function_despite_an_outlier() -> None:
    rng = np.random.default_rng(2)
    h = np.linspace(-9.0, -5.5, 20)
    exposure = np.exp(-0.9 * (h + 5.0)) * rng.uniform(0.8, 1.2, h.size)
    level = BIAS + (TARGET - BIAS) * exposure / np.exp(-0.9 * (h + 5.0)) * (1 + rng.normal(0, 0.01, h.size))
    samples = [FlatSample(*row) for row in zip(h, exposure, level, strict=True)]
    samples[5] = FlatSample(samples[5].sun_altitude, samples[5].exposure_time, 3 * TARGET)  # a cloud gap
    fit = fit_exposure_function(samples, TARGET, BIAS)
    assert fit.slope == pytest.approx(-0.9, abs=0.01)
    assert fit.offset == pytest.approx(5.0, abs=0.03)
    assert fit.rejected == 1
    assert fit.expression == f"exp({fit.slope:.4f}*(h + {fit.offset:.3f}))"


def test_fit_needs_a_range_of_altitudes() -> None:
    with pytest.raises(ValueError, match="same solar altitude"):
        fit_exposure_function([FlatSample(-6.0, 1.0, 20000.0)] * 4, TARGET, BIAS)
    with pytest.raises(ValueError, match="at least 3 flats"):
        fit_exposure_function([FlatSample(-6.0, 1.0, 500.0)] * 4, TARGET, BIAS)


async def test_flats_fit_recovers_the_simulated_twilight_and_plots_it(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    # A long dusk series in V (T_max 6 s: about 2° of solar altitude), on the virtual clock.
    obs = TwilightObservatory(DUSK, tmp_path / "night")
    try:
        flatfield = await start_flat_observatory(obs, max_exposure=6.0)
        count, _ = await flatfield.flat_field(500, BINNING, "V")
    finally:
        await obs.close()
    assert count >= 20

    plot = tmp_path / "fit.png"
    assert main(["flats", "fit", str(tmp_path / "night"), "--plot", str(plot)]) == 0
    out = capsys.readouterr().out
    match = re.search(r'V: \{"2x2": "exp\((-[\d.]+)\*\(h \+ ([\d.]+)\)\)"\}', out)
    assert match, out
    slope, offset = float(match.group(1)), float(match.group(2))
    # The simulator's sky fades 1 mag per degree: ln t grows 0.4 ln 10 = 0.921 per degree of depression.
    assert slope == pytest.approx(-0.4 * math.log(10), rel=0.04)
    for h in (-7.5, -6.5, -5.6):
        fitted = math.exp(slope * (h + offset))
        # The median pixel sees a few % less than the centre (vignetting): 10 % tolerance.
        assert fitted == pytest.approx(true_exposure_time(h, THROUGHPUTS["V"]), rel=0.1)
    assert plot.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert plot.stat().st_size > 10_000


def test_flats_fit_without_flats_is_one_clear_error(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    assert main(["flats", "fit", str(tmp_path)]) == 1
    assert "no usable sky flats under" in capsys.readouterr().err
    assert main(["flats", "fit", str(tmp_path / "missing")]) == 2
