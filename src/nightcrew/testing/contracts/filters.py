"""The filter wheel contract: names, changes, events, refusals, busy and header of an IFilters module."""

from __future__ import annotations

from typing import Any

import pytest

from nightcrew.errors import DeviceBusyError, InvalidArgumentError
from nightcrew.events import FilterChangedEvent
from nightcrew.interfaces import IFilters, IFitsHeaderBefore, MotionStatus
from nightcrew.testing.contracts._base import ContractSetup, DeviceContract, timed_call

__all__ = ["FilterWheelContract"]


class FilterWheelContract(DeviceContract):
    """Contract of an :class:`~nightcrew.interfaces.IFilters` module with at least two filters
    (see :mod:`nightcrew.testing`)."""

    interface = IFilters

    async def _wheel(self, contract: ContractSetup[Any]) -> tuple[IFilters, list[str], str]:
        wheel = await contract.proxy(IFilters)
        await wheel.init()
        names = await wheel.list_filters()
        assert len(names) >= 2, f"{contract.name} lists {names}: the suite needs two filters"
        current = await wheel.get_filter()
        assert current in names
        contract.probe.clear()
        return wheel, names, current

    def _other(self, names: list[str], current: str) -> str:
        return next(name for name in names if name != current)

    async def _moving(self, contract: ContractSetup[Any]) -> bool:
        return await (await contract.proxy(IFilters)).get_motion_status() is MotionStatus.MOVING

    async def test_a_filter_change_is_announced_and_in_the_header(self, contract: ContractSetup[Any]) -> None:
        wheel, names, current = await self._wheel(contract)
        other = self._other(names, current)
        await wheel.set_filter(other)
        assert await wheel.get_filter() == other
        assert await wheel.get_motion_status() is MotionStatus.IDLE
        event = await contract.probe.wait_for_event(FilterChangedEvent, self.timeout, sender=contract.name)
        assert event.filter_name == other
        assert isinstance(contract.module, IFitsHeaderBefore), f"{contract.name} gives no FITS header"
        cards = await (await contract.proxy(IFitsHeaderBefore)).get_fits_header_before()
        assert cards["FILTER"][0] == other

    async def test_an_unknown_filter_is_refused_and_nothing_moves(self, contract: ContractSetup[Any]) -> None:
        wheel, names, current = await self._wheel(contract)
        unknown = "-".join(names) + "-unknown"
        with pytest.raises(InvalidArgumentError, match="unknown"):
            await wheel.set_filter(unknown)
        assert await wheel.get_filter() == current
        assert await wheel.get_motion_status() is MotionStatus.IDLE

    async def test_the_filter_in_the_beam_again_is_no_change(self, contract: ContractSetup[Any]) -> None:
        wheel, names, current = await self._wheel(contract)
        await wheel.set_filter(current)
        assert await wheel.get_filter() == current
        other = self._other(names, current)
        await wheel.set_filter(other)  # an event that comes after any the first call could have sent
        event = await contract.probe.wait_for_event(FilterChangedEvent, self.timeout, sender=contract.name)
        assert event.filter_name == other

    async def test_a_second_change_while_moving_is_busy(self, contract: ContractSetup[Any]) -> None:
        wheel, names, current = await self._wheel(contract)
        other = self._other(names, current)
        change = await self._start_interruptible(
            contract, lambda: wheel.set_filter(other), lambda: self._moving(contract), "a filter change"
        )
        with pytest.raises(DeviceBusyError):
            await wheel.set_filter(current)
        await change
        assert await wheel.get_filter() == other

    async def test_changes_end_within_the_timeouts_they_announce(self, contract: ContractSetup[Any]) -> None:
        _, names, current = await self._wheel(contract)
        for name in (self._other(names, current), current):
            announced, took = await timed_call(contract, "set_filter", name)
            assert took < announced, f"set_filter({name!r}) took {took:.1f} s but announced {announced:g} s"
