"""Running the third-party INDI clients indi_getprop and indi_setprop (Debian indi-bin) from tests."""

from __future__ import annotations

import asyncio
import os
import shutil
import subprocess
from collections.abc import Callable
from pathlib import Path

import pytest

__all__ = ["PATIENCE", "getprop", "require_clients", "run", "setprop", "wait_for"]

#: Wall seconds any one awaited condition may take, even on a loaded machine.
PATIENCE = 60.0
CLIENTS = ("indi_getprop", "indi_setprop")


def require_clients() -> None:
    missing = [tool for tool in CLIENTS if shutil.which(tool) is None]
    if not missing:
        return
    message = f"IndiServer tests need {', '.join(missing)} (make system-deps installs indi-bin)"
    if os.environ.get("CI") == "true":
        pytest.fail(message)
    pytest.skip(message)


async def run(tool: str, *args: str, cwd: Path | None = None) -> tuple[int, str, str]:
    # A blocking run in a thread: Python 3.11's asyncio may leave a quickly failing tool's
    # subprocess transport unclosed (a ResourceWarning that fails whichever test is running).
    result = await asyncio.to_thread(
        subprocess.run, [tool, *args], cwd=cwd, capture_output=True, text=True, timeout=120, check=False
    )
    return result.returncode, result.stdout, result.stderr


async def getprop(port: str, *specs: str) -> dict[str, str]:
    """What indi_getprop reports for ``device.property.element`` specs (all of them, or none)."""
    _, out, _ = await run("indi_getprop", "-p", port, "-t", "5", *specs)
    values = {}
    for line in out.splitlines():
        key, _, value = line.partition("=")
        values[key] = value
    return values


async def setprop(port: str, spec: str) -> None:
    code, out, err = await run("indi_setprop", "-p", port, spec)
    assert code == 0, f"indi_setprop {spec}: exit {code}: {out}{err}"


async def wait_for(
    port: str, specs: list[str], done: Callable[[dict[str, str]], bool], what: str = ""
) -> dict[str, str]:
    """indi_getprop ``specs`` until all are reported and ``done`` holds; fail after PATIENCE."""
    loop = asyncio.get_running_loop()
    deadline = loop.time() + PATIENCE
    values: dict[str, str] = {}
    while loop.time() < deadline:
        values = await getprop(port, *specs)
        if all(spec in values for spec in specs) and done(values):
            return values
        await asyncio.sleep(0.1)  # pace the polling only; the deadline bounds the wait
    raise AssertionError(f"{what or specs} not reached within {PATIENCE} s; last: {values}")
