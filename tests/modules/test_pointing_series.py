"""PointingSeries on the simulated observatory: the mount's pointing errors measured by plate solving."""

from __future__ import annotations

import asyncio
import math
from typing import Any

import pytest

from nightcrew.errors import AbortedError, ConfigError
from nightcrew.images import Pipeline
from nightcrew.images.astrometry import CatalogAstrometry
from nightcrew.images.processors.detection import SepSourceDetection
from nightcrew.modules import Module
from nightcrew.modules.pointing import PointingSeries
from nightcrew.modules.pointing.series import CSV_COLUMNS, pointing_grid
from nightcrew.modules.sim import SimCamera, SimTelescope
from nightcrew.robotic.runner import TaskRunner
from nightcrew.robotic.scripts import PointingSeriesScript
from nightcrew.robotic.tasks import TaskProgress
from nightcrew.testing import SITE, Observatory
from nightcrew.testing.solver import SimulatedSkyIndexes
from tests.robotic.runner_sim import make_task

#: 1024² at 1.16"/px binned 2x2: a 20' field of 512² pixels, enough stars anywhere for a catalog solve.
DETECTOR = {"chip_width": 1024, "chip_height": 1024, "cosmic_rays_per_s": 0.0}
DEPTH, SEED = 17.0, 5


def test_grid_rows_interleave_alternate_and_leave_out_low_points() -> None:
    assert pointing_grid((30.0, 60.0), 2, 4) == [
        (30.0, 0.0),
        (30.0, 90.0),
        (30.0, 180.0),
        (30.0, 270.0),
        (60.0, 315.0),
        (60.0, 225.0),
        (60.0, 135.0),
        (60.0, 45.0),
    ]
    assert pointing_grid((10.0, 70.0), 3, 2, min_altitude=20.0) == [
        (40.0, 270.0),
        (40.0, 90.0),
        (70.0, 0.0),
        (70.0, 180.0),
    ]
    assert pointing_grid((45.0, 45.0), 1, 1) == [(45.0, 0.0)]


@pytest.mark.parametrize(
    ("options", "key"),
    [
        ({"alt_range": (60.0, 30.0)}, "alt_range"),
        ({"az_steps": 0}, "alt_steps"),
        ({"alt_range": (10.0, 15.0), "min_altitude": 20.0}, "min_altitude"),
        ({"move": "hadec"}, "move"),
    ],
)
def test_bad_grids_are_config_errors_naming_the_key(options: dict[str, Any], key: str) -> None:
    with pytest.raises(ConfigError, match=f"key '{key}'"):
        PointingSeries(name="pointing", site=SITE, **options)


async def start_series(observatory: Observatory, **options: Any) -> PointingSeries:
    telescope = await observatory.start(SimTelescope, "telescope", init_time=0.0, settle_time=1.0, seed=7)
    await telescope.init()
    camera: dict[str, Any] = {"detector": DETECTOR, "catalog_depth": DEPTH, "seed": SEED, "readout_time": 0.5}
    await observatory.start(
        SimCamera, "camera", focuser=None, filters=None, roof=None, weather=None, **camera
    )
    # The sky's index files for each field are built when its frame comes (cached across runs).
    indexes = SimulatedSkyIndexes(seed=SEED, depth=DEPTH)
    solver = Pipeline([SepSourceDetection(), indexes, CatalogAstrometry(index_dir=indexes.directory)])
    settings: dict[str, Any] = {
        "alt_range": (40.0, 70.0),
        "alt_steps": 2,
        "az_steps": 3,
        "exposure_time": 1.0,
    }
    return await observatory.start(
        PointingSeries,
        "pointing",
        solver=solver,
        filename="/cache/pointing-{time}.csv",
        **(settings | options),
    )


async def test_series_measures_the_mount_pointing_errors_within_arcseconds(observatory: Observatory) -> None:
    series = await start_series(observatory)
    path = await series.start_pointing_series()

    rows = await observatory.vfs.read_csv(path)
    assert tuple(rows[0]) == CSV_COLUMNS
    assert [(float(r["alt_cmd"]), float(r["az_cmd"])) for r in rows] == series.points
    misses, deviations = [], []
    solved = [row for row in rows if not row["error"]]
    # A frame that does not solve is a row with its reason; one field of this grid (alt 40 az 120)
    # sometimes gives just under the 10 matches a solve needs, depending on the frame's noise.
    assert len(solved) >= len(rows) - 1, [row["error"] for row in rows]
    assert all(row["error"].startswith("NoSolutionError") for row in rows if row["error"])
    for row in solved:
        header = (await observatory.vfs.read_fits(row["filename"]))[0].header
        ra_cmd, dec_cmd = float(row["ra_cmd"]), float(row["dec_cmd"])
        # The simulator's truth: where the mount really pointed (its random miss per slew).
        true_dra = (header["SIM-RA"] - ra_cmd) * math.cos(math.radians(dec_cmd)) * 3600.0
        true_ddec = (header["SIM-DEC"] - dec_cmd) * 3600.0
        assert float(row["dra"]) == pytest.approx(true_dra, abs=3.0)
        assert float(row["ddec"]) == pytest.approx(true_ddec, abs=3.0)
        assert int(row["stars"]) >= 10
        misses.append(math.hypot(true_dra, true_ddec))
        deviations.append(math.hypot(float(row["dra"]) - true_dra, float(row["ddec"]) - true_ddec))
    assert max(misses) > 30.0  # the 1' RMS miss per axis was there to be measured
    print(
        f"pointing series: {len(solved)} of {len(rows)} points solved, "
        f"true misses {min(misses):.0f}..{max(misses):.0f} arcsec, "
        f"measured within {max(deviations):.2f} arcsec of the truth"
    )


async def test_abort_keeps_the_points_measured_so_far(observatory: Observatory) -> None:
    series = await start_series(observatory, alt_steps=3, az_steps=6)
    running = asyncio.create_task(series.start_pointing_series())
    for _ in range(2000):  # until the first point is in the file
        if await observatory.vfs.find("/cache/pointing-*.csv"):
            break
        await asyncio.sleep(0.01)
    await series.abort()
    with pytest.raises(AbortedError):
        await running
    (path,) = await observatory.vfs.find("/cache/pointing-*.csv")
    assert 1 <= len(await observatory.vfs.read_csv(path)) < len(series.points)


async def test_a_script_configuration_runs_the_series_through_the_runner(observatory: Observatory) -> None:
    await start_series(observatory, alt_steps=1, az_steps=2)
    host = await observatory.start(Module, "robotic")
    script = PointingSeriesScript(pointing="pointing")
    runner = host.add_child(TaskRunner(scripts={"SCRIPT:pointing": script}))
    await runner.open()
    task = make_task({"type": "SCRIPT", "extra_params": {"script": "pointing", "duration": 600}})
    assert await runner.can_run(task)
    reports: list[TaskProgress] = []

    async def progress(done: TaskProgress) -> None:
        reports.append(done)

    await runner.run_task(task, progress)
    assert script.last_result is not None
    assert len(await observatory.vfs.read_csv(script.last_result)) == 2
