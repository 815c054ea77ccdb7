"""AlpacaDome and AlpacaRoof against alpaca-simulators' Dome devices: the roof and dome contracts,
following an off-centre telescope, and a dome that cannot turn.

alpaca-simulators' shutter arrives as ``OpenShutter``/``CloseShutter`` return, so no opening can be
interrupted there; the contract tests that interrupt an opening are replaced below by the same
checks on the dome's rotation, which takes the simulator 4 s.
"""

from __future__ import annotations

import asyncio
from collections.abc import AsyncIterator, Iterator
from pathlib import Path
from typing import Any

import pytest

from nightcrew.bridges.alpaca import AlpacaClient
from nightcrew.clock import RealClock
from nightcrew.errors import AbortedError, ConfigError
from nightcrew.interfaces import IDome, ModuleState, MotionStatus
from nightcrew.modules.alpaca.dome import AlpacaDome
from nightcrew.modules.alpaca.roof import AlpacaRoof
from nightcrew.modules.roof import DomeGeometry, azimuth_difference, slit_azimuth
from nightcrew.modules.sim import SimTelescope
from nightcrew.testing import ContractProbe, ContractSetup, DomeContract, Observatory, RoofContract

from .more_devices import DOME, ROLL_OFF_ROOF, start_with_more_devices


@pytest.fixture(scope="module")
def alpaca_server(tmp_path_factory: pytest.TempPathFactory, alpaca_star_table: Path) -> Iterator[str]:
    """A private simulator with the extra devices (see more_devices), for this file's tests."""
    with start_with_more_devices(tmp_path_factory.mktemp("alpaca-more"), alpaca_star_table) as simulator:
        yield simulator.url


async def _turn_until_interrupted(contract: ContractSetup[Any], target: float) -> asyncio.Task[None]:
    dome = await contract.proxy(IDome)
    turning = asyncio.ensure_future(dome.move_azimuth(target))
    await contract.wait_for(
        lambda: contract.module._rotation.busy or turning.done(), 30.0, "the dome to start turning"
    )
    assert not turning.done(), "the simulator's 4 s turn ended before it could be interrupted"
    return turning


class TestAlpacaDomeContract(DomeContract):
    @pytest.fixture
    async def contract(self, alpaca_server: str) -> AsyncIterator[ContractSetup[Any]]:
        async with Observatory(clock=RealClock()) as obs:
            probe = await obs.start(ContractProbe, "probe")
            dome = await obs.start(AlpacaDome, "dome", server=alpaca_server, device_number=DOME)
            yield ContractSetup(dome, probe)

    async def test_opening_twice_is_busy_and_closing_aborts_an_opening(
        self, contract: ContractSetup[Any]
    ) -> None:
        # The simulator's shutter cannot be caught opening; a newer turn replaces a running one.
        start = await contract.module.get_azimuth()
        turning = await _turn_until_interrupted(contract, (start + 90.0) % 360.0)
        target = (start + 10.0) % 360.0
        await (await contract.proxy(IDome)).move_azimuth(target)
        await self._expect_aborted(turning)
        assert abs(azimuth_difference(await contract.module.get_azimuth(), target)) < self.azimuth_tolerance

    async def test_stop_motion_stops_an_opening_roof(self, contract: ContractSetup[Any]) -> None:
        # The same on the rotation: stop_motion aborts the turn and the device stops slewing.
        start = await contract.module.get_azimuth()
        turning = await _turn_until_interrupted(contract, (start + 90.0) % 360.0)
        await (await contract.proxy(IDome)).stop_motion("azimuth")
        await self._expect_aborted(turning)
        assert await contract.module.device.get("slewing") is False
        assert abs(azimuth_difference(await contract.module.get_azimuth(), start)) < self.azimuth_tolerance


class TestAlpacaRoofContract(RoofContract):
    @pytest.fixture
    async def contract(self, alpaca_server: str) -> AsyncIterator[ContractSetup[Any]]:
        async with Observatory(clock=RealClock()) as obs:
            probe = await obs.start(ContractProbe, "probe")
            roof = await obs.start(AlpacaRoof, "roof", server=alpaca_server, device_number=ROLL_OFF_ROOF)
            yield ContractSetup(roof, probe)

    async def test_opening_twice_is_busy_and_closing_aborts_an_opening(
        self, contract: ContractSetup[Any]
    ) -> None:
        await self._shutter_arrives_at_once(contract)

    async def test_stop_motion_stops_an_opening_roof(self, contract: ContractSetup[Any]) -> None:
        await self._shutter_arrives_at_once(contract)

    async def _shutter_arrives_at_once(self, contract: ContractSetup[Any]) -> None:
        # Why the two tests above cannot apply here: the simulator's shutter is open as soon as
        # OpenShutter returns. Should it ever move slowly, this fails and the tests apply again.
        roof = await self._closed(contract)
        device = contract.module.device
        await device.put("openshutter")
        assert await device.get("shutterstatus") == 0
        await device.put("closeshutter")
        assert await device.get("shutterstatus") == 1
        await roof.stop_motion()  # AbortSlew on a roof at rest is accepted and changes nothing
        assert await roof.get_motion_status() is MotionStatus.PARKED


async def test_roof_starts_with_the_state_the_shutter_is_in(alpaca_server: str) -> None:
    async with AlpacaClient(alpaca_server) as client:
        device = client.device("dome", ROLL_OFF_ROOF)
        await device.put("openshutter")
        async with Observatory(clock=RealClock()) as obs:
            roof = await obs.start(AlpacaRoof, "roof", server=alpaca_server, device_number=ROLL_OFF_ROOF)
            assert await roof.get_motion_status() is MotionStatus.IDLE
            await roof.close_roof()
            assert await device.get("shutterstatus") == 1


async def test_roof_opened_by_hand_is_still_closed_by_close_roof(alpaca_server: str) -> None:
    # Fail safe: the module believes the roof closed, someone opened it at the controller.
    async with Observatory(clock=RealClock()) as obs:
        roof = await obs.start(AlpacaRoof, "roof", server=alpaca_server, device_number=ROLL_OFF_ROOF)
        await roof.close_roof()
        await roof.device.put("openshutter")
        assert await roof.get_motion_status() is MotionStatus.PARKED  # what it last knew
        await roof.close_roof()
        assert await roof.device.get("shutterstatus") == 1
        await roof.device.put("openshutter")
        await roof.open_roof()  # already open: nothing to do, and it knows it is open now
        assert await roof.get_motion_status() is MotionStatus.IDLE
        await roof.device.put("closeshutter")
        await roof.open_roof()  # closed by hand meanwhile: opens it
        assert await roof.device.get("shutterstatus") == 0
        await roof.close_roof()


async def test_dome_refuses_a_device_that_cannot_turn(alpaca_server: str) -> None:
    async with Observatory(clock=RealClock()) as obs:
        dome = await obs.start(AlpacaDome, "dome", server=alpaca_server, device_number=ROLL_OFF_ROOF)
        assert dome.state is ModuleState.ERROR
        error = await dome.get_error_string()
        assert f"dome {ROLL_OFF_ROOF} at {alpaca_server}" in error
        assert "cannot turn (CanSetAzimuth false); drive a roll-off roof with AlpacaRoof" in error


async def test_dome_follows_an_offset_telescope(alpaca_server: str) -> None:
    async with Observatory(clock=RealClock()) as obs:
        telescope = await obs.start(SimTelescope, "telescope", slew_rate=90.0, settle_time=0.0, init_time=0.0)
        dome = await obs.start(
            AlpacaDome,
            "dome",
            server=alpaca_server,
            device_number=DOME,
            follow="telescope",
            follow_interval=0.2,
            follow_tolerance=0.5,
            dome_radius=2.0,
            mount_offset=(1.0, 0.0, 0.0),
        )
        await telescope.init()
        await telescope.move_altaz(20.0, 0.0)
        alt, az = await telescope.get_altaz()
        slit = slit_azimuth(DomeGeometry(radius=2.0, east=1.0), alt, az)
        assert abs(azimuth_difference(slit, az)) > 25.0  # following the telescope's azimuth would be wrong

        async def at_slit() -> bool:
            return abs(azimuth_difference(await dome.get_azimuth(), slit)) < 0.5

        await obs.wait_for(at_slit, 60.0, message="the dome turning to the slit azimuth")
        cards = await dome.get_fits_header_before()
        assert cards["DOME-AZ"][0] == pytest.approx(slit, abs=0.5)


@pytest.mark.parametrize(
    ("cls", "options", "key"),
    [
        (AlpacaRoof, {"shutter_timeout": 300.0}, "shutter_timeout"),
        (AlpacaDome, {"rotation_timeout": 0.0}, "rotation_timeout"),
        (AlpacaDome, {"mount_offset": (3.0, 0.0, 0.0), "dome_radius": 2.0}, "mount_offset"),
    ],
)
def test_bad_options_are_refused_naming_the_key(
    cls: type[AlpacaRoof], options: dict[str, Any], key: str
) -> None:
    with pytest.raises(ConfigError, match=f"key '{key}'"):
        cls(name="dome", server="http://127.0.0.1:1", **options)


async def test_interrupted_turn_reports_aborted_to_its_caller(alpaca_server: str) -> None:
    # Closing the module mid-turn must not leave the caller hanging.
    async with Observatory(clock=RealClock()) as obs:
        dome = await obs.start(AlpacaDome, "dome", server=alpaca_server, device_number=DOME)
        start = await dome.get_azimuth()
        turning = asyncio.ensure_future(dome.move_azimuth((start + 45.0) % 360.0))
        await obs.wait_for(lambda: dome._rotation.busy, 30.0)
        await dome.stop_motion()
        with pytest.raises(AbortedError):
            await turning
