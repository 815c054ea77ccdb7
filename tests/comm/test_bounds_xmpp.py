"""Bounds over a real XMPP server: an exposure time beyond physics sent to a camera through Prosody
is refused at once with one error naming the argument and its range, and changes nothing."""

from __future__ import annotations

import pytest

from nightcrew.errors import InvalidArgumentError
from nightcrew.modules.sim import SimCamera

from .conftest import Network
from .sample import Calculator

pytestmark = pytest.mark.xmpp


async def test_an_exposure_time_beyond_physics_is_refused_over_prosody(prosody_network: Network) -> None:
    await prosody_network.start(SimCamera, "camera", detector={"chip_width": 32, "chip_height": 32})
    caller = await prosody_network.start(Calculator, "caller")
    await caller.comm.execute("camera", "set_exposure_time", [2.0])
    for value in (1e308, float(2**70)):
        with pytest.raises(InvalidArgumentError) as refused:
            await caller.comm.execute("camera", "set_exposure_time", [value])
        assert refused.value.message == (
            f"set_exposure_time(): argument 'exposure_time': {value!r} is out of range (must be <= 86400.0 s)"
        )
    assert await caller.comm.execute("camera", "get_exposure_time", []) == 2.0
