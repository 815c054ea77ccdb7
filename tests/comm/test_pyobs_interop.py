"""pyobs-core 2.19.1 modules and nightcrew modules in one observatory, on one Prosody.

The pyobs modules (pyobs' own DummyRaDecTelescope and two small modules in pyobs_peer/) run as
separate processes with pyobs' own runner and YAML configs, in pyobs' own venv (built once and
cached: pyobs_venv.py); the nightcrew modules run here with ``XmppComm(dialect="pyobs")``. The
server is the one ``nightcrew server`` sets up (shared roster, PubSub), with every account
registered before it starts.
"""

from __future__ import annotations

import asyncio
import logging
import os
import signal
import subprocess
import sys
import time
import xml.etree.ElementTree as ET
from abc import abstractmethod
from collections.abc import AsyncIterator, Iterator
from dataclasses import dataclass
from pathlib import Path

import pytest

from nightcrew.comm.xmpp import XmppComm
from nightcrew.errors import InterfaceError
from nightcrew.events import LogEvent, MotionStatusChangedEvent, MoveRaDecEvent, NewImageEvent
from nightcrew.interfaces import FitsCard, IData, IFitsHeaderBefore, ImageType, IPointingRaDec, MotionStatus
from nightcrew.interfaces.base import Interface
from nightcrew.modules import Module
from nightcrew.modules.sim import SimFilterWheel
from nightcrew.server import Account, init_server, start_server, stop_server
from nightcrew.testing.waiting import wait_for

from .pyobs_venv import pyobs_venv
from .sample import Calculator
from .xmpp_servers import DOMAIN, PASSWORD, free_port, require_command

pytestmark = pytest.mark.xmpp
PEER_DIR = Path(__file__).resolve().parent / "pyobs_peer"
NIGHTCREW_MODULES = ["nccamera", "nccalc", "ncraw", "ncwheel", "operator"]
#: pyobs modules by account: the class and extra YAML lines. pyobs' own dummy telescope stands at
#: latitude 89.9°, so that dec 89.5° is above its altitude limit at any time of day.
PYOBS_MODULES = {
    "pycamera": ("pyobs_peer_modules.PyCamera", ""),
    "shooter": ("pyobs_peer_modules.Shooter", ""),
    "pytelescope": (
        "pyobs.modules.telescope.DummyRaDecTelescope",
        "location: {longitude: 0.0, latitude: 89.9, elevation: 0.0}\n",
    ),
}
_PEER_START_TIMEOUT = 90.0  # pyobs imports astropy & co.: slow on a loaded 2-core machine


class IInteropShooter(Interface):
    """The interface the pyobs ``Shooter`` offers, declared here under the same name."""

    @abstractmethod
    async def shoot(self, camera: str, broadcast: bool) -> list[str]: ...

    @abstractmethod
    async def add_remote(self, module: str, a: float, b: float, as_dataclass: bool) -> str: ...

    @abstractmethod
    async def call_remote(self, module: str, method: str) -> str: ...

    @abstractmethod
    async def headers(self, module: str) -> list[str]: ...

    @abstractmethod
    async def states(self, module: str) -> list[str]: ...


class NightcrewCamera(Module, IData, IFitsHeaderBefore):
    """A nightcrew IData module that also keeps the events it hears and gives one FITS card."""

    def __init__(self, **kwargs: object) -> None:
        super().__init__(**kwargs)  # type: ignore[arg-type]
        self.heard: list[tuple[str, str, ImageType | None]] = []
        self.moves: list[tuple[str, float, float]] = []
        self.motions: list[tuple[str, MotionStatus]] = []
        self.logs: list[tuple[str, LogEvent]] = []

    async def open(self) -> None:
        await super().open()
        await self.comm.register_event(NewImageEvent, self.on_new_image)
        await self.comm.register_event(MoveRaDecEvent, self.on_move)
        await self.comm.register_event(MotionStatusChangedEvent, self.on_motion)
        await self.comm.register_event(LogEvent, self.on_log)

    async def on_log(self, event: LogEvent, sender: str) -> None:
        self.logs.append((sender, event))

    async def on_move(self, event: MoveRaDecEvent, sender: str) -> None:
        self.moves.append((sender, event.ra, event.dec))

    async def on_motion(self, event: MotionStatusChangedEvent, sender: str) -> None:
        self.motions.append((sender, event.status))

    async def on_new_image(self, event: NewImageEvent, sender: str) -> None:
        self.heard.append((sender, event.filename, event.image_type))

    async def get_fits_header_before(self, namespaces: list[str] | None = None) -> dict[str, FitsCard]:
        return {"CCD-TEMP": (-10.5, "sensor temperature [degC]")}

    async def grab_data(self, broadcast: bool = True, image_type: ImageType | None = None) -> str:
        filename = "/nightcrew/images/nc-0001.fits"
        if broadcast:
            await self.comm.send_event(NewImageEvent(filename=filename, image_type=ImageType.OBJECT))
        return filename


# --- fixtures: the server, pyobs' venv, pyobs' processes ------------------------------------------


@dataclass(frozen=True)
class Server:
    address: str
    ca_file: str


@pytest.fixture(scope="module")
def interop_server(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Server]:
    """A Prosody from ``nightcrew server``, every account registered before it starts (shared roster)."""
    require_command("prosody", "prosody")
    directory = tmp_path_factory.mktemp("prosody-pyobs")
    accounts = [Account(name, DOMAIN, PASSWORD) for name in [*NIGHTCREW_MODULES, *PYOBS_MODULES]]
    port = free_port()
    init_server(directory, accounts, host="127.0.0.1", port=port, domains=[DOMAIN])
    start_server(directory)
    try:
        yield Server(f"127.0.0.1:{port}", str(directory / "certs" / f"{DOMAIN}.crt"))
    finally:
        stop_server(directory)


@pytest.fixture(scope="session")
def pyobs_python() -> Path:
    started = time.monotonic()
    venv = pyobs_venv()
    logging.getLogger(__name__).info("pyobs venv ready in %.1f s", time.monotonic() - started)
    return venv


@pytest.fixture(scope="module")
def pyobs_peers(
    interop_server: Server, pyobs_python: Path, tmp_path_factory: pytest.TempPathFactory
) -> Iterator[dict[str, Path]]:
    """pyobs' runner with one YAML config per pyobs module; their log files by module name."""
    directory = tmp_path_factory.mktemp("pyobs-peers")
    processes: list[subprocess.Popen[bytes]] = []
    logs = {}
    try:
        for name, (cls, extra) in PYOBS_MODULES.items():
            config = directory / f"{name}.yaml"
            config.write_text(
                f"class: {cls}\n{extra}"
                "comm:\n"
                "  class: pyobs.comm.xmpp.XmppComm\n"
                f"  jid: {name}@{DOMAIN}\n"
                f"  password: {PASSWORD}\n"
                f"  server: {interop_server.address}\n"
                # pyobs' use_tls turns on direct TLS with STARTTLS, which a STARTTLS-only port
                # refuses; on loopback the server allows a plain stream (docs/pyobs.md).
                "  use_tls: false\n"
            )
            logs[name] = directory / f"{name}.log"
            command = [
                str(pyobs_python / "bin" / "pyobs"),
                str(config),
                "--iers-offline",
                "--log-level",
                "info",
            ]
            with logs[name].open("wb") as log_file:
                processes.append(
                    subprocess.Popen(
                        command,
                        cwd=directory,
                        env={**os.environ, "PYTHONPATH": str(PEER_DIR)},
                        stdin=subprocess.DEVNULL,
                        stdout=log_file,
                        stderr=subprocess.STDOUT,
                    )
                )
        yield logs
    finally:
        for process in processes:
            _stop(process)


def _stop(process: subprocess.Popen[bytes]) -> None:
    if process.poll() is None:
        process.send_signal(signal.SIGINT)  # pyobs' runner shuts down cleanly on SIGINT
        try:
            process.wait(15)
        except subprocess.TimeoutExpired:
            process.kill()
            process.wait(5)


@pytest.fixture
async def nightcrew_side(
    interop_server: Server, pyobs_peers: dict[str, Path]
) -> AsyncIterator[NightcrewCamera]:
    """nightcrew's camera and calculator in the pyobs dialect, once the pyobs modules are online."""
    camera = NightcrewCamera(comm=_comm("nccamera", interop_server))
    calculator = Calculator(comm=_comm("nccalc", interop_server))
    await camera.open()
    await calculator.open()
    try:

        def peers_online() -> bool:
            for name, log_file in pyobs_peers.items():
                text = log_file.read_text(errors="replace")
                assert "Traceback" not in text or name in camera.comm.clients, (
                    f"{name} failed:\n{text[-3000:]}"
                )
            return all(
                name in camera.comm.clients and name in calculator.comm.clients for name in PYOBS_MODULES
            )

        await wait_for(peers_online, _PEER_START_TIMEOUT, message="pyobs modules online for nightcrew")
        yield camera
    finally:
        await calculator.close()
        await camera.close()


def _comm(name: str, server: Server) -> XmppComm:
    return XmppComm(
        f"{name}@{DOMAIN}",
        PASSWORD,
        server=server.address,
        ca_file=server.ca_file,
        room="interop",
        dialect="pyobs",
        policy="open",  # about interoperation, not access: pyobs peers call these modules
    )


async def _shooter(camera: NightcrewCamera) -> IInteropShooter:
    return await camera.comm.proxy("shooter", IInteropShooter)


# --- the tests ----------------------------------------------------------------------------------


async def test_nightcrew_moves_pyobs_own_dummy_telescope(
    nightcrew_side: NightcrewCamera, caplog: pytest.LogCaptureFixture
) -> None:
    camera = nightcrew_side
    telescope = await camera.comm.proxy("pytelescope", IPointingRaDec)  # pyobs' interface of that name
    await telescope.move_radec(10.0, 89.5)
    # pyobs sends its MoveRaDecEvent as the move starts.
    await wait_for(lambda: ("pytelescope", 10.0, 89.5) in camera.moves, 20, message="MoveRaDecEvent")
    # Its MotionStatusChangedEvent carries per-interface statuses nightcrew drops knowingly.
    await wait_for(lambda: ("pytelescope", MotionStatus.SLEWING) in camera.motions, 20, message="slewing")
    # pyobs forwards its log records as LogEvents: they arrive as nightcrew's, without a warning each.
    await wait_for(lambda: any(s == "pytelescope" for s, _ in camera.logs), 20, message="pyobs' LogEvent")
    assert "skipped pyobs LogEvent" not in caplog.text
    assert {e.logger for s, e in camera.logs if s == "pytelescope"} == {"pyobs"}


async def test_nightcrew_calls_pyobs_and_hears_its_event(nightcrew_side: NightcrewCamera) -> None:
    camera = nightcrew_side
    pycamera = await camera.comm.proxy("pycamera", IData)  # pyobs' IData, mapped by name
    filename = await pycamera.grab_data(True)
    assert filename.startswith("/pyobs/images/frame-")
    await wait_for(
        lambda: ("pycamera", filename, ImageType.OBJECT) in camera.heard,
        20,
        message="pyobs' NewImageEvent at nightcrew",
    )


async def test_pyobs_calls_nightcrew_and_hears_its_event(nightcrew_side: NightcrewCamera) -> None:
    # nightcrew → shooter (pyobs) → nccamera.grab_data (nightcrew) → NewImageEvent → shooter.
    shooter = await _shooter(nightcrew_side)
    called, heard, sender = await shooter.shoot("nccamera", True)
    assert called == "/nightcrew/images/nc-0001.fits"
    assert (heard, sender) == (called, "nccamera")


async def test_pyobs_gets_typed_results_and_nightcrew_errors(nightcrew_side: NightcrewCamera) -> None:
    shooter = await _shooter(nightcrew_side)
    assert await shooter.add_remote("nccalc", 2.5, 4.0, False) == "float 6.5"
    # A dataclass where nightcrew expects a number: refused with one clear error, as pyobs' own.
    refused = await shooter.add_remote("nccalc", 2.5, 4.0, True)
    assert refused == "InvalidArgumentError: add(): argument 'a': expected number, got object"


async def test_fits_cards_are_pairs_in_nightcrew_and_header_entries_in_pyobs(
    nightcrew_side: NightcrewCamera,
) -> None:
    # pyobs-core 2.19 reads a card as FitsHeaderEntry(value, comment); nightcrew's is a pair.
    shooter = await _shooter(nightcrew_side)
    assert await shooter.headers("nccamera") == ["CCD-TEMP=-10.5/sensor temperature [degC]"]
    telescope = await nightcrew_side.comm.proxy("pytelescope", IFitsHeaderBefore)
    cards = await telescope.get_fits_header_before()
    value, comment = cards["TEL-RA"]
    assert isinstance(value, float) and comment == "Right ascension of telescope [degrees]"


async def test_pyobs_reads_a_nightcrew_filter_wheels_live_state(
    interop_server: Server, nightcrew_side: NightcrewCamera
) -> None:
    wheel = SimFilterWheel(comm=_comm("ncwheel", interop_server), filters=["V", "R"], change_time=0.1)
    await wheel.open()
    try:
        await wheel.set_filter("R")
        shooter = await _shooter(nightcrew_side)
        # As a pyobs GUI does: subscribe to the IFilters and IMotion states, read the current ones.
        assert await shooter.states("ncwheel") == ["R", "idle"]
    finally:
        await wheel.close()


async def test_pyobs_callers_hear_nightcrews_timeout_announcements(nightcrew_side: NightcrewCamera) -> None:
    shooter = await _shooter(nightcrew_side)
    # too_slow() announces 0.3 s (sent to pyobs as 1 s) and takes 5: pyobs' default of 10 s would
    # wait for its result; the announcement makes the pyobs caller give up first.
    assert await shooter.call_remote("nccalc", "too_slow") == "TimeoutError: "


async def test_pyobs_event_with_unknown_field_is_logged_and_skipped(
    nightcrew_side: NightcrewCamera, caplog: pytest.LogCaptureFixture
) -> None:
    camera = nightcrew_side
    pycamera = await camera.comm.proxy("pycamera")
    await camera.comm.execute("pycamera", "reduce", ["/pyobs/raw.fits"])  # NewImageEvent with raw=…
    filename = await pycamera.grab_data(True)  # type: ignore[attr-defined]
    await wait_for(lambda: any(f == filename for _, f, _ in camera.heard), 20, message="the plain event")
    assert not any(f.endswith(".reduced") for _, f, _ in camera.heard)
    assert (
        "skipped pyobs NewImageEvent from pycamera: fields nightcrew's NewImageEvent lacks: raw"
        in caplog.text
    )


async def test_unknown_pyobs_method_is_an_interface_error(nightcrew_side: NightcrewCamera) -> None:
    with pytest.raises(InterfaceError, match="pyobs module 'pycamera' has no method 'get_exposure_status'"):
        await nightcrew_side.comm.execute("pycamera", "get_exposure_status", [])


async def test_a_pyobs_value_nightcrew_cannot_map_gets_one_clear_fault(
    interop_server: Server, nightcrew_side: NightcrewCamera
) -> None:
    # A call the pyobs way, with an element pyobs' vocabulary lacks, from a plain XMPP client.
    raw = _comm("ncraw", interop_server)
    answers: asyncio.Queue[ET.Element] = asyncio.Queue()

    def keep(stanza: ET.Element) -> bool:
        if stanza.get("id") == "bad-1":
            answers.put_nowait(stanza)
            return True
        return False

    await raw.open()
    try:
        connection = raw._require_connection()  # the test speaks XML itself
        connection.add_handler("answer", "{jabber:client}iq", keep)
        call = ET.fromstring(
            "<query xmlns='jabber:iq:rpc'><methodCall><methodName>add</methodName><params>"
            "<param><value><value xmlns='urn:pyobs:rpc:1'><complex>1+2j</complex></value></value></param>"
            "</params></methodCall></query>"
        )
        connection.send(connection.stanza("iq", f"nccalc@{DOMAIN}/pyobs", call, id="bad-1", type="set"))
        answer = await asyncio.wait_for(answers.get(), 10)
    finally:
        await raw.close()
    fault = answer.find(".//{urn:pyobs:rpc:1}fault")
    assert fault is not None
    assert fault.findtext("{urn:pyobs:rpc:1}exception") or fault.findtext("exception")
    message = fault.findtext("message") or fault.findtext("{urn:pyobs:rpc:1}message")
    assert message == "add(): argument 1: pyobs value <complex> has no nightcrew equivalent"


async def test_one_shot_commands_see_and_call_pyobs_modules(
    interop_server: Server, nightcrew_side: NightcrewCamera, tmp_path: Path, caplog: pytest.LogCaptureFixture
) -> None:
    # docs/pyobs.md "From the command line": the operator's file as written there, then its commands.
    (tmp_path / "operator.yaml").write_text(
        "class: nightcrew.comm.xmpp.XmppComm\n"
        f"jid: operator@{DOMAIN}\n"
        "password: ${OPERATOR_PASSWORD}\n"
        f"server: {interop_server.address}\n"
        f"ca_file: {interop_server.ca_file}\n"
        "dialect: pyobs\n"
    )

    async def nightcrew(*args: str) -> tuple[str, str]:
        process = await asyncio.create_subprocess_exec(
            sys.executable, "-m", "nightcrew", *args, "--comm", "operator.yaml",
            cwd=tmp_path, env={**os.environ, "OPERATOR_PASSWORD": PASSWORD},
            stdout=asyncio.subprocess.PIPE, stderr=asyncio.subprocess.PIPE,
        )  # fmt: skip
        out, err = await asyncio.wait_for(process.communicate(), 60)
        assert "Traceback" not in err.decode() and "never retrieved" not in err.decode(), err.decode()
        assert process.returncode == 0, err.decode()
        return out.decode(), err.decode()

    listed, _ = await nightcrew("modules")
    rows = {line.split()[0]: line for line in listed.splitlines()}
    assert set(PYOBS_MODULES) <= set(rows), listed
    assert "IPointingRaDec" in rows["pytelescope"] and "IModule" in rows["shooter"]
    assert rows["pytelescope"].split()[1] == "ready"  # from its presence: pyobs has no get_state
    moved, _ = await nightcrew("call", "pytelescope.move_radec", "10", "89.5")
    assert moved.strip() == "null"
    # The command's own session comes and goes: the dialect modules here do not warn about it.
    assert "pyobs discovery of operator" not in caplog.text
