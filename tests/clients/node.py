"""Where the JavaScript client lives, and whether Node and its npm packages are there to run it."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from tests.comm.xmpp_servers import require_command

CLIENT = Path(__file__).resolve().parents[2] / "clients" / "js"


def node_ready() -> None:
    """Skip (fail when CI=true) without ``node`` or the client's npm packages (``make js-deps``)."""
    require_command("node", "nodejs")
    if not (CLIENT / "node_modules" / "@xmpp" / "client").is_dir():
        message = "clients/js/node_modules is missing: run `make js-deps`"
        if os.environ.get("CI") == "true":
            pytest.fail(message)
        pytest.skip(message)
