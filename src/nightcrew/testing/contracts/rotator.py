"""The rotator contract: turns, statuses, refusals, busy, stop, reversing and header of an IRotator module."""

from __future__ import annotations

import math
from typing import Any, ClassVar

import pytest

from nightcrew.errors import DeviceBusyError, InvalidArgumentError, NotSupportedError
from nightcrew.interfaces import IFitsHeaderBefore, IRotator, MotionStatus
from nightcrew.testing.contracts._base import ContractSetup, DeviceContract, timed_call

__all__ = ["RotatorContract"]


def _difference(a: float, b: float) -> float:
    """Signed degrees from ``b`` to ``a``, the short way round (-180..180)."""
    return (a - b + 180.0) % 360.0 - 180.0


class RotatorContract(DeviceContract):
    """Contract of an :class:`~nightcrew.interfaces.IRotator` module (see :mod:`nightcrew.testing`).

    Every test starts with the rotator not reversed at :attr:`angle_start` (when set) and turns by
    :attr:`angle_step`, or :attr:`long_turn` for the turns it interrupts.
    """

    interface = IRotator
    #: Degrees between the angle asked for and the one reported.
    angle_tolerance: ClassVar[float] = 0.5
    #: Degrees of a small turn.
    angle_step: ClassVar[float] = 10.0
    #: Degrees of a turn the suite interrupts (busy, stop_motion); long enough to catch it.
    long_turn: ClassVar[float] = 120.0
    #: Sky position angle every test starts at; None: wherever the rotator is.
    angle_start: ClassVar[float | None] = None

    def _near(self, angle: float, target: float) -> bool:
        return abs(_difference(angle, target)) <= self.angle_tolerance

    async def _start(self, contract: ContractSetup[Any]) -> tuple[IRotator, float]:
        rotator = await contract.proxy(IRotator)
        await rotator.init()
        if await rotator.get_rotator_reversed():
            await rotator.set_rotator_reversed(False)
        if self.angle_start is not None:
            await rotator.move_position_angle(self.angle_start)
        contract.probe.clear()
        return rotator, await rotator.get_position_angle()

    async def _moving(self, contract: ContractSetup[Any]) -> bool:
        return await (await contract.proxy(IRotator)).get_motion_status() is MotionStatus.MOVING

    async def test_a_turn_gets_there_and_reports_its_status(self, contract: ContractSetup[Any]) -> None:
        rotator, start = await self._start(contract)
        assert 0.0 <= start < 360.0
        assert await rotator.get_motion_status() is MotionStatus.IDLE and await rotator.is_ready()
        target = (start + self.angle_step) % 360.0
        await rotator.move_position_angle(target)
        angle = await rotator.get_position_angle()
        assert self._near(angle, target), f"{contract.name} at PA {angle:.2f}°, sent to {target:.2f}°"
        assert await rotator.get_motion_status() is MotionStatus.IDLE
        await contract.wait_for(
            lambda: contract.statuses()[-2:] == [MotionStatus.MOVING, MotionStatus.IDLE],
            self.timeout,
            "MotionStatusChangedEvent MOVING, then IDLE",
        )

    async def test_turns_by_an_offset_and_across_zero(self, contract: ContractSetup[Any]) -> None:
        rotator, start = await self._start(contract)
        await rotator.move_position_angle_by(self.angle_step)
        assert self._near(await rotator.get_position_angle(), start + self.angle_step)
        await rotator.move_position_angle(360.0 - self.angle_step / 2)  # then across 0° ...
        await rotator.move_position_angle_by(self.angle_step)
        angle = await rotator.get_position_angle()
        assert 0.0 <= angle < 360.0 and self._near(angle, self.angle_step / 2)
        await rotator.move_position_angle(-self.angle_step)  # ... and a negative angle is modulo 360
        assert self._near(await rotator.get_position_angle(), 360.0 - self.angle_step)

    async def test_a_mechanical_turn_moves_the_position_angle_alike(
        self, contract: ContractSetup[Any]
    ) -> None:
        rotator, start = await self._start(contract)
        mechanical = await rotator.get_mechanical_angle()
        assert 0.0 <= mechanical < 360.0
        target = (mechanical + self.angle_step) % 360.0
        await rotator.move_mechanical(target)
        assert self._near(await rotator.get_mechanical_angle(), target)
        turned = _difference(await rotator.get_position_angle(), start)
        assert turned == pytest.approx(self.angle_step, abs=2 * self.angle_tolerance)

    async def test_impossible_angles_are_refused_and_nothing_moves(
        self, contract: ContractSetup[Any]
    ) -> None:
        _, start = await self._start(contract)
        direct = contract.module  # not through the comm: the codec may refuse NaN itself
        assert isinstance(direct, IRotator)
        for angle in (math.nan, math.inf, -math.inf):
            for move in (direct.move_position_angle, direct.move_position_angle_by, direct.move_mechanical):
                with pytest.raises(InvalidArgumentError):
                    await move(angle)
        assert self._near(await direct.get_position_angle(), start)
        assert await direct.get_motion_status() is MotionStatus.IDLE

    async def test_a_second_turn_while_turning_is_busy(self, contract: ContractSetup[Any]) -> None:
        rotator, start = await self._start(contract)
        target = (start + self.long_turn) % 360.0
        turn = await self._start_interruptible(
            contract,
            lambda: rotator.move_position_angle(target),
            lambda: self._moving(contract),
            "a long turn",
        )
        with pytest.raises(DeviceBusyError):
            await rotator.move_position_angle(start)
        await turn
        assert self._near(await rotator.get_position_angle(), target)

    async def test_stop_motion_stops_a_turn_on_the_way(self, contract: ContractSetup[Any]) -> None:
        rotator, start = await self._start(contract)
        target = (start + self.long_turn) % 360.0
        turn = await self._start_interruptible(
            contract,
            lambda: rotator.move_position_angle(target),
            lambda: self._moving(contract),
            "a long turn",
        )
        await rotator.stop_motion()
        await self._expect_aborted(turn)
        assert await rotator.get_motion_status() is MotionStatus.IDLE
        assert not self._near(await rotator.get_position_angle(), target), "stopped, yet it arrived"
        await rotator.move_position_angle(start)  # usable again
        assert self._near(await rotator.get_position_angle(), start)

    async def test_reversing_is_read_back_or_refused(self, contract: ContractSetup[Any]) -> None:
        rotator, _ = await self._start(contract)
        try:
            await rotator.set_rotator_reversed(True)
        except NotSupportedError:
            assert await rotator.get_rotator_reversed() is False
            return
        assert await rotator.get_rotator_reversed() is True
        await rotator.set_rotator_reversed(False)
        assert await rotator.get_rotator_reversed() is False

    async def test_fits_header_tells_the_position_angle(self, contract: ContractSetup[Any]) -> None:
        rotator, _ = await self._start(contract)
        assert isinstance(contract.module, IFitsHeaderBefore), f"{contract.name} gives no FITS header"
        cards = await (await contract.proxy(IFitsHeaderBefore)).get_fits_header_before()
        assert self._near(float(cards["ROTPA"][0] or 0), await rotator.get_position_angle())

    async def test_turns_end_within_the_timeouts_they_announce(self, contract: ContractSetup[Any]) -> None:
        _, start = await self._start(contract)
        for method, angle in (
            ("move_position_angle", start + self.long_turn),
            ("move_position_angle_by", -self.long_turn),
        ):
            announced, took = await timed_call(contract, method, angle)
            assert took < announced, f"{method}({angle}) took {took:.1f} s but announced {announced:g} s"
