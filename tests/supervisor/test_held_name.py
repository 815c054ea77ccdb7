"""A supervisor whose name another account holds on the bus still starts its modules, says why it
is not on the bus yet, and stops cleanly: a held name is waited out, not fatal (docs/security.md)."""

from __future__ import annotations

import pytest

from nightcrew.comm.xmpp import XmppComm
from nightcrew.modules import Module
from nightcrew.testing import wait_for
from tests.comm.xmpp_servers import DOMAIN, PASSWORD

from .conftest import SupervisedDirectory

pytestmark = pytest.mark.xmpp


class _Squatter(XmppComm):
    """Another account of the server entering the room as ``supervisor``."""

    @property
    def name(self) -> str:
        return "supervisor"


async def test_a_held_supervisor_name_keeps_the_modules_running(supervised: SupervisedDirectory) -> None:
    prosody = supervised.prosody
    prosody.account("squatter")
    squatter = Module(
        comm=_Squatter(
            f"squatter@{DOMAIN}",
            PASSWORD,
            server=prosody.address,
            room=supervised.room,
            ca_file=str(prosody.ca_file),
        )
    )
    await squatter.open()
    try:
        prosody.account("supervisor")
        comm = supervised.directory.parent / "supervisor.yaml"
        comm.write_text(f"<<: !include {supervised.directory / 'xmpp.yaml'}\njid: supervisor@{DOMAIN}\n")
        supervised.write_module("zeta")
        supervised.up("--comm", str(comm))
        await supervised.wait_for_status(lambda status: status["zeta"]["state"] == "running", "zeta running")
        message = f"squatter@{DOMAIN} holds the name of module 'supervisor'"
        await wait_for(lambda: message in supervised.supervisor_log(), 30, message="the held name logged")
        assert "trying again in" in supervised.supervisor_log()
        assert supervised.terminate() == 0
    finally:
        await squatter.close()
