"""Alpaca discovery on loopback: the UDP query finds AlpacaServer, the management API lists its
devices, and ``nightcrew alpaca discover`` prints them and writes one module file per device that
exists, named by role as ``nightcrew init`` names them.

All traffic stays on this machine: queries go to the loopback broadcast address 127.255.255.255
or to 127.0.0.1, to the discovery port the server picked. alpaca-simulators has neither the UDP
responder nor the management API; ``--server`` finds its devices by asking each for its name.
"""

from __future__ import annotations

import asyncio
import json
import socket
from pathlib import Path

import pytest
import yaml

from nightcrew.bridges.alpaca.discovery import DiscoveredServer, describe_server, discover_servers
from nightcrew.bridges.alpaca.errors import AlpacaConnectionError
from nightcrew.cli.main import main
from nightcrew.config import build_object, load_config, validate_config
from nightcrew.modules import Module
from nightcrew.testing.alpaca import AlpacaSimulator

from .served import Served, served_observatory


@pytest.fixture
async def served() -> Served:  # type: ignore[misc]
    async with served_observatory() as served:
        yield served


@pytest.mark.parametrize("address", ["127.255.255.255", "127.0.0.1"])
async def test_discovery_finds_the_server(served: Served, address: str) -> None:
    port = served.server.discovery_port
    assert port is not None
    found = await discover_servers(address, port=port, wait=0.5)
    assert found == [DiscoveredServer("127.0.0.1", served.server.port)]


async def test_the_responder_answers_only_discovery_queries(served: Served) -> None:
    port = served.server.discovery_port
    assert port is not None
    loop = asyncio.get_running_loop()
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as sock:
        sock.bind(("127.0.0.1", 0))
        sock.setblocking(False)
        for query in (b"hello", b"alpacadiscovery1"):
            await loop.sock_sendto(sock, query, ("127.0.0.1", port))
        # The only answer is the one to the real query.
        data = await asyncio.wait_for(loop.sock_recv(sock, 1024), timeout=10.0)
        assert json.loads(data) == {"AlpacaPort": served.server.port}


async def test_no_server_no_answer() -> None:
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as sock:
        sock.bind(("127.0.0.1", 0))  # a port nobody answers on
        silent = sock.getsockname()[1]
        assert await discover_servers("127.0.0.1", port=silent, wait=0.2, queries=1) == []


async def test_management_api_of_the_found_server(served: Served) -> None:
    info = await describe_server(served.url)
    assert (info.name, info.manufacturer) == ("nightcrew", "nightcrew")
    assert [(d.device_type, d.number, d.name) for d in info.devices] == [
        ("Telescope", 0, "telescope"),
        ("Camera", 0, "camera"),
        ("Dome", 0, "dome"),
        ("Focuser", 0, "focuser"),
        ("FilterWheel", 0, "filters"),
        ("SafetyMonitor", 0, "weather"),
    ]
    assert len({d.unique_id for d in info.devices}) == 6


async def test_cli_lists_and_writes_module_files(
    served: Served, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    port = served.server.discovery_port
    args = ["alpaca", "discover", "--address", "127.255.255.255", "--port", str(port), "--wait", "0.5"]
    code = await asyncio.to_thread(main, [*args, "--write", str(tmp_path)])
    out = capsys.readouterr().out
    assert code == 0, out
    assert f"{served.url}  nightcrew" in out
    assert "  Telescope 0: telescope  [" in out
    files = await asyncio.to_thread(lambda: sorted(p.name for p in tmp_path.glob("*.yaml")))
    # The served dome is the simulated roll-off roof (CanSetAzimuth false): a roof.
    assert files == [
        "camera.yaml",
        "filters.yaml",
        "focuser.yaml",
        "roof.yaml",
        "safetymonitor.yaml",
        "telescope.yaml",
    ]
    camera = load_config(tmp_path / "camera.yaml")
    assert dict(camera) == {
        "class": "nightcrew.modules.alpaca.AlpacaCamera",
        "server": served.url,
        "device_number": 0,
    }
    # Every file is a valid module configuration; all but the telescope (which needs the site) build.
    for name in files:
        config = load_config(tmp_path / name)
        validate_config(config, Module)
        if name != "telescope.yaml":
            assert isinstance(build_object({**config, "name": name.removesuffix(".yaml")}, Module), Module)
    # Nothing is overwritten: a second run refuses before writing anything.
    (tmp_path / "roof.yaml").write_text("# mine\n")
    code = await asyncio.to_thread(main, [*args, "--write", str(tmp_path)])
    assert code == 2
    assert "not overwriting existing files" in capsys.readouterr().err
    assert (tmp_path / "roof.yaml").read_text() == "# mine\n"


async def test_cli_without_servers_says_so(capsys: pytest.CaptureFixture[str]) -> None:
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as sock:
        sock.bind(("127.0.0.1", 0))
        silent = sock.getsockname()[1]
        args = ["alpaca", "discover", "--address", "127.0.0.1", "--port", str(silent), "--wait", "0.2"]
        code = await asyncio.to_thread(main, args)
    assert code == 1
    assert f"no Alpaca server answered (127.0.0.1:{silent})" in capsys.readouterr().err


def test_cli_finds_the_devices_of_alpaca_simulators(
    alpaca_simulator: AlpacaSimulator, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    code = main(["alpaca", "discover", "--server", alpaca_simulator.url, "--write", str(tmp_path)])
    out = capsys.readouterr().out
    assert code == 0, out
    for device in ("Telescope 0", "Camera 0", "Dome 0", "Focuser 0", "FilterWheel 0", "SafetyMonitor 0"):
        assert f"  {device}: " in out
    # Only the devices that exist (the simulators answer for device 0 of each type, and with an
    # error for 1..7), one file each, named by role; its dome turns: a dome, not a roof.
    files = sorted(p.name for p in tmp_path.glob("*.yaml"))
    assert files == [
        "camera.yaml",
        "conditions.yaml",
        "cover.yaml",
        "dome.yaml",
        "filters.yaml",
        "focuser.yaml",
        "rotator.yaml",
        "safetymonitor.yaml",
        "switch.yaml",
        "telescope.yaml",
    ]
    telescope = yaml.safe_load((tmp_path / "telescope.yaml").read_text())
    assert telescope == {
        "class": "nightcrew.modules.alpaca.AlpacaTelescope",
        "server": alpaca_simulator.url,
        "device_number": 0,
    }


async def test_a_server_that_is_not_there(capsys: pytest.CaptureFixture[str]) -> None:
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as sock:
        sock.bind(("127.0.0.1", 0))  # bound, not listening: connections are refused
        url = f"http://127.0.0.1:{sock.getsockname()[1]}"
        with pytest.raises(AlpacaConnectionError, match=f"{url}/management/v1/description"):
            await describe_server(url)
        code = await asyncio.to_thread(main, ["alpaca", "discover", "--server", url])
    assert code == 1
    err = capsys.readouterr().err
    assert f"{url}: {url}/management/v1/description: ClientConnectorError" in err
    assert f"no Alpaca server answered ({url})" in err
