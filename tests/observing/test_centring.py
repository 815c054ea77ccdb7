"""Centring on the simulated mount (in-process comm, virtual time): a chosen pixel, the default
5" tolerance, the report, the one error when the tolerance is not reached, and bad input."""

from __future__ import annotations

from typing import Any

import pytest

from nightcrew.errors import ConfigError, InterfaceError, InvalidArgumentError
from nightcrew.images import Image
from nightcrew.modules.pointing import Acquisition, AcquisitionFailedError
from nightcrew.modules.sim import SimCamera
from nightcrew.testing import Observatory
from tests.modules.sim_observatory import PLEIADES

from .conftest import ObservatoryFactory
from .pointing_sim import start_pointing_observatory
from .test_acquisition import STEADY, acquisition_pipeline

#: A realistic miss after a slew: 1' RMS per axis (the simulated mount's default).
MOUNT = {"pointing_error": 1.0, "seed": 7, **STEADY}


async def _acquisition(obs: Observatory, **options: Any) -> Acquisition:
    await obs.start(
        Acquisition,
        "acquisition",
        camera="camera",
        telescope="mount",
        pipeline=acquisition_pipeline(),
        **options,
    )
    return obs.module("acquisition", Acquisition)


async def test_the_target_lands_on_the_chosen_pixel_within_5_arcsec(
    observatory_at: ObservatoryFactory,
) -> None:
    async with observatory_at() as obs:
        await start_pointing_observatory(obs, mount=MOUNT)
        acquisition = await _acquisition(obs, target_pixel=[300.0, 700.0])
        result = await acquisition.acquire_target()
        assert result["iterations"] <= 2 and result["offset"] < 5.0
        assert len(result["offsets"]) == result["iterations"] and result["offsets"][0] > 5.0
        # The truth, from a frame the acquisition did not take: the target's star field sits there.
        camera = obs.module("camera", SimCamera)
        filename = await camera.grab_data(broadcast=False)
        image = await acquisition_pipeline()(await Image.from_vfs(obs.vfs, filename))
        x, y = image.sky_to_pixel(*PLEIADES)
        assert abs(float(x) - 300.0) * 1.16 < 5.0 and abs(float(y) - 700.0) * 1.16 < 5.0


async def test_an_unreached_tolerance_is_one_error_with_the_last_offset(
    observatory_at: ObservatoryFactory,
) -> None:
    async with observatory_at() as obs:
        await start_pointing_observatory(obs, mount=MOUNT)
        acquisition = await _acquisition(obs, max_iterations=1)
        with pytest.raises(
            AcquisitionFailedError, match=r'target still \d+\.\d" off after 1 iterations \(tolerance 5"; '
        ):
            await acquisition.acquire_target()


async def test_a_target_pixel_outside_the_frame_moves_nothing(observatory_at: ObservatoryFactory) -> None:
    async with observatory_at() as obs:
        _, mount = await start_pointing_observatory(obs, mount=MOUNT)
        acquisition = await _acquisition(obs, target_pixel=[1500.0, 10.0])
        with pytest.raises(
            InvalidArgumentError, match=r"target_pixel \(1500, 10\) is outside the 1024x1024 frame"
        ):
            await acquisition.acquire_target()
        assert await mount.get_offsets_radec() == (0.0, 0.0)


async def test_sync_needs_a_mount_that_syncs(observatory_at: ObservatoryFactory) -> None:
    async with observatory_at() as obs:
        await start_pointing_observatory(obs, mount=MOUNT)
        acquisition = await _acquisition(obs, method="sync")
        with pytest.raises(InterfaceError, match=r"method: sync needs a telescope that syncs \(ISyncRaDec\)"):
            await acquisition.acquire_target()


@pytest.mark.parametrize(
    ("options", "message"),
    [
        ({"tolerance": 0.0}, r"key 'tolerance'.*tolerance must be > 0 arcsec, got 0.0"),
        ({"tolerance": -1.0}, r"tolerance must be > 0 arcsec"),
        ({"target_pixel": [-1.0, 20.0]}, r"key 'target_pixel'.*target_pixel \(-1, 20\) is outside the frame"),
        ({"target_pixel": [1.0]}, r"target_pixel must be two numbers"),
        ({"method": "nudge"}, r"key 'method'.*method must be 'offset' or 'sync', got 'nudge'"),
        ({"max_iterations": 0}, r"max_iterations must be >= 1"),
    ],
)
def test_bad_centring_options_fail_when_built(options: dict[str, Any], message: str) -> None:
    with pytest.raises(ConfigError, match=message):
        Acquisition(name="acquisition", camera="camera", pipeline=acquisition_pipeline(), **options)
