"""Seeing on the simulated observatory: the measured seeing matches the simulator's."""

from __future__ import annotations

import asyncio

import pytest

from nightcrew.errors import ConfigError
from nightcrew.modules.image.seeing import Seeing, zenith_seeing
from tests.modules.sim_observatory import expose, start_observatory

from .conftest import ObservatoryFactory

OPTICS_FWHM = 0.8  # the SimCamera's default optics_fwhm_arcsec


@pytest.mark.parametrize("sim_seeing", [1.5, 2.5])
async def test_seeing_matches_the_simulated_seeing(
    observatory_at: ObservatoryFactory, sim_seeing: float
) -> None:
    async with observatory_at() as obs:
        seeing = await obs.start(Seeing, "seeing", optics_fwhm=OPTICS_FWHM)
        camera = await start_observatory(obs, seeing=sim_seeing)
        await camera.set_window(256, 256, 512, 512)  # enough stars, a quarter of the pixels
        airmass = 0.0
        for _ in range(3):
            airmass = (await expose(obs, camera, 2.0)).header["AIRMASS"]
        for _ in range(100):  # the module measures after the event: give it a moment
            if len(seeing._values) == 3:
                break
            await asyncio.sleep(0.02)
        measured = seeing.seeing
        assert measured is not None
        # The simulator's seeing is along the line of sight; the module reports it at the zenith.
        expected = sim_seeing * airmass**-0.6
        error = measured / expected - 1.0
        print(f'seeing: measured {measured:.3f}", simulated {expected:.3f}" at zenith: {100 * error:+.1f} %')
        assert abs(error) < 0.10
        # The next frame carries the median.
        header = (await expose(obs, camera, 1.0)).header
        assert header["SEEING"] == pytest.approx(measured, abs=0.01)


def test_zenith_seeing_removes_optics_and_airmass() -> None:
    assert zenith_seeing(1.0, optics_fwhm=0.6) == pytest.approx(0.8)
    assert zenith_seeing(2.0, airmass=2.0) == pytest.approx(2.0 * 2.0**-0.6)
    with pytest.raises(ValueError, match="not above the optics"):
        zenith_seeing(0.5, optics_fwhm=0.8)


def test_bad_configuration_is_refused() -> None:
    with pytest.raises(ConfigError, match=r"history.*must be >= 1"):
        Seeing(name="seeing", history=0)
