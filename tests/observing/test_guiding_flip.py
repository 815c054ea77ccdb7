"""Guiding on a German-equatorial mount: the field turns half round on the other side of the pier,
so a guider working in pixels turns its calibration with the mount's side (``pier_side``)."""

from __future__ import annotations

import asyncio

import pytest

from nightcrew.astro import local_sidereal_time
from nightcrew.astro.pier import hour_angle
from nightcrew.errors import ConfigError
from nightcrew.images import Pipeline
from nightcrew.images.processors.offsets import NStarOffsets
from nightcrew.interfaces import LoopState, PierSide
from nightcrew.modules.pointing import ScienceFrameAutoGuiding
from nightcrew.modules.pointing.guiding import position_angle_on_side
from nightcrew.testing import SITE

from .conftest import ObservatoryFactory
from .pointing_sim import start_pointing_observatory
from .test_guiding import wait_for_state

DEC = 24.0
GEM = {"east": -120.0, "west": 120.0, "counterweight_up": 15.0}
BUMP = 4.0  # arcsec north, behind the guider's back


def test_the_calibration_turns_half_round_on_the_other_side() -> None:
    assert position_angle_on_side(10.0, PierSide.EAST, PierSide.EAST) == 10.0
    assert position_angle_on_side(10.0, PierSide.EAST, PierSide.WEST) == 190.0
    assert position_angle_on_side(270.0, PierSide.WEST, PierSide.EAST) == 90.0
    assert position_angle_on_side(10.0, PierSide.EAST, PierSide.UNKNOWN) == 10.0


def test_a_pier_side_that_is_no_side_is_a_config_error() -> None:
    with pytest.raises(ConfigError, match=r"key 'pier_side': must be east or west, got 'north'"):
        ScienceFrameAutoGuiding(
            name="guiding", camera="camera", pipeline=Pipeline([NStarOffsets()]), pier_side="north"
        )


def _ra_at_hour_angle(now: float, ha: float) -> float:
    ra = (local_sidereal_time(now, SITE.longitude) - ha) % 360.0
    return (ra + hour_angle(ra, DEC, SITE.longitude, now) - ha) % 360.0


async def _correction_after_bump(
    observatory_at: ObservatoryFactory, ha: float, pier_side: str | None
) -> tuple[PierSide, float]:
    """The mount's side at hour angle ``ha`` and the north offset (arcsec) the guider leaves after
    one frame that shows a bump of :data:`BUMP` north (0 when it corrects it all, more than
    BUMP when it pushes the wrong way)."""
    async with observatory_at() as obs:
        camera, mount = await start_pointing_observatory(obs, mount={"seed": 4, "gem": GEM})
        await mount.move_radec(_ra_at_hour_angle(obs.clock.time(), ha), DEC)
        await camera.set_window(256, 256, 512, 512)
        guiding = await obs.start(
            ScienceFrameAutoGuiding,
            "guiding",
            camera="camera",
            telescope="mount",
            pipeline=Pipeline([NStarOffsets()]),
            gain=1.0,
            max_error=10.0,
            pier_side=pier_side,
        )
        await guiding.start()
        await camera.set_exposure_time(2.0)
        await camera.grab_data()  # the reference
        await wait_for_state(guiding, LoopState.CLOSED)
        dra, ddec = await mount.get_offsets_radec()
        await mount.set_offsets_radec(dra, ddec + BUMP / 3600.0)
        await camera.grab_data()
        for _ in range(1000):  # the correction follows the frame's event (wall seconds, bounded)
            if (await mount.get_offsets_radec())[1] != pytest.approx(ddec + BUMP / 3600.0):
                break
            await asyncio.sleep(0.01)
        left = ((await mount.get_offsets_radec())[1] - ddec) * 3600.0
        await guiding.stop()
        return await mount.get_pier_side(), left


@pytest.mark.parametrize("ha", [-15.0, 15.0])
async def test_the_guider_corrects_on_either_side_of_the_pier(
    observatory_at: ObservatoryFactory, ha: float
) -> None:
    side, left = await _correction_after_bump(observatory_at, ha, "east")
    assert side is (PierSide.WEST if ha < 0 else PierSide.EAST)
    assert abs(left) < 1.0, left  # the bump corrected to within the stars' measurement


async def test_a_guider_that_ignores_the_flip_pushes_the_wrong_way(
    observatory_at: ObservatoryFactory,
) -> None:
    side, left = await _correction_after_bump(observatory_at, -15.0, None)
    assert side is PierSide.WEST
    assert left > 1.5 * BUMP, left  # the field upside down: the error doubled instead of cancelled
