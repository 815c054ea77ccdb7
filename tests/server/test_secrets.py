"""``server init`` makes the passwords module and person files keep in ``secrets/`` (no server needed)."""

from __future__ import annotations

import stat
from pathlib import Path

import pytest

from nightcrew.errors import ConfigError
from nightcrew.server import Account, accounts_from_configs, create_missing_passwords

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
