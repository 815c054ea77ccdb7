"""A second process with a supervised module's account: one of them exits non-zero, saying why,
the supervisor reports it and restarts its module; nothing stays alive and offline."""

from __future__ import annotations

import asyncio
import subprocess
import sys

import pytest

from nightcrew.testing import wait_for

from .conftest import REPOSITORY, SupervisedDirectory

pytestmark = pytest.mark.xmpp

TOOK_OVER = "another session took over this account (a second process with the same account?)"


async def test_second_process_with_the_same_account(supervised: SupervisedDirectory) -> None:
    path = supervised.write_module("roofish")
    supervised.up()
    status = await supervised.wait_for_status(lambda s: s["roofish"]["state"] == "running", "running")
    first_pid = status["roofish"]["pid"]
    # Running is not yet logged in: an intruder that logged in first would be the one kicked out.
    log_file = supervised.log_dir / "roofish.log"
    await wait_for(
        lambda: log_file.exists() and "roofish is ready" in log_file.read_text(errors="replace"),
        60,
        message="the supervised roofish logged in",
    )

    intruder = await asyncio.create_subprocess_exec(
        sys.executable, "-m", "nightcrew", "run", str(path),
        cwd=REPOSITORY, env=supervised.env(), stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
    )  # fmt: skip
    try:
        # The server hands the account to the newcomer: the supervised process exits 1, saying why ...
        status = await supervised.wait_for_status(
            lambda s: s["roofish"]["restarts"] >= 1,
            "the supervised module lost its account and was restarted",
        )
        assert status["roofish"]["last_exit"].startswith("exited 1: roofish@")
        assert TOOK_OVER in status["roofish"]["last_exit"]
        assert first_pid != status["roofish"]["pid"]
        # ... and its restart takes the account back: the intruder exits 1 with the same clear error.
        _, output = await asyncio.wait_for(intruder.communicate(), 120)
    finally:
        if intruder.returncode is None:
            intruder.kill()
            await intruder.wait()
    stderr = output.decode()
    assert intruder.returncode == 1
    assert stderr.splitlines()[-1].startswith("nightcrew: error: roofish@")
    assert TOOK_OVER in stderr.splitlines()[-1]
    status = await supervised.wait_for_status(lambda s: s["roofish"]["state"] == "running", "running again")
    assert supervised.terminate() == 0
