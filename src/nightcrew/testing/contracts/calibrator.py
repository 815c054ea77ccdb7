"""The cover-calibrator contract: cover and light states, refusals, halt and timeouts of an
ICoverCalibrator module."""

from __future__ import annotations

from typing import Any, ClassVar

import pytest

from nightcrew.errors import InvalidArgumentError, MoveError, NotSupportedError
from nightcrew.interfaces import CalibratorState, CoverState, ICoverCalibrator
from nightcrew.testing.contracts._base import ContractSetup, DeviceContract, timed_call

__all__ = ["CoverCalibratorContract"]


class CoverCalibratorContract(DeviceContract):
    """Contract of an :class:`~nightcrew.interfaces.ICoverCalibrator` module with a cover, a light
    or both (see :mod:`nightcrew.testing`). A part the device lacks must report NOT_PRESENT and
    refuse to be driven (NotSupportedError); every test leaves the light off.
    """

    interface = ICoverCalibrator
    #: Brightness the light is switched on at; None: half its maximum.
    brightness: ClassVar[int | None] = None

    async def _device(self, contract: ContractSetup[Any]) -> tuple[ICoverCalibrator, bool, bool]:
        """The proxy, whether there is a cover, whether there is a light."""
        device = await contract.proxy(ICoverCalibrator)
        cover = await device.get_cover_state() is not CoverState.NOT_PRESENT
        light = await device.get_calibrator_state() is not CalibratorState.NOT_PRESENT
        assert cover or light, f"{contract.name} has neither a cover nor a light"
        return device, cover, light

    async def test_the_cover_opens_and_closes(self, contract: ContractSetup[Any]) -> None:
        device, cover, _ = await self._device(contract)
        if not cover:
            for call in (device.open_cover, device.close_cover, device.halt_cover):
                with pytest.raises(NotSupportedError):
                    await call()
            assert await device.get_cover_state() is CoverState.NOT_PRESENT
            return
        await device.close_cover()
        assert await device.get_cover_state() is CoverState.CLOSED
        await device.open_cover()
        assert await device.get_cover_state() is CoverState.OPEN
        await device.close_cover()
        assert await device.get_cover_state() is CoverState.CLOSED

    async def test_the_light_goes_on_at_a_brightness_and_off(self, contract: ContractSetup[Any]) -> None:
        device, _, light = await self._device(contract)
        if not light:
            with pytest.raises(NotSupportedError):
                await device.calibrator_on(1)
            for call in (device.calibrator_off, device.get_brightness, device.get_max_brightness):
                with pytest.raises(NotSupportedError):
                    await call()
            assert await device.get_calibrator_state() is CalibratorState.NOT_PRESENT
            return
        maximum = await device.get_max_brightness()
        assert maximum >= 1
        brightness = maximum // 2 if self.brightness is None else self.brightness
        try:
            await device.calibrator_on(brightness)
            assert await device.get_calibrator_state() is CalibratorState.READY
            assert await device.get_brightness() == brightness
        finally:
            await device.calibrator_off()
        assert await device.get_calibrator_state() is CalibratorState.OFF
        assert await device.get_brightness() == 0

    async def test_brightness_out_of_range_is_refused_and_the_light_stays_off(
        self, contract: ContractSetup[Any]
    ) -> None:
        device, _, light = await self._device(contract)
        if not light:  # refused as the device lacks a light, whatever the brightness
            with pytest.raises(NotSupportedError):
                await device.calibrator_on(-1)
            return
        await device.calibrator_off()
        maximum = await device.get_max_brightness()
        for brightness in (-1, maximum + 1):
            with pytest.raises(InvalidArgumentError):
                await device.calibrator_on(brightness)
        direct = contract.module  # not through the comm: the codec may convert a float itself
        assert isinstance(direct, ICoverCalibrator)
        with pytest.raises(InvalidArgumentError):
            await direct.calibrator_on(0.5)  # type: ignore[arg-type]
        assert await device.get_calibrator_state() is CalibratorState.OFF
        assert await device.get_brightness() == 0

    async def test_halt_cover_stops_a_moving_cover(self, contract: ContractSetup[Any]) -> None:
        device, cover, _ = await self._device(contract)
        if not cover:
            with pytest.raises(NotSupportedError):
                await device.halt_cover()
            return
        await device.close_cover()

        async def moving() -> bool:
            return await device.get_cover_state() is CoverState.MOVING

        opening = await self._start_interruptible(contract, device.open_cover, moving, "opening the cover")
        await device.halt_cover()
        with pytest.raises(MoveError):  # it did not get open
            await opening
        assert await device.get_cover_state() not in (CoverState.MOVING, CoverState.OPEN)
        await device.close_cover()  # usable again
        assert await device.get_cover_state() is CoverState.CLOSED

    async def test_calls_end_within_the_timeouts_they_announce(self, contract: ContractSetup[Any]) -> None:
        _, cover, light = await self._device(contract)
        calls: list[tuple[str, tuple[Any, ...]]] = []
        if cover:
            calls += [("open_cover", ()), ("close_cover", ())]
        if light:
            calls += [("calibrator_on", (1,)), ("calibrator_off", ())]
        for method, args in calls:
            announced, took = await timed_call(contract, method, *args)
            assert took < announced, f"{method}{args} took {took:.1f} s but announced {announced:g} s"
