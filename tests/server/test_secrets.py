"""``server init`` makes the passwords module and person files keep in ``secrets/``, and writes no
access policy nobody names."""

from __future__ import annotations

import stat
from pathlib import Path

import pytest

from nightcrew.cli.main import main
from nightcrew.errors import ConfigError
from nightcrew.server import Account, accounts_from_configs, create_missing_passwords, policies_named
from nightcrew.testing.processes import free_port

from ..comm.xmpp_servers import require_command

COMM = (
    "comm:\n  class: nightcrew.comm.xmpp.XmppComm\n  jid: {name}@obs.local\n  password: !include {secret}\n"
)


def _module(directory: Path, name: str, secret: str = "") -> Path:
    path = directory / f"{name}.yaml"
    comm = COMM.format(name=name, secret=secret or f"secrets/{name}.password")
    path.write_text("class: nightcrew.modules.Module\n" + comm)
    return path


def test_one_random_private_password_per_account(tmp_path: Path) -> None:
    files = [_module(tmp_path, name) for name in ("roof", "camera")]
    person = tmp_path / "observer.yaml"  # a comm file alone: a person's
    person.write_text(COMM.replace("  ", "").replace("comm:\n", "").format(
        name="observer", secret="secrets/observer.password"))  # fmt: skip
    made = create_missing_passwords([*files, person])
    secrets = tmp_path / "secrets"
    assert made == [secrets / f"{name}.password" for name in ("roof", "camera", "observer")]
    assert stat.S_IMODE(secrets.stat().st_mode) == 0o700
    assert all(stat.S_IMODE(path.stat().st_mode) == 0o600 for path in made)
    accounts = accounts_from_configs([*files, person])
    passwords = {a.user: a.password for a in accounts}
    assert len(set(passwords.values())) == 3 and all(len(p) == 32 for p in passwords.values())
    assert Account("observer", "obs.local", passwords["observer"], person=True) in accounts
    # Kept on a second run: the modules' files and the server's accounts stay in step.
    assert create_missing_passwords([*files, person]) == []
    assert {a.user: a.password for a in accounts_from_configs([*files, person])} == passwords


def test_only_files_in_a_secrets_folder_are_made(tmp_path: Path) -> None:
    elsewhere = _module(tmp_path, "roof", secret="roof.password")
    assert create_missing_passwords([elsewhere]) == []
    with pytest.raises(ConfigError, match=r"cannot include 'roof\.password'"):
        accounts_from_configs([elsewhere])


def test_an_unset_variable_in_the_path_is_one_error(tmp_path: Path) -> None:
    bad = _module(tmp_path, "roof", secret="${NO_SUCH_FOLDER}/roof.password")
    unset = r"roof\.yaml:5: key 'password': environment variable NO_SUCH_FOLDER"
    with pytest.raises(ConfigError, match=unset):
        create_missing_passwords([bad], environ={})


def test_server_init_writes_no_policy_beside_one_the_modules_name(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A `nightcrew init` directory has its access.policy, which comm.yaml names: server init
    writes none into xmpp/ that nobody would name; where the modules name none, it writes one."""
    require_command("prosody", "prosody")
    (tmp_path / "access.policy").write_text("roles: {modules: ['*']}\naccounts: {roof: [modules]}\n")
    (tmp_path / "comm.yaml").write_text("class: nightcrew.comm.xmpp.XmppComm\npolicy: access.policy\n")
    roof = tmp_path / "roof.yaml"
    roof.write_text(
        "class: nightcrew.modules.Module\ncomm:\n  <<: !include comm.yaml\n  jid: roof@obs.local\n"
        "  password: !include secrets/roof.password\n"
    )
    assert main(["server", "init", str(tmp_path / "xmpp"), "--port", str(free_port()), str(roof)]) == 0
    assert policies_named([roof]) == [tmp_path / "access.policy"]
    assert not (tmp_path / "xmpp" / "access.policy").exists()
    assert f"the modules name their access policy ({tmp_path / 'access.policy'}); none written" in (
        capsys.readouterr().out
    )
    (tmp_path / "access.policy").unlink()  # named, but not there: the starting policy is written
    assert main(["server", "init", str(tmp_path / "xmpp"), "--port", str(free_port()), str(roof)]) == 0
    assert (tmp_path / "xmpp" / "access.policy").exists()


def test_a_one_line_overlay_gets_the_password_of_the_file_it_merges(tmp_path: Path) -> None:
    """docs/operations.md, step 5: a host's file that merges an example makes that example's password
    (beside the example); a file writing its own comm makes only its own."""
    (tmp_path / "examples").mkdir()
    bundled = _module(tmp_path / "examples", "roof")
    overlay = tmp_path / "host" / "roof.yaml"
    overlay.parent.mkdir()
    overlay.write_text(f"<<: !include {bundled}\npark_on_close: true\n")
    own = tmp_path / "host" / "camera.yaml"
    own.write_text(f"<<: !include {bundled}\n" + COMM.format(name="camera", secret="secrets/camera.password"))
    made = create_missing_passwords([overlay, own])
    assert made == [
        tmp_path / "examples" / "secrets" / "roof.password",
        tmp_path / "host" / "secrets" / "camera.password",
    ]
    assert {a.user for a in accounts_from_configs([overlay, own])} == {"roof", "camera"}
