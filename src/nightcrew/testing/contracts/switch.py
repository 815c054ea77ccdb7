"""The switch contract: the list of switches, on/off and values read back, refusals of an ISwitch module."""

from __future__ import annotations

import math
from typing import Any

import pytest

from nightcrew.errors import InvalidArgumentError, NotSupportedError
from nightcrew.interfaces import ISwitch, SwitchInfo
from nightcrew.testing.contracts._base import ContractSetup, DeviceContract

__all__ = ["SwitchContract"]


class SwitchContract(DeviceContract):
    """Contract of an :class:`~nightcrew.interfaces.ISwitch` module with at least one writable switch
    (see :mod:`nightcrew.testing`). Every test puts back the values it changed.
    """

    interface = ISwitch

    async def _switches(self, contract: ContractSetup[Any]) -> tuple[ISwitch, list[SwitchInfo]]:
        device = await contract.proxy(ISwitch)
        switches = await device.get_switches()
        assert switches, f"{contract.name} lists no switches"
        return device, switches

    def _writable(self, contract: ContractSetup[Any], switches: list[SwitchInfo]) -> list[SwitchInfo]:
        writable = [info for info in switches if info.can_write]
        assert writable, f"{contract.name} has no writable switch: the suite needs one"
        return writable

    def _tolerance(self, info: SwitchInfo) -> float:
        return max(info.step, info.max_value - info.min_value) * 1e-6

    async def test_the_switches_are_numbered_in_order_with_sane_ranges(
        self, contract: ContractSetup[Any]
    ) -> None:
        device, switches = await self._switches(contract)
        assert [info.index for info in switches] == list(range(len(switches)))
        for info in switches:
            assert info.name, f"switch {info.index} has no name"
            assert math.isfinite(info.min_value) and math.isfinite(info.max_value)
            assert info.min_value < info.max_value, f"switch {info.index}: {info.min_value}..{info.max_value}"
            assert 0.0 <= info.step <= info.max_value - info.min_value, (
                f"switch {info.index}: step {info.step}"
            )
            value = await device.get_switch_value(info.index)
            slack = self._tolerance(info)
            assert info.min_value - slack <= value <= info.max_value + slack, (
                f"switch {info.index} at {value}"
            )
            assert await device.get_switch(info.index) is (value > info.min_value + slack)

    async def test_on_and_off_go_to_the_ends_of_the_range(self, contract: ContractSetup[Any]) -> None:
        device, switches = await self._switches(contract)
        for info in self._writable(contract, switches):
            before = await device.get_switch_value(info.index)
            try:
                await device.set_switch(info.index, True)
                assert await device.get_switch(info.index) is True
                assert await device.get_switch_value(info.index) == pytest.approx(info.max_value)
                await device.set_switch(info.index, False)
                assert await device.get_switch(info.index) is False
                assert await device.get_switch_value(info.index) == pytest.approx(info.min_value)
            finally:
                await device.set_switch_value(info.index, before)

    async def test_a_value_in_steps_is_read_back(self, contract: ContractSetup[Any]) -> None:
        device, switches = await self._switches(contract)
        for info in self._writable(contract, switches):
            before = await device.get_switch_value(info.index)
            step = info.step or (info.max_value - info.min_value) / 2
            value = info.min_value + step * math.floor((info.max_value - info.min_value) / step / 2)
            try:
                await device.set_switch_value(info.index, value)
                assert await device.get_switch_value(info.index) == pytest.approx(
                    value, abs=self._tolerance(info)
                )
            finally:
                await device.set_switch_value(info.index, before)

    async def test_values_off_range_or_off_step_are_refused_and_nothing_changes(
        self, contract: ContractSetup[Any]
    ) -> None:
        device, switches = await self._switches(contract)
        direct = contract.module  # NaN not through the comm: the codec may refuse it itself
        assert isinstance(direct, ISwitch)
        for info in self._writable(contract, switches):
            before = await device.get_switch_value(info.index)
            span = info.max_value - info.min_value
            wrong = [info.max_value + span, info.min_value - span]
            if 0 < info.step < span:
                wrong.append(info.min_value + info.step / 2)
            for value in wrong:
                with pytest.raises(InvalidArgumentError):
                    await device.set_switch_value(info.index, value)
            with pytest.raises(InvalidArgumentError):
                await direct.set_switch_value(info.index, math.nan)
            assert await device.get_switch_value(info.index) == before

    async def test_switches_it_does_not_have_are_refused(self, contract: ContractSetup[Any]) -> None:
        device, switches = await self._switches(contract)
        for number in (-1, len(switches)):
            with pytest.raises(InvalidArgumentError):
                await device.get_switch(number)
            with pytest.raises(InvalidArgumentError):
                await device.get_switch_value(number)
            with pytest.raises(InvalidArgumentError):
                await device.set_switch(number, True)
            with pytest.raises(InvalidArgumentError):
                await device.set_switch_value(number, switches[0].min_value)

    async def test_read_only_switches_refuse_writes(self, contract: ContractSetup[Any]) -> None:
        device, switches = await self._switches(contract)
        for info in switches:
            if info.can_write:
                continue
            with pytest.raises(NotSupportedError):
                await device.set_switch(info.index, True)
            with pytest.raises(NotSupportedError):
                await device.set_switch_value(info.index, info.min_value)
