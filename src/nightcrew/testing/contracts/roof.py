"""The roof and dome contracts: opening, closing, events, refusals and weather of IRoof/IDome modules."""

from __future__ import annotations

import math
from typing import Any, ClassVar

import pytest

from nightcrew.errors import DeviceBusyError, InvalidArgumentError, MoveError
from nightcrew.events import RoofClosedEvent, RoofClosingEvent, RoofOpenedEvent
from nightcrew.interfaces import IDome, IFitsHeaderBefore, IRoof, MotionStatus
from nightcrew.testing.contracts._base import ContractSetup, DeviceContract, timed_call

__all__ = ["DomeContract", "RoofContract"]


class RoofContract(DeviceContract):
    """Contract of an :class:`~nightcrew.interfaces.IRoof` module (see :mod:`nightcrew.testing`).

    A roof is PARKED when closed and IDLE when open; closing always wins; bad weather closes it
    and keeps it closed until the weather is good.
    """

    interface = IRoof

    async def _status(self, contract: ContractSetup[Any]) -> MotionStatus:
        return await (await contract.proxy(IRoof)).get_motion_status()

    async def _opening(self, contract: ContractSetup[Any]) -> bool:
        return await self._status(contract) is MotionStatus.MOVING

    async def _closed(self, contract: ContractSetup[Any]) -> IRoof:
        roof = await contract.proxy(IRoof)
        await roof.close_roof()
        contract.probe.clear()
        return roof

    async def test_open_and_close_change_the_status_and_are_announced(
        self, contract: ContractSetup[Any]
    ) -> None:
        roof = await self._closed(contract)
        assert await roof.get_motion_status() is MotionStatus.PARKED
        await roof.open_roof()
        assert await roof.get_motion_status() is MotionStatus.IDLE
        await contract.probe.wait_for_event(RoofOpenedEvent, self.timeout, sender=contract.name)
        await roof.close_roof()
        assert await roof.get_motion_status() is MotionStatus.PARKED
        await contract.probe.wait_for_event(RoofClosedEvent, self.timeout, sender=contract.name)
        kinds = [type(e) for e, s in contract.probe.events if s == contract.name and type(e) in _ROOF_EVENTS]
        assert kinds == [RoofOpenedEvent, RoofClosingEvent, RoofClosedEvent]
        statuses = contract.statuses()
        assert statuses[0] is MotionStatus.MOVING and statuses[-2:] == [
            MotionStatus.PARKING,
            MotionStatus.PARKED,
        ]
        assert MotionStatus.IDLE in statuses

    async def test_init_opens_and_park_closes(self, contract: ContractSetup[Any]) -> None:
        roof = await self._closed(contract)
        await roof.init()
        assert await roof.get_motion_status() is MotionStatus.IDLE and await roof.is_ready()
        await roof.park()
        assert await roof.get_motion_status() is MotionStatus.PARKED

    async def test_opening_twice_is_busy_and_closing_aborts_an_opening(
        self, contract: ContractSetup[Any]
    ) -> None:
        roof = await self._closed(contract)
        opening = await self._start_interruptible(
            contract, lambda: roof.open_roof(), lambda: self._opening(contract), "opening"
        )
        with pytest.raises(DeviceBusyError):
            await roof.open_roof()
        await roof.close_roof()
        await self._expect_aborted(opening)
        assert await roof.get_motion_status() is MotionStatus.PARKED

    async def test_stop_motion_stops_an_opening_roof(self, contract: ContractSetup[Any]) -> None:
        roof = await self._closed(contract)
        opening = await self._start_interruptible(
            contract, lambda: roof.open_roof(), lambda: self._opening(contract), "opening"
        )
        await roof.stop_motion()
        await self._expect_aborted(opening)
        assert await roof.get_motion_status() not in (MotionStatus.MOVING, MotionStatus.PARKING)
        await roof.close_roof()
        assert await roof.get_motion_status() is MotionStatus.PARKED

    async def test_bad_weather_closes_and_keeps_closed_until_good_weather(
        self, contract: ContractSetup[Any]
    ) -> None:
        roof = await self._closed(contract)
        await roof.open_roof()
        await contract.probe.send_bad_weather("contract suite: rain")
        await contract.wait_for(
            lambda: self._is(contract, MotionStatus.PARKED), self.timeout, "the roof closing on bad weather"
        )
        with pytest.raises(MoveError, match="weather"):
            await roof.open_roof()
        await contract.probe.send_good_weather()

        async def opens() -> bool:
            try:
                await roof.open_roof()
            except MoveError:  # the good news has not arrived yet
                return False
            return True

        await contract.wait_for(opens, self.timeout, "the roof opening again after good weather")
        assert await roof.get_motion_status() is MotionStatus.IDLE
        await roof.close_roof()

    async def test_motions_end_within_the_timeouts_they_announce(self, contract: ContractSetup[Any]) -> None:
        await self._closed(contract)
        for method in ("open_roof", "close_roof", "init", "park"):
            announced, took = await timed_call(contract, method)
            assert took < announced, f"{method}() took {took:.1f} s but announced {announced:g} s"

    async def _is(self, contract: ContractSetup[Any], status: MotionStatus) -> bool:
        return await self._status(contract) is status


_ROOF_EVENTS = (RoofOpenedEvent, RoofClosingEvent, RoofClosedEvent)


class DomeContract(RoofContract):
    """Contract of an :class:`~nightcrew.interfaces.IDome` module: the roof contract for its
    shutter plus the slit azimuth."""

    interface = IDome
    #: Degrees between the azimuth asked for and the one reported once there.
    azimuth_tolerance: ClassVar[float] = 1.0
    #: Degrees of an azimuth move.
    azimuth_step: ClassVar[float] = 5.0

    def _near(self, az: float, target: float) -> bool:
        return abs((az - target + 180.0) % 360.0 - 180.0) <= self.azimuth_tolerance

    async def test_move_azimuth_gets_there(self, contract: ContractSetup[Any]) -> None:
        dome = await contract.proxy(IDome)
        start = await dome.get_azimuth()
        assert 0.0 <= start < 360.0
        target = (round(start) + self.azimuth_step) % 360.0
        await dome.move_azimuth(target)
        az = await dome.get_azimuth()
        assert self._near(az, target), f"dome at {az:.2f}°, sent to {target:.2f}°"

    async def test_impossible_azimuths_are_invalid_arguments(self, contract: ContractSetup[Any]) -> None:
        dome = contract.module
        assert isinstance(dome, IDome)
        before = await dome.get_azimuth()
        for az in (math.nan, math.inf):
            with pytest.raises(InvalidArgumentError):
                await dome.move_azimuth(az)
        assert self._near(await dome.get_azimuth(), before)

    async def test_fits_header_tells_the_azimuth(self, contract: ContractSetup[Any]) -> None:
        assert isinstance(contract.module, IFitsHeaderBefore), f"{contract.name} gives no FITS header"
        dome = await contract.proxy(IDome)
        cards = await (await contract.proxy(IFitsHeaderBefore)).get_fits_header_before()
        assert "DOME-AZ" in cards
        assert self._near(float(cards["DOME-AZ"][0] or 0), await dome.get_azimuth())
