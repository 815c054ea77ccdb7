"""Every example directory passes ``nightcrew check`` as shipped (once ``nightcrew server init`` has
made the accounts' passwords, certificate and policy), or says in one line which environment
variables to set; ``check`` tells module files, task files, policies and fragments apart."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from nightcrew.cli.main import main
from nightcrew.server import create_missing_passwords

REPOSITORY = Path(__file__).resolve().parents[2]
EXAMPLES = REPOSITORY / "examples"
DIRECTORIES = sorted(path.name for path in EXAMPLES.iterdir() if path.is_dir() and not path.is_symlink())
#: The variables the examples read for secrets; a developer's shell may have some set.
SECRETS = (
    "NC_FILECACHE_TOKEN",
    "NIGHTCREW_ARCHIVE_TOKEN",
    "TELEGRAM_TOKEN",
    "CHAT_PASSWORD",
)


@pytest.fixture(scope="module")
def passwords(tmp_path_factory: pytest.TempPathFactory) -> str:
    """The examples' accounts' passwords, made once as `nightcrew server init` makes them: their folder."""
    folder = str(tmp_path_factory.mktemp("examples") / "secrets")
    create_missing_passwords(EXAMPLES.rglob("*.yaml"), environ={**os.environ, "SIM_XMPP_SECRETS": folder})
    return folder


@pytest.mark.usefixtures("bundled_xmpp_files")  # the certificate and policy `server init` writes
@pytest.mark.parametrize("directory", DIRECTORIES)
def test_an_example_directory_passes_or_names_the_variables_to_set(
    directory: str, passwords: str, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    for name in SECRETS:
        monkeypatch.delenv(name, raising=False)
    monkeypatch.setenv("SIM_XMPP_SECRETS", passwords)
    code = main(["check", str(EXAMPLES / directory)])
    captured = capsys.readouterr()
    if code != 0:
        assert len(captured.err.splitlines()) == 1, captured.err
        assert captured.err.startswith("set "), captured.err
    else:
        assert captured.err == ""


def test_the_loose_example_files_pass(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["check", *map(str, sorted(EXAMPLES.glob("*.yaml")))]) == 0, capsys.readouterr().err


def test_module_task_policy_and_fragment_files_are_told_apart(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    site = "{latitude: 51.5, longitude: 10.0, elevation: 200}\n"
    (tmp_path / "site.yaml").write_text(site, encoding="utf-8")
    (tmp_path / "standalone.yaml").write_text(
        "class: nightcrew.modules.test.StandAlone\nsite: !include site.yaml\n", encoding="utf-8"
    )
    policy = "roles: {operator: ['*']}\naccounts: {alice: [operator]}\n"
    (tmp_path / "policy.yaml").write_text(policy, encoding="utf-8")
    sample = REPOSITORY / "src" / "nightcrew" / "robotic" / "samples" / "double-cluster.yaml"
    (tmp_path / "double-cluster.yaml").write_text(sample.read_text(encoding="utf-8"), encoding="utf-8")
    (tmp_path / "notes.yaml").write_text("just: notes\n", encoding="utf-8")
    assert main(["check", str(tmp_path)]) == 0
    assert capsys.readouterr().out.splitlines() == [
        f"OK {tmp_path}/double-cluster.yaml (task file)",
        f"SKIP {tmp_path}/notes.yaml: neither a module file (no 'class'), a task file (no 'requests') "
        "nor an access policy (no 'roles'), and no file here includes it",
        f"OK {tmp_path}/policy.yaml (access policy)",
        f"OK {tmp_path}/standalone.yaml",
    ]


def test_an_invalid_task_file_is_one_line_naming_file_and_field(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    sample = REPOSITORY / "src" / "nightcrew" / "robotic" / "samples" / "double-cluster.yaml"
    text = sample.read_text(encoding="utf-8").replace("priority: 1", "priority: 1\ncolour: red")
    (tmp_path / "tasks.yaml").write_text(text, encoding="utf-8")
    assert main(["check", str(tmp_path)]) == 2
    error = capsys.readouterr().err
    assert error.count("\n") == 1 and error.startswith(f"{tmp_path}/tasks.yaml: ") and "colour" in error


def test_a_problem_in_a_fragment_is_one_line_naming_the_files_that_include_it(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    (tmp_path / "xmpp.yaml").write_text(
        "class: nightcrew.comm.xmpp.XmppComm\npassword: secret\nca_file: certs/observatory.crt\n",
        encoding="utf-8",
    )
    for name in ("roof", "telescope", "camera"):
        module = "class: nightcrew.modules.test.StandAlone\ncomm:\n  <<: !include xmpp.yaml\n"
        (tmp_path / f"{name}.yaml").write_text(f"{module}  jid: {name}@obs.local\n", encoding="utf-8")
    assert main(["check", str(tmp_path)]) == 2
    assert capsys.readouterr().err == (
        f"{tmp_path}/xmpp.yaml:3: key 'comm.ca_file': file {tmp_path}/certs/observatory.crt not found "
        f"(included from {tmp_path}/camera.yaml, {tmp_path}/roof.yaml and 1 more)\n"
    )
