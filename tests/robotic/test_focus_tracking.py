"""Focus series run on a tracked field: the mastermind's own (at dusk, after the flats) and AUTO_FOCUS tasks.

A probe stands in for the focus module and asks the simulated telescope, at the start and the end of
its series, whether it tracks and where it really points (ISimTelescopeTruth). A telescope left at
an alt/az position (as by the flat-field pointing) lets the sky drift by 15"/s, 0.1° in a 30 s series.
"""

from __future__ import annotations

from dataclasses import dataclass
from datetime import timedelta
from typing import Any

import numpy as np

from nightcrew.astro import angular_separation, radec_to_altaz
from nightcrew.astro.star_fields import StarFieldRules
from nightcrew.focus import FocusSeriesError
from nightcrew.interfaces import IAutoFocus, ITelescope, MotionStatus
from nightcrew.modules import Module
from nightcrew.modules.sim.interfaces import ISimTelescopeTruth
from nightcrew.robotic.mastermind import catalogue_stars
from nightcrew.robotic.planning import PlannedSlot
from nightcrew.robotic.scripts import AutoFocusScript
from nightcrew.robotic.tasks import TaskState
from nightcrew.testing import SITE

from .mastermind_night import Parts, group, start_mastermind, start_night
from .runner_sim import PLEIADES, ProgressLog, SimSetup, make_task, sim

__all__ = ["sim"]

SERIES_S = 30.0
#: Where the true pointing may move while tracking: drift 1"/min and 5" periodic error, with margin.
TRACKED_ARCSEC = 20.0


@dataclass(frozen=True)
class Look:
    """What the probe saw at one moment of its series."""

    t: float
    status: MotionStatus
    true_radec: tuple[float, float]


class FocusProbe(Module, IAutoFocus):
    """A stand-in focus module: each series looks at the telescope at its start and end."""

    def __init__(self, *, failures: int = 0, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.series: list[tuple[Look, Look]] = []
        self._failures = failures  # series that find no focus (as on a field with a bright star)

    async def auto_focus(self, count: int, step: float, exposure_time: float) -> tuple[float, float]:
        first = await self._look()
        await self.clock.sleep(SERIES_S)
        self.series.append((first, await self._look()))
        if len(self.series) <= self._failures:
            raise FocusSeriesError("only 2 usable frames, need at least 5")
        return 25.0, 0.01

    async def _look(self) -> Look:
        telescope = await self.proxy("telescope", ITelescope)
        truth = await self.proxy("telescope", ISimTelescopeTruth)
        return Look(self.clock.time(), await telescope.get_motion_status(), await truth.get_true_radec())

    async def auto_focus_status(self) -> dict[str, Any]:
        return {}

    async def abort(self) -> None:
        pass


def assert_tracked(first: Look, last: Look) -> None:
    moved = angular_separation(*first.true_radec, *last.true_radec) * 3600.0
    print(f'\nseries of {last.t - first.t:.0f} s: {first.status} .. {last.status}, field moved {moved:.1f}"')
    assert first.status is MotionStatus.TRACKING and last.status is MotionStatus.TRACKING
    assert moved < TRACKED_ARCSEC


async def focus_before_a_task(parts: Parts, *, failures: int) -> FocusProbe:
    """A night with one task due now, the telescope left as the flat-field pointing leaves it (alt
    80°, az 90°, not tracking) and a mastermind focusing with ``probe``; returns once the task is done."""
    site = await start_night(parts, [group(PLEIADES)], [{"at": 0, "temperature": 8.0}])
    clock = site.obs.clock
    probe = await site.obs.start(FocusProbe, "probe", failures=failures)
    await site.telescope.init()
    await site.telescope.move_altaz(80.0, 90.0)
    (task,) = site.tasks
    now = clock.now()
    await site.archive.write_schedule([PlannedSlot(task.id, now, now + timedelta(hours=1))], replace_from=now)
    await start_mastermind(site, autofocus="probe")
    start = clock.time()
    while (await site.archive.get_task(task.id)).state is not TaskState.COMPLETED:
        assert clock.time() - start < 1800, "the task did not complete"
        await clock.sleep(10.0)
    return probe


async def test_the_mastermind_focuses_on_a_tracked_field_not_where_the_flats_left_the_telescope(
    parts: Parts,
) -> None:
    probe = await focus_before_a_task(parts, failures=0)
    ((first, last),) = probe.series  # focused before the task
    assert_tracked(first, last)
    assert_a_good_field(first, near=(80.0, 90.0))


def assert_a_good_field(look: Look, near: tuple[float, float]) -> None:
    """The field of ``look`` is the catalogue's: high, near ``near`` (alt, az), with its stars."""
    rules = StarFieldRules()
    alt, az = radec_to_altaz(*look.true_radec, SITE.latitude, SITE.longitude, look.t)
    assert alt >= rules.min_altitude - 0.1
    assert angular_separation(az, alt, near[1], near[0]) <= rules.max_distance
    stars = catalogue_stars()
    bright, faint = rules.magnitudes
    cone = np.degrees(np.arccos(np.clip(stars.xyz @ _unit(*look.true_radec), -1, 1))) <= rules.radius + 0.05
    assert np.sum(cone & (stars.mag >= bright) & (stars.mag <= faint)) >= rules.min_stars


def _unit(ra: float, dec: float) -> Any:
    r, d = np.radians(ra), np.radians(dec)
    return np.array([np.cos(d) * np.cos(r), np.cos(d) * np.sin(r), np.sin(d)])


async def test_a_failed_focus_is_tried_on_another_field_before_giving_up(parts: Parts) -> None:
    probe = await focus_before_a_task(parts, failures=1)
    (failed, _), (second, last) = probe.series  # one failure, then a second field, then the task
    assert_tracked(second, last)
    assert_a_good_field(second, near=(80.0, 90.0))
    moved = angular_separation(*failed.true_radec, *second.true_radec)
    assert moved >= 2 * StarFieldRules().radius - 0.05  # another field, not the same one again


async def test_an_auto_focus_task_tracks_its_target(sim: SimSetup) -> None:
    probe = await sim.obs.start(FocusProbe, "probe")
    await sim.telescope.move_altaz(80.0, 90.0)
    runner = await sim.runner({"AUTO_FOCUS": AutoFocusScript(focus="probe")})
    focus_frames = {"exposure_time": 2.0, "exposure_count": 7}
    task = make_task({"type": "AUTO_FOCUS", "target": PLEIADES, "instrument_configs": [focus_frames]})
    await runner.run_task(task, ProgressLog())

    ((first, last),) = probe.series
    assert_tracked(first, last)
    ra, dec = PLEIADES["ra"], PLEIADES["dec"]
    assert isinstance(ra, float) and isinstance(dec, float)
    assert angular_separation(*first.true_radec, ra, dec) < 0.1  # within the pointing error of 1'


async def test_an_auto_focus_task_without_a_target_tracks_a_catalogue_field_near_the_pointing(
    sim: SimSetup,
) -> None:
    probe = await sim.obs.start(FocusProbe, "probe")
    await sim.telescope.move_altaz(80.0, 90.0)
    runner = await sim.runner({"AUTO_FOCUS": AutoFocusScript(focus="probe", field={"min_stars": 4})})
    focus_frames = {"exposure_time": 2.0, "exposure_count": 7}
    await runner.run_task(
        make_task({"type": "AUTO_FOCUS", "instrument_configs": [focus_frames]}), ProgressLog()
    )

    ((first, last),) = probe.series
    assert_tracked(first, last)
    assert_a_good_field(first, near=(80.0, 90.0))
