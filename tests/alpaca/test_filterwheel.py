"""AlpacaFilterWheel beyond the contract: names from the device or the config, focus offsets, and a
config that does not fit the device."""

from __future__ import annotations

from nightcrew.clock import RealClock
from nightcrew.interfaces import ModuleState
from nightcrew.modules.alpaca import AlpacaFilterWheel
from nightcrew.testing import Observatory
from nightcrew.testing.alpaca import AlpacaSimulator


async def test_names_and_focus_offsets_come_from_the_device(alpaca_simulator: AlpacaSimulator) -> None:
    async with Observatory(clock=RealClock()) as obs:
        wheel = await obs.start(AlpacaFilterWheel, "filters", server=alpaca_simulator.url)
        assert await wheel.list_filters() == ["Red", "Green", "Blue", "Clear", "Luminance"]
        assert await wheel.get_config_value("focus_offsets") == {
            "Red": -100,
            "Green": -100,
            "Blue": 50,
            "Clear": 0,
            "Luminance": 100,
        }
        await wheel.set_filter("Luminance")
        assert await wheel.device.get("position") == 4
        assert (await wheel.get_fits_header_before())["FILTER"][0] == "Luminance"


async def test_configured_names_replace_the_devices(alpaca_simulator: AlpacaSimulator) -> None:
    async with Observatory(clock=RealClock()) as obs:
        wheel = await obs.start(
            AlpacaFilterWheel, "filters", server=alpaca_simulator.url, filters=["R", "G", "B", "C", "L"]
        )
        await wheel.set_filter("G")
        assert await wheel.device.get("position") == 1
        wrong = await obs.start(AlpacaFilterWheel, "wrong", server=alpaca_simulator.url, filters=["U", "B"])
        assert wrong.state is ModuleState.ERROR
        assert "2 names configured, but filterwheel 0 at" in await wrong.get_error_string()
