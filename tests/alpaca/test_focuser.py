"""AlpacaFocuser beyond the contract: steps and mm, range and temperature from the device, and a
relative focuser moved in chunks of MaxIncrement."""

from __future__ import annotations

import pytest

from nightcrew.clock import RealClock
from nightcrew.modules.alpaca import AlpacaFocuser
from nightcrew.testing import Observatory
from nightcrew.testing.alpaca import AlpacaSimulator
from tests.alpaca.faulty_server import FaultyServer, value


async def test_steps_range_and_temperature_from_the_device(alpaca_simulator: AlpacaSimulator) -> None:
    async with Observatory(clock=RealClock()) as obs:
        focuser = await obs.start(AlpacaFocuser, "focuser", server=alpaca_simulator.url)
        await focuser.set_focus(12.345)
        assert await focuser.device.get("position") == 12345  # 1 µm per step
        assert await focuser.get_focus() == pytest.approx(12.345)
        assert focuser._max_focus == pytest.approx(100.0)  # MaxStep 100000 steps
        assert await focuser.get_temperatures() == {"focuser": pytest.approx(20.0)}
        cards = await focuser.get_fits_header_before()
        assert cards["FOCUS"][0] == pytest.approx(12.345) and cards["FOCTEMP"][0] == pytest.approx(20.0)


async def test_a_relative_focuser_moves_in_chunks() -> None:
    server = FaultyServer()
    server.replies.update(
        {
            "connecting": value(False),
            "stepsize": value(2.0),
            "absolute": value(False),
            "maxstep": value(50000),
            "maxincrement": value(1000),
            "ismoving": value(False),
            "temperature": value(5.0),
        }
    )
    await server.start()
    try:
        async with Observatory(clock=RealClock()) as obs:
            focuser = await obs.start(AlpacaFocuser, "focuser", server=server.url)
            await focuser.set_focus(5.0)  # 2500 steps of 2 µm from where it was (0)
            await focuser.set_focus(4.0)
        moves = [int(fields["Position"]) for method, member, fields in server.requests if member == "move"]
        assert moves == [1000, 1000, 500, -500]
    finally:
        await server.stop()
