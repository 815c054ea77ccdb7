"""Listings and introspection show a caller only what the policy lets it call (every transport).

``system.listMethods``, ``methodSignature``, ``methodHelp`` and ``describe`` are answered per caller
by the callee; the interfaces announced (LocalComm's discovery, XMPP disco#info answered per asking
entity) are those with a method the caller may call, so ``nightcrew modules`` and the shell's
completion list only those.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from nightcrew.cli._operator import list_modules, method_names
from nightcrew.comm.base import Comm
from nightcrew.errors import ForbiddenError, InterfaceError
from nightcrew.modules.sim import SimCamera, SimRoof
from nightcrew.security import load_policy

from .conftest import Network
from .sample import Calculator

POLICY = """\
roles:
  observer: ["camera.*", "*.get_*", IModule]
  operator: ["*"]
accounts:
  observer: [observer]
  operator: [operator]
"""


def _secured(network: Network, name: str, policy: Path) -> Comm:
    if network.server is not None:
        return network.server.comm(name, room=network.room, policy=str(policy))
    from nightcrew.comm.local import LocalComm

    return LocalComm(name, network=network._local, policy=str(policy))


async def test_listings_show_only_what_the_caller_may_call(network: Network, tmp_path: Path) -> None:
    policy_file = tmp_path / "policy.yaml"
    policy_file.write_text(POLICY)
    policy = load_policy(policy_file)
    for cls, name in ((SimRoof, "roof"), (SimCamera, "camera")):
        module = cls(comm=_secured(network, name, policy_file))
        network._modules.append(module)
        await module.open()
    observer = await network.start(Calculator, "observer")
    operator = await network.start(Calculator, "operator")
    stranger = await network.start(Calculator, "stranger")

    everything = await operator.comm.execute("roof", "system.listMethods", [])
    seen = await observer.comm.execute("roof", "system.listMethods", [])
    assert "open_roof" in everything and "open_roof" not in seen and "get_motion_status" in seen
    assert [m for m in everything if m.startswith("system.") or policy.allows("observer", "roof", m, None)
            or m in seen] == seen  # fmt: skip
    assert [m for m in seen if not m.startswith("system.")] == await _documented(observer.comm, "roof")
    assert await stranger.comm.execute("roof", "system.listMethods", []) == [
        m for m in everything if m.startswith("system.")
    ]
    with pytest.raises(InterfaceError, match="no method 'open_roof'"):
        await observer.comm.execute("roof", "system.methodHelp", ["open_roof"])
    with pytest.raises(InterfaceError, match="no method 'open_roof'"):
        await observer.comm.execute("roof", "system.methodSignature", ["open_roof"])
    assert await operator.comm.execute("roof", "system.methodHelp", ["open_roof"])
    roof_doc = await observer.comm.execute("roof", "system.describe", ["IRoof"])
    assert "open_roof" not in {m["name"] for m in roof_doc["methods"]}
    with pytest.raises(InterfaceError, match="does not offer IRoof"):
        await stranger.comm.execute("roof", "system.describe", ["IRoof"])

    # Announced interfaces: the camera wholly, the roof for its getters, nothing to a stranger.
    assert "IRoof" in await observer.comm.get_interface_names("roof")
    assert set(await observer.comm.get_interface_names("camera")) == set(
        await operator.comm.get_interface_names("camera")
    )
    assert await stranger.comm.get_interface_names("roof") == []
    assert "open_roof" not in await method_names(observer.comm, "roof")  # the shell's completion
    assert "open_roof" in await method_names(operator.comm, "roof")
    listed = {info.name: info.interfaces for info in await list_modules(stranger.comm)}
    assert listed["roof"] == [] and listed["camera"] == []  # `nightcrew modules` as a stranger
    with pytest.raises(ForbiddenError):  # hidden, and refused all the same
        await stranger.comm.execute("roof", "get_motion_status", [])


async def _documented(comm: Comm, module: str) -> list[str]:
    document = await comm.execute(module, "system.describe", [])
    return sorted(method["name"] for method in document["methods"])


async def test_a_call_acting_as_an_identity_is_checked_as_that_identity(
    network: Network, tmp_path: Path
) -> None:
    policy_file = tmp_path / "policy.yaml"
    policy_file.write_text(POLICY + '  "operator:viewer": [observer]\n')
    roof = SimRoof(comm=_secured(network, "roof", policy_file))
    network._modules.append(roof)
    await roof.open()
    operator = await network.start(Calculator, "operator")
    with operator.comm.acting_as("viewer"):  # as the console does for a viewer's session
        assert await operator.comm.execute("roof", "get_motion_status", []) == "parked"
        with pytest.raises(ForbiddenError, match=r"operator:viewer may not call roof\.open_roof\(\)"):
            await operator.comm.execute("roof", "open_roof", [])
    with operator.comm.acting_as("nobody"), pytest.raises(ForbiddenError, match="operator:nobody may not"):
        await operator.comm.execute("roof", "get_motion_status", [])
    with pytest.raises(ValueError, match="not an identity name"), operator.comm.acting_as("a:b"):
        pass
    await operator.comm.execute("roof", "close_roof", [])  # as itself again: everything
