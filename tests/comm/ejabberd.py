"""A private ejabberd for the tests: own config, spool and node name, on a free loopback port.

Debian's ``ejabberdctl`` runs everything as the ``ejabberd`` user (via ``su`` when called as
root), so the instance lives in a directory that user owns, and the fixture needs root (as CI has).
Accounts are registered with ``ejabberdctl register`` (each call starts an Erlang VM, so they run
in parallel).
"""

from __future__ import annotations

import os
import shutil
import subprocess
import tempfile
import time
from collections.abc import Iterator
from concurrent.futures import ThreadPoolExecutor
from contextlib import contextmanager
from pathlib import Path

import pytest

from nightcrew.server import Account
from nightcrew.server._tls import make_self_signed

from .xmpp_servers import DOMAIN, XmppServer, free_port

# ejabberdctl's own `started` gives up after ~60 s; an Erlang VM on a loaded 2-core machine can take
# longer, so the fixture asks again up to this many times.
_START_ATTEMPTS = 3
_START_TIMEOUT = 60.0


def ejabberd_config(directory: Path, port: int, certfile: Path) -> str:
    """ejabberd.yml: one loopback c2s port with STARTTLS, SCRAM, no shapers, a non-anonymous MUC."""
    return f"""# Written by the nightcrew test fixture; see docs/xmpp-servers.md.
hosts:
  - {DOMAIN}
loglevel: info
log_rotate_count: 0
certfiles:
  - {certfile}
listen:
  -
    port: {port}
    ip: "127.0.0.1"
    module: ejabberd_c2s
    starttls: true
    shaper: none
    access: c2s
    max_stanza_size: 2097152
auth_method: internal
auth_password_format: scram
acl:
  local:
    user_regexp: ""
access_rules:
  local:
    allow: local
  c2s:
    allow: all
  muc_create:
    allow: local
shaper_rules:
  max_user_sessions: 10
  c2s_shaper: none
modules:
  mod_disco: {{}}
  mod_ping: {{}}
  mod_muc:
    host: "conference.@HOST@"
    access: all
    access_create: muc_create
    history_size: 0
    min_message_interval: 0
    min_presence_interval: 0
    default_room_options:
      anonymous: false
      persistent: false
      mam: false
"""


class EjabberdControl:
    """ejabberdctl with this instance's config, spool, logs and node name."""

    def __init__(self, directory: Path, node: str) -> None:
        self.directory = directory
        self.node = node

    def _ctl(self, *args: str, timeout: float = 60) -> subprocess.CompletedProcess[str]:
        d = self.directory
        command = [
            "ejabberdctl",
            "--node", self.node,
            "--config-dir", str(d),
            "--config", str(d / "ejabberd.yml"),
            "--ctl-config", str(d / "ejabberdctl.cfg"),
            "--spool", str(d / "spool"),
            "--logs", str(d / "logs"),
            *args,
        ]  # fmt: skip
        return subprocess.run(command, capture_output=True, text=True, timeout=timeout, check=False)

    def register(self, account: Account) -> None:
        result = self._ctl("register", account.user, account.domain, account.password)
        if result.returncode != 0 and "already registered" not in result.stdout + result.stderr:
            raise RuntimeError(f"ejabberdctl register {account.jid}: {result.stdout}{result.stderr}")

    def start(self) -> None:
        self._ctl("start")
        for _ in range(_START_ATTEMPTS):
            result = self._ctl("started", timeout=_START_TIMEOUT + 5)  # waits until ejabberd runs
            if result.returncode == 0:
                break
        if result.returncode != 0:
            raise RuntimeError(f"ejabberd did not start: {self.log_tail()}")

    def stop(self) -> None:
        self._ctl("stop")
        self._ctl("stopped", timeout=30)

    def log_tail(self) -> str:
        log = self.directory / "logs" / "error.log"
        return log.read_text()[-2000:] if log.is_file() else "(no error.log)"


@contextmanager
def running_ejabberd(names: list[str], password: str) -> Iterator[XmppServer]:
    if os.geteuid() != 0:
        message = "the ejabberd fixture needs root (ejabberdctl switches to the ejabberd user)"
        if os.environ.get("CI") == "true":
            pytest.fail(message)
        pytest.skip(message)
    # Not under pytest's tmp dir: the ejabberd user must be able to reach it.
    directory = Path(tempfile.mkdtemp(prefix="nightcrew-ejabberd-"))
    port = free_port()
    cert, key = make_self_signed(directory / "certs", DOMAIN)
    pem = directory / "certs" / "server.pem"
    pem.write_text(cert.read_text() + key.read_text())
    (directory / "ejabberd.yml").write_text(ejabberd_config(directory, port, pem))
    # Keep Erlang's port mapper and distribution on loopback; no pidfile in /run.
    (directory / "ejabberdctl.cfg").write_text("ERL_EPMD_ADDRESS=127.0.0.1\nINET_DIST_INTERFACE=127.0.0.1\n")
    for sub in ("spool", "logs"):
        (directory / sub).mkdir()
    shutil.chown(directory, "ejabberd", "ejabberd")
    for path in directory.rglob("*"):
        shutil.chown(path, "ejabberd", "ejabberd")
    control = EjabberdControl(directory, f"nightcrew{port}@localhost")
    started = time.monotonic()
    control.start()
    server = XmppServer("ejabberd", directory, port, control, str(cert))
    try:
        with ThreadPoolExecutor(max_workers=4) as pool:
            list(pool.map(lambda name: server.account(name, password), names))
        print(f"ejabberd ready in {time.monotonic() - started:.1f} s")
        yield server
    finally:
        control.stop()
        shutil.rmtree(directory, ignore_errors=True)
