"""Acquisition on the simulated observatory: from a pointing miss of up to 10' to below 2"."""

from __future__ import annotations

import math
from typing import Any

import pytest

from nightcrew.astro import angular_separation
from nightcrew.errors import InvalidArgumentError
from nightcrew.images import Pipeline
from nightcrew.images.astrometry import CatalogAstrometry
from nightcrew.images.processors.detection import SepSourceDetection
from nightcrew.images.processors.offsets import AstrometryOffsets
from nightcrew.modules.pointing import Acquisition
from nightcrew.modules.pointing.apply import SkyError, pixel_error_to_sky
from nightcrew.testing.solver import SimulatedSkyIndexes
from tests.modules.sim_observatory import CATALOG_DEPTH, PLEIADES, SEED

from .conftest import ObservatoryFactory
from .pointing_sim import start_pointing_observatory

#: 100x: three 2 s exposures and small offsets take a few seconds of wall time at most.
#: Tracking errors off: they are the guider's job, and the ~1 s of wall time a plate solve takes
#: is 100 s on this clock, in which the periodic error alone moves the field by up to 6".
STEADY = {"drift_rate": 0.0, "periodic_amplitude": 0.0}


def acquisition_pipeline() -> Pipeline:
    # The index files of the sky the simulator renders (the camera's depth and seed), built for the
    # field when its first frame comes (cached across runs).
    indexes = SimulatedSkyIndexes(seed=SEED, depth=CATALOG_DEPTH)
    return Pipeline(
        [SepSourceDetection(), indexes, CatalogAstrometry(index_dir=indexes.directory), AstrometryOffsets()]
    )


@pytest.mark.parametrize(("pointing_error", "seed"), [(5.8, 15), (4.0, 2)])
async def test_acquisition_converges_from_a_large_miss(
    observatory_at: ObservatoryFactory, pointing_error: float, seed: int
) -> None:
    async with observatory_at() as obs:
        _, mount = await start_pointing_observatory(
            obs, mount={"pointing_error": pointing_error, "seed": seed, **STEADY}
        )
        await obs.start(
            Acquisition,
            "acquisition",
            camera="camera",
            telescope="mount",
            pipeline=acquisition_pipeline(),
            tolerance=2.0,
            max_iterations=5,
        )
        acquisition = obs.module("acquisition", Acquisition)
        start_miss = angular_separation(*await mount.get_true_radec(), *PLEIADES) * 60.0
        result: dict[str, Any] = await acquisition.acquire_target()
        final = angular_separation(*await mount.get_true_radec(), *PLEIADES) * 3600.0
        print(
            f"acquisition: miss {start_miss:.2f}' -> {final:.2f}\" (true) "
            f"in {result['iterations']} iterations; measured "
            f'{", ".join(f"{d:.1f}" for d in result["offsets"])}"'
        )
        assert 2.0 < start_miss <= 10.0
        assert result["iterations"] <= 3
        assert result["offset"] < 2.0
        assert final < 2.0


async def test_acquisition_refuses_an_offset_above_the_maximum(observatory_at: ObservatoryFactory) -> None:
    async with observatory_at() as obs:
        _, mount = await start_pointing_observatory(obs, mount={"pointing_error": 7.0, "seed": 15, **STEADY})
        await obs.start(
            Acquisition,
            "acquisition",
            camera="camera",
            telescope="mount",
            pipeline=acquisition_pipeline(),
            max_offset=120.0,
        )
        acquisition = obs.module("acquisition", Acquisition)
        with pytest.raises(
            InvalidArgumentError, match=r"measured offset \d+\.\d\" exceeds max_offset 120\": not applied"
        ):
            await acquisition.acquire_target()
        assert await mount.get_offsets_radec() == (0.0, 0.0)


def test_pixel_offsets_become_sky_offsets_with_the_sim_orientation() -> None:
    # North up, east left: stars moving right (+x) mean the telescope points east of its target.
    error = pixel_error_to_sky(2.0, 0.0, 1.5)
    assert error == SkyError(pytest.approx(3.0), pytest.approx(0.0))  # type: ignore[arg-type]
    assert pixel_error_to_sky(0.0, 2.0, 1.5).north == pytest.approx(-3.0)
    turned = pixel_error_to_sky(2.0, 0.0, 1.0, position_angle=90.0)
    assert turned.north == pytest.approx(-2.0) and abs(turned.east) < 1e-12
    assert math.isclose(SkyError(3.0, 4.0).limited(1.0).distance, 1.0)
