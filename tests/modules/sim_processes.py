"""The bundled simulated observatory's module processes (``examples/sim-processes``), for tests that
run them as separate ``nightcrew run`` processes on an XMPP server."""

from __future__ import annotations

import signal
import subprocess
import sys
from pathlib import Path

import yaml

from nightcrew.server import Account, accounts_from_configs, policy_for_accounts

REPOSITORY = Path(__file__).resolve().parents[2]
OVERLAYS = REPOSITORY / "examples" / "sim-processes"
#: Dusk of the default night of ``nightcrew sim``; every process starts its clock here.
CLOCK_START = "2026-11-10T17:50:00"
CLOCK_SPEED = 20.0


def starting_policy_file(directory: Path, domain: str, operators: tuple[str, ...] = ()) -> str:
    """The access policy ``nightcrew server init xmpp examples/sim-processes/*.yaml`` writes (the
    tutorial's step), for tests whose server was made without it: its path, for SIM_XMPP_POLICY.
    ``operators``: more people's accounts, given to init with ``--operator NAME`` each."""
    environ = {"SIM_XMPP_PASSWORD": "-", "SIM_XMPP_DOMAIN": domain}
    accounts = accounts_from_configs(sorted(OVERLAYS.glob("*.yaml")), environ=environ)
    accounts += [Account(name, domain, "-", person=True) for name in operators]
    path = directory / "access.policy"
    path.write_text(yaml.safe_dump(policy_for_accounts(accounts, ("operator", *operators))))
    return str(path)


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
