"""The imaging script on a moving target: the mount follows it along its ephemeris while exposing."""

from __future__ import annotations

from nightcrew.astro import angular_separation
from nightcrew.astro.elements import MajorBody
from nightcrew.astro.ephemeris import position_at
from nightcrew.interfaces import MotionStatus
from nightcrew.robotic.scripts import ImagingScript

from .runner_sim import ProgressLog, SimSetup, make_task, sim

__all__ = ["sim"]


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
