"""The bundled simulated observatory's module processes (``examples/sim-processes``), for tests that
run them as separate ``nightcrew run`` processes on an XMPP server."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
from collections.abc import Iterable
from pathlib import Path

import yaml

from nightcrew.server import Account, accounts_from_configs, create_missing_passwords, policy_for_accounts
from tests.comm.xmpp_servers import DOMAIN, XmppServer

REPOSITORY = Path(__file__).resolve().parents[2]
OVERLAYS = REPOSITORY / "examples" / "sim-processes"
#: Dusk of the default night of ``nightcrew sim``; every process starts its clock here.
CLOCK_START = "2026-11-10T17:50:00"
CLOCK_SPEED = 20.0


def secrets_folder(directory: Path) -> str:
    """The test's SIM_XMPP_SECRETS: where the accounts' passwords are made."""
    return str(directory / "secrets")


def overlay_passwords(directory: Path, domain: str) -> dict[str, str]:
    """What ``nightcrew server init xmpp examples/sim-processes/*.yaml`` (the tutorial's step) makes
    first, for tests on a server of their own: a random password per account of the overlays, made
    as init makes them in :func:`secrets_folder`; the passwords by account, for registering them."""
    return {account.user: account.password for account in _overlay_accounts(directory, domain)}


def _overlay_accounts(directory: Path, domain: str) -> list[Account]:
    environ = {"SIM_XMPP_SECRETS": secrets_folder(directory), "SIM_XMPP_DOMAIN": domain}
    overlays = sorted(OVERLAYS.glob("*.yaml"))
    create_missing_passwords(overlays, environ=environ)
    return accounts_from_configs(overlays, environ=environ)


def starting_policy_file(directory: Path, domain: str, operators: tuple[str, ...] = ()) -> str:
    """The access policy ``nightcrew server init xmpp examples/sim-processes/*.yaml`` writes (the
    tutorial's step), for tests whose server was made without it: its path, for SIM_XMPP_POLICY.
    ``operators``: more people's accounts, given to init with ``--operator NAME`` each."""
    accounts = _overlay_accounts(directory, domain)
    accounts += [Account(name, domain, "-", person=True) for name in operators]
    path = directory / "access.policy"
    path.write_text(yaml.safe_dump(policy_for_accounts(accounts, ("operator", *operators))))
    return str(path)


def overlay_environment(
    server: XmppServer, room: str, directory: Path, modules: Iterable[str], operators: tuple[str, ...] = ()
) -> dict[str, str]:
    """What the overlays read (the tutorial's variables) for processes of ``modules`` on a test's
    server in ``room``: their accounts registered with the passwords ``server init`` makes, the
    starting policy (``operators``: as for :func:`starting_policy_file`); images in directory/images."""
    assert server.ca_file is not None
    passwords = overlay_passwords(directory, DOMAIN)
    for name in modules:
        server.account(name, passwords[name])
    return {
        **os.environ,
        "SIM_XMPP_SECRETS": secrets_folder(directory),
        "SIM_XMPP_SERVER": server.address,
        "SIM_XMPP_DOMAIN": DOMAIN,
        "SIM_XMPP_ROOM": room,
        "SIM_XMPP_CA_FILE": server.ca_file,
        "SIM_XMPP_POLICY": starting_policy_file(directory, DOMAIN, operators),
        "SIM_CLOCK_START": CLOCK_START,
        "SIM_CLOCK_SPEED": str(CLOCK_SPEED),
        "SIM_IMAGES": str(directory / "images"),
    }


class Processes:
    """The module processes, their logs (stderr in files: a pipe nobody reads could fill up)."""

    def __init__(self, logs: Path) -> None:
        self.logs = logs
        self.running: dict[str, subprocess.Popen[bytes]] = {}

    def start(self, name: str, env: dict[str, str]) -> None:
        with open(self.logs / f"{name}.log", "wb") as log:
            self.running[name] = subprocess.Popen(
                [sys.executable, "-m", "nightcrew", "run", str(OVERLAYS / f"{name}.yaml")],
                env=env,
                stdout=subprocess.DEVNULL,
                stderr=log,
            )

    def log(self, name: str) -> str:
        return (self.logs / f"{name}.log").read_text(errors="replace")

    def check_alive(self) -> None:
        for name, process in self.running.items():
            assert process.poll() is None, f"{name} exited {process.returncode}:\n{self.log(name)}"

    def stop(self) -> list[str]:
        """SIGTERM to all, then each must exit 0; returns what went wrong, with the process's log."""
        for process in self.running.values():
            if process.poll() is None:
                process.send_signal(signal.SIGTERM)
        problems = []
        for name, process in self.running.items():
            try:
                process.wait(timeout=15)
            except subprocess.TimeoutExpired:
                problems.append(f"{name} did not stop within 15 s of SIGTERM")
            else:
                if process.returncode != 0:
                    problems.append(f"{name} exited {process.returncode}:\n{self.log(name)}")
        return problems

    def kill(self) -> None:
        for process in self.running.values():
            if process.poll() is None:
                process.kill()
                process.wait()
