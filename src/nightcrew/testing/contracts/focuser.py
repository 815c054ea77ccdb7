"""The focuser contract: moves, offsets, range refusals, busy, stop and header of an IFocuser module."""

from __future__ import annotations

import math
from typing import Any, ClassVar

import pytest

from nightcrew.errors import DeviceBusyError, InvalidArgumentError
from nightcrew.interfaces import IFitsHeaderBefore, IFocuser, MotionStatus
from nightcrew.testing.contracts._base import ContractSetup, DeviceContract, timed_call

__all__ = ["FocuserContract"]


class FocuserContract(DeviceContract):
    """Contract of an :class:`~nightcrew.interfaces.IFocuser` module (see :mod:`nightcrew.testing`).

    Every test first moves to :attr:`focus_start` (when set) and moves upwards from there by
    :attr:`focus_step`, or :attr:`long_focus_move` for the moves it interrupts: leave that much room
    above the start position.
    """

    interface = IFocuser
    #: mm between the focus asked for and the one reported.
    focus_tolerance: ClassVar[float] = 0.005
    #: mm of a small move (and of the offset).
    focus_step: ClassVar[float] = 0.1
    #: mm of a move the suite interrupts (busy, stop_motion); long enough to catch it.
    long_focus_move: ClassVar[float] = 5.0
    #: mm every test starts at; None: wherever the focuser is.
    focus_start: ClassVar[float | None] = None

    async def _start(self, contract: ContractSetup[Any]) -> tuple[IFocuser, float]:
        focuser = await contract.proxy(IFocuser)
        await focuser.init()
        if await focuser.get_focus_offset() != 0.0:
            await focuser.set_focus_offset(0.0)
        if self.focus_start is not None:
            await focuser.set_focus(self.focus_start)
        contract.probe.clear()
        return focuser, await focuser.get_focus()

    async def _moving(self, contract: ContractSetup[Any]) -> bool:
        return await (await contract.proxy(IFocuser)).get_motion_status() is MotionStatus.MOVING

    async def test_set_focus_gets_there_and_reports_its_status(self, contract: ContractSetup[Any]) -> None:
        focuser, start = await self._start(contract)
        assert await focuser.get_motion_status() is MotionStatus.IDLE and await focuser.is_ready()
        await focuser.set_focus(start + self.focus_step)
        assert await focuser.get_focus() == pytest.approx(start + self.focus_step, abs=self.focus_tolerance)
        assert await focuser.get_motion_status() is MotionStatus.IDLE
        await contract.wait_for(
            lambda: contract.statuses()[-2:] == [MotionStatus.MOVING, MotionStatus.IDLE],
            self.timeout,
            "MotionStatusChangedEvent MOVING, then IDLE",
        )

    async def test_an_offset_adds_to_the_focus_and_the_header(self, contract: ContractSetup[Any]) -> None:
        focuser, start = await self._start(contract)
        await focuser.set_focus_offset(self.focus_step)
        assert await focuser.get_focus_offset() == pytest.approx(self.focus_step, abs=self.focus_tolerance)
        assert await focuser.get_focus() == pytest.approx(start, abs=self.focus_tolerance)
        assert isinstance(contract.module, IFitsHeaderBefore), f"{contract.name} gives no FITS header"
        cards = await (await contract.proxy(IFitsHeaderBefore)).get_fits_header_before()
        assert float(cards["FOCUS"][0] or 0) == pytest.approx(
            start + self.focus_step, abs=self.focus_tolerance
        )
        await focuser.set_focus_offset(0.0)

    async def test_positions_out_of_range_are_refused_and_nothing_moves(
        self, contract: ContractSetup[Any]
    ) -> None:
        focuser, start = await self._start(contract)
        for position in (1e6, -1e6):
            with pytest.raises(InvalidArgumentError):
                await focuser.set_focus(position)
        with pytest.raises(InvalidArgumentError):
            await focuser.set_focus_offset(1e6)
        direct = contract.module
        assert isinstance(direct, IFocuser)
        with pytest.raises(InvalidArgumentError):
            await direct.set_focus(math.nan)  # not through the comm: the codec may refuse NaN itself
        assert await focuser.get_focus() == pytest.approx(start, abs=self.focus_tolerance)
        assert await focuser.get_focus_offset() == 0.0
        assert await focuser.get_motion_status() is MotionStatus.IDLE

    async def test_a_second_move_while_moving_is_busy(self, contract: ContractSetup[Any]) -> None:
        focuser, start = await self._start(contract)
        target = start + self.long_focus_move
        move = await self._start_interruptible(
            contract, lambda: focuser.set_focus(target), lambda: self._moving(contract), "a long move"
        )
        with pytest.raises(DeviceBusyError):
            await focuser.set_focus(start)
        await move
        assert await focuser.get_focus() == pytest.approx(target, abs=self.focus_tolerance)

    async def test_stop_motion_stops_a_move(self, contract: ContractSetup[Any]) -> None:
        focuser, start = await self._start(contract)
        move = await self._start_interruptible(
            contract,
            lambda: focuser.set_focus(start + self.long_focus_move),
            lambda: self._moving(contract),
            "a long move",
        )
        await focuser.stop_motion()
        await self._expect_aborted(move)
        assert await focuser.get_motion_status() is MotionStatus.IDLE
        await focuser.set_focus(start)  # usable again
        assert await focuser.get_focus() == pytest.approx(start, abs=self.focus_tolerance)

    async def test_moves_end_within_the_timeouts_they_announce(self, contract: ContractSetup[Any]) -> None:
        _, start = await self._start(contract)
        for position in (start + self.long_focus_move, start):
            announced, took = await timed_call(contract, "set_focus", position)
            assert took < announced, f"set_focus({position}) took {took:.1f} s but announced {announced:g} s"
