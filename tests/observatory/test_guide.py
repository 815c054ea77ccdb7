"""docs/observatory.md, run as written against alpaca-simulators and a private Prosody.

Every ```sh block of the guide runs in order in one temporary home directory (``~``), with this
test's free ports in place of the guide's 11111 (Alpaca), 5222 (XMPP) and 37180 (console): the guide
cannot rot. Without alpaca-simulators or Prosody the test skips, except under CI=true.
"""

from __future__ import annotations

import os
import re
import sys
from pathlib import Path

import pytest

from nightcrew.server import stop_server
from nightcrew.testing.processes import free_port
from tests.comm.xmpp_servers import require_command

from .guide import Guide, shell_blocks
from .simulators import require_simulators

pytestmark = pytest.mark.xmpp
GUIDE = Path(__file__).resolve().parents[2] / "docs" / "observatory.md"


@pytest.mark.timeout(600)  # servers, some twenty modules and every step of the guide, busy machine
def test_the_guide_runs_as_written(tmp_path: Path) -> None:
    require_simulators()
    require_command("prosody", "prosody")
    ports = {"11111": free_port(), "5222": free_port(), "37180": free_port()}
    blocks = shell_blocks(GUIDE.read_text())
    assert len(blocks) >= 10
    environment = {
        **os.environ,
        "PATH": f"{Path(sys.executable).parent}:{os.environ['PATH']}",
        "NIGHTCREW_SUPERVISOR_SOCKET": str(tmp_path / "supervisor.sock"),
    }
    environment.pop("NIGHTCREW_COMM", None)
    guide = Guide(tmp_path, environment)
    outputs = []
    try:
        for block in blocks:
            for placeholder, port in ports.items():
                block = block.replace(placeholder, str(port))
            outputs.append(guide.run_block(block))
    finally:
        guide.stop()
        if (tmp_path / "observatory" / "xmpp" / "prosody.pid").exists():
            stop_server(tmp_path / "observatory" / "xmpp")  # the guide stopped short of its last block
    shown = "\n".join(outputs)
    observatory = tmp_path / "observatory"
    assert "  Telescope 0: Simulator Telescope" in shown
    assert f"wrote {observatory}: telescope, camera, dome, " in shown
    assert "OK mastermind.yaml" in shown and "OK scheduler.yaml" in shown
    assert "prosody running" in shown
    for module in ("telescope", "camera", "dome", "mastermind", "scheduler", "weather", "console"):
        assert f"\n{module} " in shown and "running" in shown
    # Told over the operator's comm, the scheduler plans it at once: listed as planned, or still pending.
    assert re.search(r"\b(PENDING|SCHEDULED) +M31 first light", shown), shown
    assert "\n200\n" in shown  # the console answers
    assert (observatory / "units" / "nightcrew.service").exists()
