"""Every example of the simulated observatory is a valid configuration that builds a module.

The files live in ``examples/observatory``; the package's ``nightcrew/night/observatory`` is a
link to that directory (a built package holds a copy), so the examples and what ``nightcrew sim``
runs are the same files. ``nightcrew sim`` reads them with :func:`load_in_process` (without their
``comm``) and replaces the ``comm`` and ``clock`` they name for ``nightcrew up``
(tests/supervisor/test_observatory_up.py runs them that way).
"""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from nightcrew.cli.main import main
from nightcrew.config import build_object, config_files, load_config, validate_config
from nightcrew.modules import Module
from nightcrew.night.build import bundled_observatory, files_environ, load_in_process
from nightcrew.night.init import ALPACA_ROLES, FoundDevice, InitOptions, name_by_role, observatory_files

REPOSITORY = Path(__file__).resolve().parents[2]
#: The module files (shared/ holds fragments and the operator's comm).
EXAMPLES = [
    path
    for path in config_files([bundled_observatory()], environ=files_environ())
    if path.parent.name != "shared"
]
#: What `nightcrew sim` puts in place of the files' own.
REPLACED = ("comm", "clock")


def test_examples_observatory_is_the_bundled_observatory() -> None:
    observatory = REPOSITORY / "examples" / "observatory"
    assert observatory.is_dir() and not observatory.is_symlink()  # the one source
    assert bundled_observatory().resolve() == observatory.resolve()
    assert (REPOSITORY / "examples" / "sim").resolve() == observatory.resolve()  # the older name


def test_there_is_an_example_for_every_sim_device() -> None:
    classes = {load_in_process(path)["class"].rsplit(".", 1)[1] for path in EXAMPLES}
    expected = {
        "SimTelescope",
        "SimFocuser",
        "SimFilterWheel",
        "SimRoof",
        "SimDome",
        "SimWeatherStation",
        "SimCamera",
    }
    assert expected <= classes


def test_the_site_fragment_is_not_a_module_file() -> None:
    assert all(path.name != "site.yaml" for path in EXAMPLES)


@pytest.mark.parametrize("path", EXAMPLES, ids=lambda p: p.name)
def test_example_validates_and_builds(path: Path) -> None:
    config = load_in_process(path)
    validate_config(config, Module)
    kept = {key: value for key, value in config.items() if key not in REPLACED}
    module = build_object({**kept, "name": path.stem}, Module)
    assert isinstance(module, Module)


#: Where the bundled device files say how they run as processes (their comm and clock).
PROCESS = "# As a process of its own"


def _alpaca(role: str, device_type: str, *filters: str) -> FoundDevice:
    """A device of alpaca-simulators as ``nightcrew init --alpaca`` finds it."""
    cls = ALPACA_ROLES[device_type][1] if role != "roof" else "nightcrew.modules.alpaca.AlpacaRoof"
    config = {"class": cls, "server": "http://127.0.0.1:11111", "device_number": 0}
    return FoundDevice(role, config, f"Alpaca {device_type} 0", filter_names=filters)


@pytest.mark.usefixtures("bundled_xmpp_files")  # its comm, as `server init xmpp` would give it
def test_init_s_device_files_replace_the_simulated_ones_without_renames(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """docs/observatory.md: the device files ``init`` writes take the place of the simulated ones,
    the robotic modules unchanged, and ``nightcrew check`` passes on the result."""
    found = [
        _alpaca("telescope", "telescope"),
        _alpaca("camera", "camera"),
        _alpaca("roof", "dome"),
        _alpaca("focuser", "focuser"),
        _alpaca("filters", "filterwheel", "V", "R"),
        _alpaca("conditions", "observingconditions"),
    ]
    devices = name_by_role(found)
    options = InitOptions(latitude=51.56, longitude=9.94, comm="embedded")
    layout = observatory_files(options, devices, lambda name: "unused")
    observatory = tmp_path / "observatory"
    ignore = shutil.ignore_patterns("frames", "xmpp", "logs", "*.sqlite*", "*.jsonl")
    shutil.copytree(bundled_observatory(), observatory, ignore=ignore)
    bundled_devices = {path.stem for path in observatory.glob("*.yaml")}
    assert set(devices) == bundled_devices  # every simulated device has its real one, same name
    for name in devices:  # init's file, then the replaced file's lines from PROCESS on (comm, clock)
        path = observatory / f"{name}.yaml"
        process = PROCESS + path.read_text(encoding="utf-8").split(PROCESS, 1)[1]
        path.write_text(layout.files[f"{name}.yaml"] + process, encoding="utf-8")
    # The bundled directory passes as shipped in tests/supervisor/test_observatory_up.py.
    assert main(["check", str(observatory)]) == 0, capsys.readouterr().err
    # What the robotic modules call the weather verdict and the station is what init wrote.
    verdict = load_config(observatory / "robotic" / "weather.yaml")
    assert {str(station["module"]) for station in verdict["stations"].values()} <= set(devices)
    assert load_config(observatory / "robotic" / "mastermind.yaml")["weather"] == "weather"
    assert "weather" in layout.modules  # init's verdict has the name the robotic modules call
