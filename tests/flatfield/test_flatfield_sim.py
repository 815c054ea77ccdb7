"""Twilight flats on the simulated observatory: dusk and dawn, levels on target, pointing, abort."""

from __future__ import annotations

import asyncio
from collections.abc import AsyncIterator
from pathlib import Path

import numpy as np
import pytest
from astropy.io import fits  # type: ignore[import-untyped]

from nightcrew.astro import sun_altaz
from nightcrew.errors import AbortedError
from nightcrew.modules.flatfield import FlatFieldScheduler
from nightcrew.testing import SITE

from .sim import BINNING, DAWN, DUSK, FUNCTIONS, TARGET, TwilightObservatory, start_flat_observatory


@pytest.fixture
async def dusk(tmp_path: Path) -> AsyncIterator[TwilightObservatory]:
    obs = TwilightObservatory(DUSK, tmp_path)
    try:
        yield obs
    finally:
        await obs.close()


@pytest.fixture
async def dawn(tmp_path: Path) -> AsyncIterator[TwilightObservatory]:
    obs = TwilightObservatory(DAWN, tmp_path)
    try:
        yield obs
    finally:
        await obs.close()


def frames(directory: Path) -> list[tuple[fits.Header, float]]:
    """(header, mean level) of every flat written, in time order."""
    found = []
    for path in sorted(directory.glob("*-skyflat-*.fits")):
        with fits.open(path) as hdus:
            found.append((hdus[0].header, float(np.mean(hdus[0].data))))
    return found


async def test_a_simulated_dusk_yields_flats_on_the_target_level(dusk: TwilightObservatory) -> None:
    flatfield = await start_flat_observatory(dusk)
    count, seconds = await flatfield.flat_field(10, BINNING, "V")
    assert count == 10
    written = frames(dusk.directory)
    levels = [level for _, level in written]
    on_target = [level for level in levels if abs(level - TARGET) <= 0.1 * TARGET]
    assert len(on_target) >= 8, f"levels: {[round(x) for x in levels]}"
    assert all(abs(level - TARGET) <= 0.1 * TARGET for level in levels[1:])  # all but the test exposure
    assert float(np.mean(on_target)) == pytest.approx(TARGET, rel=0.03)
    headers = [header for header, _ in written]
    exposure_times = [h["EXPTIME"] for h in headers]
    assert exposure_times[-1] > exposure_times[1]  # the sky darkens: exposures grow
    assert seconds == pytest.approx(sum(exposure_times[-count:]), rel=1e-6)
    assert all(h["IMAGETYP"] == "skyflat" and h["FILTER"] == "V" and h["XBINNING"] == 2 for h in headers)
    # The flat-fielder wrote the Sun's altitude, which agrees with DATE-OBS at the site.
    for header in headers:
        assert -9.5 < header["SUNALT"] < -4.0
        assert header["SUNALT"] == pytest.approx(header["SIM-SUNA"], abs=0.05)
    # Opposite the Sun at 80°, dithered: no two flats at the same spot.
    positions = {(round(h["TEL-ALT"], 4), round(h["TEL-AZ"], 4)) for h in headers}
    assert len(positions) == len(headers)
    start = DUSK.timestamp()
    assert abs(headers[0]["TEL-ALT"] - 80.0) < 0.1
    assert abs((headers[0]["TEL-AZ"] - sun_altaz(SITE, start)[1]) % 360.0 - 180.0) < 2.0


async def test_a_simulated_dawn_works_in_reverse(dawn: TwilightObservatory) -> None:
    flatfield = await start_flat_observatory(dawn)
    count, _ = await flatfield.flat_field(8, BINNING, "R")
    assert count == 8
    written = frames(dawn.directory)
    levels = [level for _, level in written]
    assert sum(abs(level - TARGET) <= 0.1 * TARGET for level in levels) >= 8, levels
    exposure_times = [h["EXPTIME"] for h, _ in written]
    assert exposure_times[-1] < exposure_times[1]  # the sky brightens: exposures shrink
    assert all(h["FILTER"] == "R" for h, _ in written)


async def test_dusk_stops_when_the_sky_is_too_dark(dusk: TwilightObservatory) -> None:
    # A T_max of 2 s is passed about 7 minutes after T_min: far fewer than 100 flats.
    flatfield = await start_flat_observatory(dusk, max_exposure=2.0)
    count, _ = await flatfield.flat_field(100, BINNING, "V")
    assert 0 < count < 100
    last = frames(dusk.directory)[-1][0]
    assert last["EXPTIME"] <= 2.0


async def test_abort_stops_a_running_series(dusk: TwilightObservatory) -> None:
    flatfield = await start_flat_observatory(dusk)
    running = asyncio.create_task(flatfield.flat_field(50, BINNING, "V"))
    await dusk.wait_for(lambda: bool(frames(dusk.directory)), 600.0, message="a first flat")
    await flatfield.abort()
    with pytest.raises(AbortedError, match="flat fields aborted"):
        await running
    assert await flatfield.get_fits_header_before() == {}  # no longer running


async def test_scheduler_takes_combinations_by_priority_and_remembers(dusk: TwilightObservatory) -> None:
    await start_flat_observatory(dusk)
    state = "/cache/flats/last-taken.yaml"
    await dusk.vfs.write_yaml(state, {"R 2x2": "2024-01-14T16:30:00+00:00"})  # R yesterday, V never
    options = {
        "flatfield": "flatfield",
        "flats": [
            {"filter": "R", "binning": "2x2", "count": 3},
            {"filter": "V", "binning": "2x2", "count": 3},
        ],
        "state_file": state,
    }
    scheduler = await dusk.start(FlatFieldScheduler, "flatscheduler", **options)
    await scheduler.run()
    filters = [header["FILTER"] for header, _ in frames(dusk.directory)]
    assert filters.index("V") < filters.index("R")  # never taken goes first
    assert filters.count("V") >= 3 and filters.count("R") >= 3
    saved = await dusk.vfs.read_yaml(state)
    assert set(saved) == {"V 2x2", "R 2x2"}
    assert saved["R 2x2"].startswith("2024-01-15T16:")
    again = await dusk.start(FlatFieldScheduler, "flatscheduler2", **options)
    assert again.last_taken == scheduler.last_taken


async def test_scheduler_with_the_functions_plans_for_the_twilight(dusk: TwilightObservatory) -> None:
    await start_flat_observatory(dusk)
    options = {
        "flatfield": "flatfield",
        "flats": [
            {"filter": "V", "binning": "2x2", "count": 3},  # never taken, listed first
            {"filter": "B", "binning": "2x2", "count": 3},
        ],
        "functions": FUNCTIONS,
        "max_exposure": 30.0,
        "overhead": 5.0,
    }
    scheduler = await dusk.start(FlatFieldScheduler, "flatscheduler", **options)
    await scheduler.run()
    filters = [header["FILTER"] for header, _ in frames(dusk.directory)]
    # B needs 4x V's exposure, so its opening closes first: planned before V.
    assert filters[0] == "B" and filters.index("V") > filters.index("B")
    assert filters.count("B") >= 3 and filters.count("V") >= 3
