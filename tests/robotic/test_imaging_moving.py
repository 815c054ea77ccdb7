"""The imaging script on a moving target: the mount follows it along its ephemeris while exposing."""

from __future__ import annotations

from datetime import UTC, datetime
from typing import Any

from nightcrew.astro import angular_separation
from nightcrew.astro.elements import MajorBody
from nightcrew.astro.ephemeris import position_at
from nightcrew.interfaces import MotionStatus
from nightcrew.robotic.scripts import ImagingScript
from nightcrew.robotic.tasks import parse_request_group, tasks_of_group
from nightcrew.testing import Observatory
from nightcrew.vfs import MemoryFile

from .runner_sim import ProgressLog, SimSetup, make_task, request_group, sim, start_sim

__all__ = ["sim"]

SATELLITE: dict[str, Any] = {
    "type": "SATELLITE",
    "name": "example satellite",
    "tle_line1": "1 25544U 98067A   26314.50000000  .00009878  00000-0  18200-3 0  5083",
    "tle_line2": "2 25544  51.6498 270.0000 0003572  55.9686 274.8005 15.49815350868470",
}


async def test_jupiter_is_followed_by_rates_through_the_exposures(sim: SimSetup) -> None:
    runner = await sim.runner({"EXPOSE": ImagingScript()})
    task = make_task(
        {
            "type": "EXPOSE",
            "target": {"type": "MAJOR_BODY", "name": "jupiter"},  # about 28° up at the test epoch
            "instrument_configs": [{"exposure_time": 30.0, "exposure_count": 2}],
        }
    )
    await runner.run_task(task, ProgressLog())
    assert [h["EXPTIME"] for h in await sim.headers(2)] == [30.0, 30.0]
    assert await sim.telescope.get_motion_status() is MotionStatus.TRACKING
    ra_rate, dec_rate = await sim.telescope.get_tracking_rates()
    assert (ra_rate, dec_rate) != (0.0, 0.0)  # Jupiter's own motion, a few arcsec per minute
    where = await sim.telescope.get_radec()
    expected = position_at(MajorBody("jupiter"), sim.telescope.observatory, sim.obs.clock.time())
    assert angular_separation(*where, *expected) * 3600 < 1.0


async def test_a_satellite_task_waits_for_the_pass_and_follows_it() -> None:
    obs = Observatory(epoch="2026-11-10T18:30:00+00:00")  # the pass above 30° is 18:37:40 - 18:40:38
    try:
        setup = await start_sim(obs)
        runner = await setup.runner({"EXPOSE": ImagingScript()})
        group = request_group(
            {
                "type": "EXPOSE",
                "target": SATELLITE,
                "instrument_configs": [{"exposure_time": 2.0, "exposure_count": 3}],
            }
        )
        group["requests"][0]["windows"] = [{"start": "2026-11-10T18:15:00Z", "end": "2026-11-10T18:50:00Z"}]
        task = tasks_of_group(parse_request_group(group), "g", ["1"])[0]
        await runner.run_task(task, ProgressLog())
        starts = [datetime.fromisoformat(h["DATE-OBS"]).replace(tzinfo=UTC) for h in await setup.headers(3)]
        assert all(datetime(2026, 11, 10, 18, 37, 40, tzinfo=UTC) <= t for t in starts)
        assert all(t <= datetime(2026, 11, 10, 18, 40, 38, tzinfo=UTC) for t in starts)
        assert await setup.telescope.get_tracking_rates() != (0.0, 0.0)
    finally:
        await obs.close()
        MemoryFile.clear_shared()
