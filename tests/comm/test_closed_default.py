"""Closed by default: a module on XMPP without a policy refuses state changes; ``policy: open`` is
explicit and warned at every start; the in-process comm needs no policy.
"""

from __future__ import annotations

import logging
from pathlib import Path

import pytest

from nightcrew.comm.local import LocalComm, LocalNetwork
from nightcrew.config import build_object
from nightcrew.errors import ForbiddenError
from nightcrew.modules.sim import SimCamera

from .conftest import Network
from .sample import Calculator


async def test_xmpp_without_policy_refuses_state_changes(
    prosody_network: Network, caplog: pytest.LogCaptureFixture
) -> None:
    server = prosody_network.server
    assert server is not None
    caplog.set_level(logging.INFO, logger="nightcrew.comm.base")
    camera = SimCamera(comm=server.comm("camera", room=prosody_network.room))
    prosody_network._modules.append(camera)
    await camera.open()
    assert "camera has no access policy: it refuses every state-changing call" in caplog.text
    caller = await prosody_network.start(Calculator, "observer")

    assert await caller.comm.execute("camera", "get_exposure_time", []) >= 0  # reading is allowed
    with pytest.raises(ForbiddenError, match=r"observer may not call camera\.set_exposure_time\(\)"):
        await caller.comm.execute("camera", "set_exposure_time", [2.0])


async def test_policy_open_is_explicit_and_warned(
    prosody_network: Network, caplog: pytest.LogCaptureFixture
) -> None:
    camera = await prosody_network.start(SimCamera, "camera")  # the fixture says `policy: open`
    assert "camera runs with 'policy: open': every account on the server may call all its methods" in (
        caplog.text
    )
    caller = await prosody_network.start(Calculator, "observer")
    await caller.comm.execute("camera", "set_exposure_time", [2.0])
    assert await camera.get_exposure_time() == 2.0


def test_policy_open_in_a_file_is_a_word_not_a_path(tmp_path: Path) -> None:
    config = {
        "class": "nightcrew.comm.xmpp.XmppComm",
        "jid": "camera@observatory.local",
        "password": "x",
        "policy": "open",
    }
    comm = build_object(config)
    assert comm.policy is None  # everything allowed


async def test_in_process_comm_needs_no_policy(caplog: pytest.LogCaptureFixture) -> None:
    network = LocalNetwork()
    camera = SimCamera(comm=LocalComm("camera", network=network))
    caller = Calculator(comm=LocalComm("observer", network=network))
    await camera.open()
    await caller.open()
    try:
        await caller.comm.execute("camera", "set_exposure_time", [2.0])
        assert "policy" not in caplog.text
    finally:
        await caller.close()
        await camera.close()
