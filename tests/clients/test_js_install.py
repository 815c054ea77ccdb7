"""The generated client installed as docs/clients.md says, from a directory of one's own."""

from __future__ import annotations

import os
import subprocess
from pathlib import Path

from .node import CLIENT, node_ready

SCRIPT = """\
import { ICamera, INTERFACES, NightcrewClient } from "nightcrew-client";
console.log(typeof NightcrewClient, Object.keys(INTERFACES).length, typeof ICamera.prototype.grab_data);
"""


def test_the_client_installs_into_any_directory_and_imports_by_name(tmp_path: Path) -> None:
    node_ready()
    # The documented command, in a directory of one's own; offline: a local directory needs no registry.
    quiet = {"npm_config_offline": "true", "npm_config_audit": "false", "npm_config_fund": "false"}
    env = {**os.environ, **quiet}
    install = subprocess.run(
        ["npm", "install", str(CLIENT)], cwd=tmp_path, env=env, capture_output=True, text=True, timeout=120
    )
    assert install.returncode == 0, install.stderr
    (tmp_path / "script.mjs").write_text(SCRIPT)
    run = subprocess.run(["node", "script.mjs"], cwd=tmp_path, capture_output=True, text=True, timeout=60)
    assert run.returncode == 0, run.stderr
    kind, count, method = run.stdout.split()
    assert (kind, method) == ("function", "function") and int(count) > 40
