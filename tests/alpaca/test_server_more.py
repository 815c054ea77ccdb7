"""What the conformance suite does not see: served rotators, switches, flat panels and pulse
guiding do what a client asks, with raw HTTP as any client sends it."""

from __future__ import annotations

from collections.abc import AsyncIterator
from typing import Any

import aiohttp
import pytest
import pytest_asyncio

from nightcrew.bridges.alpaca.errors import INVALID_OPERATION, INVALID_VALUE
from nightcrew.bridges.alpaca.server_telescope import GUIDE_RATE
from nightcrew.interfaces import IOffsetsRaDec
from nightcrew.testing import wait_for

from .served import MILKY_WAY, Served, served_observatory

pytestmark = pytest.mark.asyncio(loop_scope="module")


class Client:
    def __init__(self, session: aiohttp.ClientSession, url: str) -> None:
        self._session, self._url = session, url

    async def call(self, method: str, path: str, **params: str) -> dict[str, Any]:
        url = f"{self._url}/api/v1/{path}"
        request = (
            self._session.get(url, params=params) if method == "GET" else self._session.put(url, data=params)
        )
        async with request as response:
            assert response.status == 200, await response.text()
            body: dict[str, Any] = await response.json()
            return body

    async def value(self, path: str, **params: str) -> Any:
        body = await self.call("GET", path, **params)
        assert body["ErrorNumber"] == 0, body
        return body["Value"]

    async def put(self, path: str, **params: str) -> None:
        body = await self.call("PUT", path, **params)
        assert body["ErrorNumber"] == 0, body


@pytest_asyncio.fixture(scope="module", loop_scope="module")
async def served() -> AsyncIterator[Served]:
    async with served_observatory(more_devices=True) as served:
        yield served


@pytest_asyncio.fixture(scope="module", loop_scope="module")
async def client(served: Served) -> AsyncIterator[Client]:
    async with aiohttp.ClientSession() as session:
        client = Client(session, served.url)
        for device in ("telescope", "rotator", "switch", "covercalibrator"):
            await client.put(f"{device}/0/connected", Connected="True")
        yield client


async def test_pulse_guiding_moves_the_offsets_by_rate_times_length(served: Served, client: Client) -> None:
    body = await client.call("PUT", "telescope/0/pulseguide", Direction="2", Duration="100")
    assert body["ErrorNumber"] == INVALID_OPERATION  # parked: no target to guide on
    await client.put("telescope/0/unpark")
    await wait_for(lambda: _not(client.value("telescope/0/atpark")), 30.0, message="unparked")
    await client.put(
        "telescope/0/slewtocoordinates", RightAscension=str(MILKY_WAY[0] / 15), Declination="4.7"
    )
    assert await client.value("telescope/0/canpulseguide") is True

    await client.put("telescope/0/pulseguide", Direction="2", Duration="30000")  # east: +RA
    assert await client.value("telescope/0/ispulseguiding") is True
    body = await client.call("PUT", "telescope/0/pulseguide", Direction="3", Duration="100")
    assert body["ErrorNumber"] == INVALID_OPERATION  # the RA axis is still guiding
    assert "a pulse on the ra axis is still running" in body["ErrorMessage"]
    await client.put("telescope/0/pulseguide", Direction="1", Duration="200")  # south: the other axis
    await client.put("telescope/0/abortslew")  # ends the pulses
    assert await client.value("telescope/0/ispulseguiding") is False
    offsets = await served.server.proxy("telescope", IOffsetsRaDec)
    dra, ddec = await offsets.get_offsets_radec()
    assert (dra, ddec) == pytest.approx((GUIDE_RATE * 30.0, -GUIDE_RATE * 0.2))

    body = await client.call("PUT", "telescope/0/pulseguide", Direction="7", Duration="100")
    assert body["ErrorNumber"] == INVALID_VALUE
    assert "direction must be 0 (north), 1 (south), 2 (east) or 3 (west), got 7" in body["ErrorMessage"]


async def _not(value: Any) -> bool:
    return not await value


async def test_a_served_rotator_turns_to_the_position_angle(client: Client) -> None:
    await client.put("rotator/0/moveabsolute", Position="90")
    await wait_for(lambda: _not(client.value("rotator/0/ismoving")), 10.0, message="rotator stopped")
    assert await client.value("rotator/0/position") == pytest.approx(90.0)
    assert await client.value("rotator/0/targetposition") == pytest.approx(90.0)
    state = {item["Name"]: item["Value"] for item in await client.value("rotator/0/devicestate")}
    assert state["Position"] == pytest.approx(90.0) and state["IsMoving"] is False


async def test_a_served_switch_sets_values_within_its_range(client: Client) -> None:
    assert await client.value("switch/0/maxswitch") == 2
    assert await client.value("switch/0/getswitchname", Id="1") == "dew heater"
    await client.put("switch/0/setswitchvalue", Id="1", Value="40")
    assert await client.value("switch/0/getswitchvalue", Id="1") == 40.0
    assert await client.value("switch/0/getswitch", Id="1") is True
    for params in ({"Id": "2", "Value": "1"}, {"Id": "1", "Value": "150"}):
        body = await client.call("PUT", "switch/0/setswitchvalue", **params)
        assert body["ErrorNumber"] == INVALID_VALUE, body


async def test_a_served_flat_panel_closes_and_lights(client: Client) -> None:
    await client.put("covercalibrator/0/closecover")
    await wait_for(lambda: _is(client.value("covercalibrator/0/coverstate"), 1), 10.0, message="closed")
    maximum = await client.value("covercalibrator/0/maxbrightness")
    await client.put("covercalibrator/0/calibratoron", Brightness=str(maximum))
    await wait_for(lambda: _is(client.value("covercalibrator/0/calibratorstate"), 3), 10.0, message="ready")
    assert await client.value("covercalibrator/0/brightness") == maximum
    body = await client.call("PUT", "covercalibrator/0/calibratoron", Brightness=str(maximum + 1))
    assert body["ErrorNumber"] == INVALID_VALUE


async def _is(value: Any, expected: Any) -> bool:
    return bool(await value == expected)
