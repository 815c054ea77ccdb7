"""``nightcrew server init|start|stop|status`` with a real Prosody."""

from __future__ import annotations

import os
import shutil
import socket
import stat
from pathlib import Path

import pytest

from nightcrew.cli.main import main
from nightcrew.comm.xmpp import XmppComm
from nightcrew.errors import ConfigError, ForbiddenError
from nightcrew.interfaces import IModule, ModuleState
from nightcrew.modules import Module
from nightcrew.server import Account, accounts_from_configs, read_password

pytestmark = pytest.mark.xmpp


def _config(path: Path, jid: str, password: str) -> Path:
    path.write_text(
        "class: nightcrew.modules.Module\n"
        "comm:\n"
        "  class: nightcrew.comm.xmpp.XmppComm\n"
        f"  jid: {jid}\n"
        f"  password: {password}\n"
    )
    return path


def _free_port() -> int:
    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        port: int = sock.getsockname()[1]
        return port


def test_accounts_come_from_module_configs_with_env_resolved(tmp_path: Path) -> None:
    camera = _config(tmp_path / "camera.yaml", "camera@obs.local", "${CAMERA_PASSWORD}")
    roof = _config(tmp_path / "roof.yaml", "roof@obs.local/dome", "plain")
    local = tmp_path / "local.yaml"
    local.write_text("class: nightcrew.modules.Module\nname: local\n")
    accounts = accounts_from_configs([camera, roof, local], environ={"CAMERA_PASSWORD": "s3cret"})
    assert accounts == [Account("camera", "obs.local", "s3cret"), Account("roof", "obs.local", "plain")]


def test_accounts_come_from_comm_descriptions_too(tmp_path: Path) -> None:
    # A file holding just a comm, as the operator commands take with --comm.
    operator = tmp_path / "operator.yaml"
    operator.write_text(
        "class: nightcrew.comm.xmpp.XmppComm\njid: operator@obs.local\npassword: ${OP_PASSWORD}\n"
    )
    assert accounts_from_configs([operator], environ={"OP_PASSWORD": "pw"}) == [
        Account("operator", "obs.local", "pw", person=True)
    ]
    bad = tmp_path / "bad.yaml"
    bad.write_text("class: nightcrew.comm.xmpp.XmppComm\njid: operator@obs.local\n")
    with pytest.raises(ConfigError, match="key 'password': missing"):
        accounts_from_configs([bad])


def test_one_jid_with_two_passwords_is_refused(tmp_path: Path) -> None:
    first = _config(tmp_path / "a.yaml", "camera@obs.local", "one")
    second = _config(tmp_path / "b.yaml", "camera@obs.local", "two")
    with pytest.raises(ConfigError, match=r"camera@obs\.local appears twice"):
        accounts_from_configs([first, second])


async def test_init_start_status_stop(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    if shutil.which("prosody") is None:
        if os.environ.get("CI") == "true":
            pytest.fail("prosody is not installed")
        pytest.skip("prosody is not installed")
    os.environ["NC_TEST_CAMERA_PASSWORD"] = "s3cret"
    camera = _config(tmp_path / "camera.yaml", "camera@obs.local", "${NC_TEST_CAMERA_PASSWORD}")
    directory = tmp_path / "server"
    port = _free_port()
    try:
        assert main(["server", "init", str(directory), "--port", str(port), str(camera)]) == 0
        config = (directory / "prosody.cfg.lua").read_text()
        enabled = next(line for line in config.splitlines() if line.startswith("modules_enabled"))
        assert 'interfaces = { "127.0.0.1" }' in config and "limits" not in enabled
        assert main(["server", "status", str(directory)]) == 3
        assert main(["server", "start", str(directory)]) == 0
        assert main(["server", "status", str(directory)]) == 0
        comm = XmppComm(
            "camera@obs.local",
            "s3cret",
            server=f"127.0.0.1:{port}",
            ca_file=str(directory / "certs" / "obs.local.crt"),
            require_tls=True,  # the server offers TLS with the certificate init made
        )
        module = Module(comm=comm)
        await module.open()
        await module.close()
    finally:
        main(["server", "stop", str(directory)])
        del os.environ["NC_TEST_CAMERA_PASSWORD"]
    assert main(["server", "status", str(directory)]) == 3
    out = capsys.readouterr().out
    assert "camera@obs.local" in out and "not running" in out


def test_every_account_is_on_the_shared_roster_and_may_make_pubsub_nodes(tmp_path: Path) -> None:
    # What pyobs-core peers need (docs/pyobs.md); test_pyobs_interop.py shows it working.
    if shutil.which("prosody") is None:
        if os.environ.get("CI") == "true":
            pytest.fail("prosody is not installed")
        pytest.skip("prosody is not installed")
    directory = tmp_path / "server"
    camera = _config(tmp_path / "camera.yaml", "camera@obs.local", "pw1")
    dome = _config(tmp_path / "dome.yaml", "dome@obs.local", "pw2")
    assert main(["server", "init", str(directory), "--port", str(_free_port()), str(camera)]) == 0
    assert main(["server", "init", str(directory), "--port", str(_free_port()), str(dome)]) == 0
    roster = (directory / "groups-obs.local.txt").read_text().split()
    assert roster == ["[+observatory]", "camera@obs.local", "dome@obs.local"]  # init again keeps camera
    config = (directory / "prosody.cfg.lua").read_text()
    assert f'groups_file = "{(directory / "groups-obs.local.txt").resolve()}"' in config
    assert 'Component "pubsub.obs.local" "pubsub"' in config
    assert 'admins = { "camera@obs.local"; "dome@obs.local" }' in config


async def test_a_client_account_without_a_module_file(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """``--account webpage``: a client (a JavaScript page, pyobs) gets its own random password in
    secrets/, and the starting policy lets it in as an observer: it reads, it changes nothing."""
    if shutil.which("prosody") is None:
        if os.environ.get("CI") == "true":
            pytest.fail("prosody is not installed")
        pytest.skip("prosody is not installed")
    camera = _config(tmp_path / "camera.yaml", "camera@obs.local", "pw1")
    directory, port = tmp_path / "server", _free_port()
    assert (
        main(["server", "init", str(directory), "--port", str(port), "--account", "webpage", str(camera)])
        == 0
    )
    secret = directory / "secrets" / "webpage.password"
    assert f"account webpage@obs.local: its password is in {secret} (mode 0600)" in capsys.readouterr().out
    assert stat.S_IMODE(secret.stat().st_mode) == 0o600
    password = read_password(secret)
    assert (
        main(["server", "init", str(directory), "--port", str(port), "--account", "webpage", str(camera)])
        == 0
    )
    assert read_password(secret) == password  # kept: the client's copy stays valid

    def comm(jid: str, password: str) -> XmppComm:
        return XmppComm(
            jid, password, server=f"127.0.0.1:{port}", ca_file=str(directory / "certs" / "obs.local.crt"),
            policy=str(directory / "access.policy"),
        )  # fmt: skip

    module, client = (
        Module(comm=comm("camera@obs.local", "pw1")),
        Module(comm=comm("webpage@obs.local", password)),
    )
    assert main(["server", "start", str(directory)]) == 0
    try:
        await module.open()
        await client.open()  # admitted to the members-only room by the policy
        camera_proxy = await client.comm.proxy("camera", IModule)
        assert await camera_proxy.get_state() is ModuleState.READY
        with pytest.raises(ForbiddenError):
            await camera_proxy.reset_error()
        await client.close()
        await module.close()
    finally:
        main(["server", "stop", str(directory)])


@pytest.mark.parametrize(
    ("name", "message"),
    [
        ("camera", "a module or person file already has this account\n"),
        ("we b", "a name of letters, digits, '.', '_' or '-'\n"),
    ],
)
def test_a_bad_client_account_is_one_error(
    tmp_path: Path, name: str, message: str, capsys: pytest.CaptureFixture[str]
) -> None:
    camera = _config(tmp_path / "camera.yaml", "camera@obs.local", "pw1")
    assert main(["server", "init", str(tmp_path / "server"), "--account", name, str(camera)]) == 2
    assert capsys.readouterr().err == f"nightcrew: error: --account {name!r}: {message}"
    assert not (tmp_path / "server").exists()
