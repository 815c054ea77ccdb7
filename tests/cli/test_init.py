"""``nightcrew init DIR`` against alpaca-simulators: an observatory directory, all of it or nothing.

The directory holds one module file per device that exists, named by role; the site; the comm
(XMPP: a password per account in secrets/, mode 0600, and the access policy; embedded: none); and
the robotic modules the devices allow. Every file passes ``nightcrew check``.
"""

from __future__ import annotations

import stat
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path

import pytest
import yaml

from nightcrew.cli.main import main
from nightcrew.config import config_files, load_config
from nightcrew.events import hardware_event_names
from nightcrew.night.init import FoundDevice, InitOptions, name_by_role, observatory_files
from nightcrew.security import load_policy
from nightcrew.testing.alpaca import AlpacaSimulator
from tests.observatory.simulators import run_alpaca_simulators, server_init

DEVICES = {"telescope", "camera", "dome", "focuser", "filters", "rotator", "safetymonitor", "conditions"}
DEVICES |= {"cover", "switch"}
ROBOTIC = {"weather", "scheduler", "mastermind", "watchdog", "focus", "flatfield", "flatpointing", "pipeline"}
ROBOTIC |= {"console"}
SITE = ["--latitude", "48", "--longitude", "8", "--elevation", "1000", "--timezone", "Europe/Berlin"]


@pytest.fixture(scope="module")
def simulator(tmp_path_factory: pytest.TempPathFactory) -> Iterator[AlpacaSimulator]:
    yield from run_alpaca_simulators(tmp_path_factory.mktemp("alpaca-simulators"))


def init(*args: str) -> int:
    return main(["init", *args])


def check(directory: Path, monkeypatch: pytest.MonkeyPatch, *, but: tuple[str, ...] = ()) -> None:
    """Every file `nightcrew check DIR` checks passes (``but`` those named), run in DIR as the
    guide does (relative paths there: the policy, the certificate, the task archive)."""
    monkeypatch.chdir(directory)
    files = [str(p) for p in config_files(["."]) if p.name not in but]
    assert main(["check", *files]) == 0


def test_an_xmpp_observatory_for_the_alpaca_simulators(
    simulator: AlpacaSimulator,
    tmp_path: Path,
    capsys: pytest.CaptureFixture[str],
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    directory = tmp_path / "observatory"
    assert init(str(directory), "--non-interactive", "--alpaca", simulator.url, *SITE) == 0
    out = capsys.readouterr().out
    assert out.startswith(f"wrote {directory}: telescope, camera, dome, ")
    modules = {p.stem for p in directory.glob("*.yaml")} - {"comm"}
    assert modules == DEVICES | ROBOTIC | {"operator", "observer"}
    camera = load_config(directory / "camera.yaml")
    assert (camera["class"], camera["server"], camera["device_number"]) == (
        "nightcrew.modules.alpaca.AlpacaCamera",
        simulator.url,
        0,
    )
    assert camera["comm"]["jid"] == "camera@observatory.local"
    assert dict(load_config(directory / "shared" / "site.yaml")) == {
        "latitude": 48.0,
        "longitude": 8.0,
        "elevation": 1000.0,
    }
    # A random password per account, readable by its owner only; every module has one.
    secrets = directory / "secrets"
    assert stat.S_IMODE(secrets.stat().st_mode) == 0o700
    passwords = {}
    for name in modules:
        path = secrets / f"{name}.password"
        assert stat.S_IMODE(path.stat().st_mode) == 0o600, path
        passwords[name] = yaml.safe_load(path.read_text())
    assert len(set(passwords.values())) == len(passwords)
    assert load_config(directory / "camera.yaml")["comm"]["password"] == passwords["camera"]
    # The policy names every module, the operator and the observer.
    policy = load_policy(directory / "access.policy")
    assert set(policy.accounts) >= modules
    assert policy.roles_of("observer") == ("observer",) and policy.roles_of("operator") == ("operator",)
    # Events that move hardware only from the weather verdict and the watchdog (docs/security.md);
    # rapid-response requests that pre-empt from the modules and the operator.
    # (and a focus series' result, which a person may not forge, from the modules: not a hardware event)
    assert sorted(policy.events) == sorted([*hardware_event_names(), "FocusFoundEvent"])
    for name in hardware_event_names():
        senders = {
            account for account in policy.accounts if policy.accepts_event(account, name, moves_hardware=True)
        }
        if name == "RapidResponseEvent":
            granted = {a for a in policy.accounts if {"modules", "operator"} & set(policy.roles_of(a))}
            assert senders == granted and "operator" in granted and "observer" not in granted, name
        else:
            assert senders == {"weather", "watchdog"}, name
    # The scheduler and the mastermind share one task archive, relative to the directory.
    for name in ("scheduler", "mastermind"):
        archive = load_config(directory / f"{name}.yaml")["archive"]
        assert dict(archive) == {
            "class": "nightcrew.robotic.archives.SqliteTaskArchive",
            "path": "tasks.sqlite",
        }
    assert load_config(directory / "mastermind.yaml")["roof"] == "dome"  # the simulator's dome turns
    # As the guide does: the server's accounts and certificate, then the check (which finds the files).
    server_init(directory, monkeypatch)
    check(directory, monkeypatch, but=("scheduler.yaml",))


def test_the_whole_directory_passes_check(
    simulator: AlpacaSimulator, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    assert init(str(tmp_path / "o"), "--non-interactive", "--alpaca", simulator.url, *SITE) == 0
    server_init(tmp_path / "o", monkeypatch)
    assert main(["check", "."]) == 0


def test_an_embedded_observatory_has_no_comm_and_no_secrets(
    simulator: AlpacaSimulator, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    directory = tmp_path / "one-process"
    assert (
        init(str(directory), "--non-interactive", "--comm", "embedded", "--alpaca", simulator.url, *SITE) == 0
    )
    assert not (directory / "comm.yaml").exists() and not (directory / "access.policy").exists()
    # Only the people's console passwords: no module logs in anywhere.
    assert {p.name for p in (directory / "secrets").iterdir()} == {
        "console-accounts.yaml",
        "operator.password",
        "observer.password",
    }
    assert "comm" not in load_config(directory / "telescope.yaml")
    # the dead-man's switch: what the watchdog secures also secures itself when it falls silent
    for secured in ("telescope", "dome"):
        assert load_config(directory / f"{secured}.yaml")["watchdog"] == "watchdog"
    check(directory, monkeypatch, but=("scheduler.yaml",))


def test_a_non_empty_directory_is_refused_unless_forced(
    simulator: AlpacaSimulator, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    (tmp_path / "tasks.sqlite").write_text("mine")
    (tmp_path / "camera.yaml").write_text("# mine\n")
    assert init(str(tmp_path), "--non-interactive", "--alpaca", simulator.url, *SITE) == 2
    assert (
        capsys.readouterr().err.strip()
        == f"nightcrew: error: {tmp_path} is not empty; use --force to write into it"
    )
    assert sorted(p.name for p in tmp_path.iterdir()) == ["camera.yaml", "tasks.sqlite"]
    assert init(str(tmp_path), "--non-interactive", "--force", "--alpaca", simulator.url, *SITE) == 0
    assert (tmp_path / "tasks.sqlite").read_text() == "mine"  # what is not init's stays
    assert load_config(tmp_path / "camera.yaml")["class"] == "nightcrew.modules.alpaca.AlpacaCamera"
    assert not list(tmp_path.parent.glob(f".{tmp_path.name}.init-*"))  # no staging folder left


def test_an_unreachable_server_is_one_line_and_nothing_is_written(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    url = "http://127.0.0.1:9"  # the discard port: nothing listens on loopback
    assert init(str(tmp_path / "o"), "--non-interactive", "--alpaca", url, *SITE) == 1
    err = capsys.readouterr().err.strip()
    assert err.startswith(f"nightcrew: error: Alpaca server {url}: ") and "\n" not in err
    assert list(tmp_path.iterdir()) == []


def test_non_interactive_needs_the_site_and_a_server(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    assert init(str(tmp_path / "o"), "--non-interactive", "--alpaca", "http://127.0.0.1:9") == 2
    assert "--latitude is needed with --non-interactive" in capsys.readouterr().err
    assert init(str(tmp_path / "o"), "--non-interactive", *SITE) == 2
    assert "name the devices' servers: --alpaca URL" in capsys.readouterr().err
    assert (
        init(str(tmp_path / "o"), "--non-interactive", *SITE, "--timezone", "Mars/Olympus", "--indi", "x")
        == 2
    )
    assert "unknown time zone 'Mars/Olympus'" in capsys.readouterr().err
    assert list(tmp_path.iterdir()) == []


def test_interactive_init_asks_with_defaults(simulator: AlpacaSimulator, tmp_path: Path) -> None:
    directory = tmp_path / "asked"
    # Latitude, longitude, then the defaults (elevation, name, time zone, horizon, comm), then servers.
    answers = f"51.5\n9.9\n\nHill top\n\n\n\n{simulator.url}\n\n"
    done = subprocess.run(
        [sys.executable, "-m", "nightcrew", "init", str(directory)],
        input=answers,
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
    )
    assert done.returncode == 0, done.stderr
    assert "Latitude, degrees north: " in done.stdout and "Time zone [UTC]: " in done.stdout
    site = load_config(directory / "shared" / "site.yaml")
    assert dict(site) == {"latitude": 51.5, "longitude": 9.9, "elevation": 0.0, "name": "Hill top"}
    assert (directory / "comm.yaml").exists()


def test_names_by_role_number_only_where_a_role_repeats() -> None:
    def device(role: str) -> FoundDevice:
        return FoundDevice(role, {"class": "x"}, role)

    named = name_by_role([device("camera"), device("telescope"), device("camera"), device("roof")])
    assert list(named) == ["telescope", "camera1", "camera2", "roof"]
    with pytest.raises(ValueError, match="unknown role 'mirror'"):
        device("mirror")


def test_robotic_modules_only_where_their_devices_exist() -> None:
    options = InitOptions(latitude=48.0, longitude=8.0)
    devices = {
        "telescope": FoundDevice("telescope", {"class": "t"}, "mount"),
        "camera": FoundDevice("camera", {"class": "c"}, "ccd"),
    }
    layout = observatory_files(options, devices, lambda name: f"pw-{name}")
    assert layout.modules == ["telescope", "camera", "scheduler", "pipeline", "console"]
    assert layout.left_out == {
        "weather": "no safety monitor or weather station found",
        "focus": "needs a camera and a focuser",
        "flatfield": "needs a camera, a telescope and a filter wheel that names its filters",
        "mastermind": "needs a telescope, a camera, a roof or dome and a weather verdict",
        "watchdog": "watches the mastermind and the weather verdict",
    }
    assert yaml.safe_load(layout.files["secrets/camera.password"]) == "pw-camera"
