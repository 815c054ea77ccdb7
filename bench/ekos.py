"""KStars/Ekos (Debian ``kstars``) against nightcrew's IndiServer, scripted through Ekos' D-Bus interface.

Run: ``make bench-ekos`` (installs ``kstars``, ``xvfb`` and ``xauth`` first), or
``.venv/bin/python bench/ekos.py [--out DIR] [--keep]``. It starts itself again under
``xvfb-run -a dbus-run-session`` when there is no D-Bus session, so KStars gets a private X server
and a private session bus; its home is a fresh directory under ``--out``.

Steps, each timed (wall seconds):

1. the simulated observatory (telescope, camera, focuser, filter wheel, dome) in this process on a
   real-time clock, served by IndiServer on a free loopback port;
2. KStars starts (``org.kde.kstars`` on the bus);
3. an Ekos profile ``nightcrew`` in *remote* mode with that host and port is written to KStars'
   user database, Ekos is shown, the profile chosen and started: Ekos connects;
4. every served device appears in Ekos (``/KStars/INDI`` ``getDevices``);
5. the mount is unparked and slewed (Ekos' mount module, ``/KStars/Ekos/Mount``) to a point 50°
   high in the south, and nightcrew's telescope reports the target;
6. one frame is captured by Ekos' capture module into ``--out/frames`` and the FITS file checked;
7. cooling (``CCD_TEMPERATURE``, ``CCD_COOLER``) and the pier side (``TELESCOPE_PIER_SIDE``) are
   read through KStars' INDI interface.

At the end it prints the properties Ekos asked for (from IndiServer's debug log of
``getProperties``/``new*Vector``): ``tests/indi/test_ekos_properties.py`` checks that every one of
them is served.
"""

from __future__ import annotations

import argparse
import asyncio
import contextlib
import logging
import os
import re
import shutil
import sqlite3
import sys
import tempfile
import time
from collections.abc import AsyncIterator, Awaitable, Callable
from contextlib import asynccontextmanager
from pathlib import Path
from typing import Any

from astropy.io import fits  # type: ignore[import-untyped]

from nightcrew.astro import altaz_to_radec, angular_separation, j2000_to_of_date
from nightcrew.clock import RealClock
from nightcrew.comm.local import LocalComm, LocalNetwork
from nightcrew.interfaces import MotionStatus
from nightcrew.modules import Module
from nightcrew.modules.indi.server import IndiServer
from nightcrew.modules.sim import SimCamera, SimDome, SimFilterWheel, SimFocuser, SimTelescope
from nightcrew.site import Site
from nightcrew.vfs import LocalFile, VirtualFileSystem

SITE = Site(latitude=51.56, longitude=9.94, elevation=201.0, name="Göttingen")
BUS = ("--session", "--dest", "org.kde.kstars")
_INSIDE = "NIGHTCREW_EKOS_INSIDE"
_ASKED = re.compile(r"INDI client \S+: (getProperties|new\w+Vector) (\S+)\.(\S+)")


class AskedFor(logging.Handler):
    """Collects ``device.property`` of every getProperties and new*Vector IndiServer logs."""

    def __init__(self) -> None:
        super().__init__(logging.DEBUG)
        self.get: set[str] = set()
        self.new: set[str] = set()
        self.get_all = 0  # getProperties of every device at once

    def emit(self, record: logging.LogRecord) -> None:
        match = _ASKED.match(record.getMessage())
        if match is None:
            return
        kind, device, name = match.groups()
        if kind == "getProperties" and device == "None":
            self.get_all += 1
        elif kind == "getProperties":
            self.get.add(f"{device}.{name}")
        else:
            self.new.add(f"{device}.{name}")


class Steps:
    """Prints each step with its wall time."""

    def __init__(self) -> None:
        self.times: dict[str, float] = {}

    @asynccontextmanager
    async def step(self, name: str) -> AsyncIterator[None]:
        print(f"-- {name} ...", flush=True)
        start = time.monotonic()
        try:
            yield
        except BaseException as exc:
            print(
                f"   FAILED after {time.monotonic() - start:.1f} s: {type(exc).__name__}: {exc}", flush=True
            )
            raise
        self.times[name] = time.monotonic() - start
        print(f"   ok in {self.times[name]:.1f} s", flush=True)


async def gdbus(*args: str, wait: float = 20.0) -> str:
    """``gdbus call`` on KStars; returns its GVariant text, raises RuntimeError with its error."""
    process = await asyncio.create_subprocess_exec(
        "gdbus",
        "call",
        *BUS,
        "--timeout",
        str(int(wait)),
        *args,
        stdout=asyncio.subprocess.PIPE,
        stderr=asyncio.subprocess.PIPE,
    )
    out, err = await process.communicate()
    if process.returncode != 0:
        raise RuntimeError(f"gdbus {' '.join(args[:3])}: {err.decode().strip()}")
    return out.decode().strip()


async def introspect(path: str) -> str:
    process = await asyncio.create_subprocess_exec(
        "gdbus",
        "introspect",
        *BUS,
        "--object-path",
        path,
        stdout=asyncio.subprocess.PIPE,
        stderr=asyncio.subprocess.PIPE,
    )
    out, _ = await process.communicate()
    return out.decode() if process.returncode == 0 else ""


async def until(what: str, check: Callable[[], Awaitable[bool]], within: float, every: float = 0.5) -> None:
    """Wait until ``check()`` is true, at most ``within`` wall seconds."""
    deadline = time.monotonic() + within
    while True:
        try:
            if await check():
                return
        except RuntimeError:
            pass
        if time.monotonic() > deadline:
            raise TimeoutError(f"{what}: not within {within:g} s")
        await asyncio.sleep(every)


def indi(method: str, *args: str) -> Awaitable[str]:
    # "--": a negative number is an argument, not an option
    return gdbus("--object-path", "/KStars/INDI", "--method", f"org.kde.kstars.INDI.{method}", "--", *args)


def write_profile(home: Path, port: int) -> None:
    """A remote Ekos profile named nightcrew, one driver per served device role."""
    database = home / ".local/share/kstars/userdb.sqlite"
    with sqlite3.connect(database) as db:
        db.execute("DELETE FROM driver WHERE profile IN (SELECT id FROM profile WHERE name = 'nightcrew')")
        db.execute("DELETE FROM profile WHERE name = 'nightcrew'")
        cursor = db.execute(
            "INSERT INTO profile (name, host, port, autoconnect, portselector) "
            "VALUES ('nightcrew', '127.0.0.1', ?, 1, 0)",
            (port,),
        )
        profile = cursor.lastrowid
        for label, role in (
            ("Telescope Simulator", "Mount"),
            ("CCD Simulator", "CCD"),
            ("Focuser Simulator", "Focuser"),
            ("Filter Simulator", "Filter"),
            ("Dome Simulator", "Dome"),
        ):
            db.execute("INSERT INTO driver (label, role, profile) VALUES (?, ?, ?)", (label, role, profile))


async def observatory(out: Path) -> tuple[list[Module], IndiServer, SimTelescope]:
    clock = RealClock()
    network = LocalNetwork()
    (out / "nightcrew").mkdir(parents=True, exist_ok=True)
    vfs = VirtualFileSystem({"cache": LocalFile(str(out / "nightcrew"))})

    def context(name: str) -> dict[str, Any]:
        return {"comm": LocalComm(name, network=network), "clock": clock, "site": SITE, "vfs": vfs}

    telescope = SimTelescope(**context("telescope"))
    modules: list[Module] = [
        telescope,
        SimCamera(
            roof=None, weather=None, detector={"chip_width": 320, "chip_height": 240}, **context("camera")
        ),
        SimFocuser(**context("focuser")),
        SimFilterWheel(filters=["B", "V", "R"], **context("filters")),
        SimDome(**context("dome")),
    ]
    for module in modules:
        await module.open()
    server = IndiServer(
        port=0,
        telescope="telescope",
        camera="camera",
        focuser="focuser",
        filters="filters",
        dome="dome",
        **context("indi"),
    )
    await server.open()
    modules.append(server)
    return modules, server, telescope


async def run(out: Path, keep: bool) -> int:
    steps = Steps()
    asked = AskedFor()
    server_log = logging.getLogger("nightcrew.modules.indi.server")
    server_log.setLevel(logging.DEBUG)
    server_log.addHandler(asked)
    home = out / "home"
    shutil.rmtree(home, ignore_errors=True)
    home.mkdir(parents=True)
    frames = out / "frames"
    shutil.rmtree(frames, ignore_errors=True)
    frames.mkdir()
    env = {**os.environ, "HOME": str(home), "XDG_RUNTIME_DIR": str(home / "run")}
    (home / "run").mkdir(mode=0o700)
    os.environ.update(env)  # gdbus and KStars alike
    modules: list[Module] = []
    kstars: asyncio.subprocess.Process | None = None
    failed = False
    try:
        async with steps.step("observatory and IndiServer"):
            modules, server, telescope = await observatory(out)
        async with steps.step("KStars up on D-Bus"):
            with (out / "kstars.log").open("wb") as kstars_log:
                kstars = await asyncio.create_subprocess_exec(
                    "kstars", stdout=kstars_log, stderr=asyncio.subprocess.STDOUT, env=env
                )
            await until("KStars' INDI interface", lambda: _has("/KStars/INDI"), 120)
        async with steps.step("Ekos profile nightcrew started (remote 127.0.0.1)"):
            write_profile(home, server.port)
            # The action's reply may never come (Ekos opens its window); Ekos' object tells.
            with contextlib.suppress(RuntimeError):
                await gdbus(
                    "--object-path",
                    "/kstars/MainWindow_1",
                    "--method",
                    "org.kde.KMainWindow.activateAction",
                    "show_ekos",
                    wait=5,
                )
            await until("Ekos on D-Bus", lambda: _has("/KStars/Ekos"), 60)
            profiles = await gdbus(
                "--object-path", "/KStars/Ekos", "--method", "org.kde.kstars.Ekos.getProfiles"
            )
            print(f"   profiles: {profiles}")
            await gdbus(
                "--object-path", "/KStars/Ekos", "--method", "org.kde.kstars.Ekos.setProfile", "nightcrew"
            )
            await gdbus("--object-path", "/KStars/Ekos", "--method", "org.kde.kstars.Ekos.start")
        async with steps.step("every served device in Ekos"):
            wanted = set(server.devices)

            async def all_devices() -> bool:
                listed = await indi("getDevices")
                return all(f"'{name}'" in listed for name in wanted)

            await until("devices " + ", ".join(sorted(wanted)), all_devices, 60)
            print(f"   devices: {await indi('getDevices')}")
            (out / "ekos-tree.txt").write_text(await _tree())
        async with steps.step("mount unparked and slewed by Ekos"):
            await _slew(telescope)
        async with steps.step("a frame captured by Ekos into its own directory"):
            await _capture(frames)
        async with steps.step("cooler set to -10 C through KStars' INDI client"):
            await indi("setNumber", "camera", "CCD_TEMPERATURE", "CCD_TEMPERATURE_VALUE", "-10")
            await indi("sendProperty", "camera", "CCD_TEMPERATURE")

            async def cooler_on() -> bool:
                return "On" in await indi("getSwitch", "camera", "CCD_COOLER", "COOLER_ON")

            await until("CCD_COOLER.COOLER_ON", cooler_on, 30)
        async with steps.step("cooling and pier side read through KStars"):
            for args in (
                ("camera", "CCD_TEMPERATURE", "CCD_TEMPERATURE_VALUE"),
                ("camera", "CCD_COOLER", "COOLER_ON"),
                ("telescope", "TELESCOPE_PIER_SIDE", "PIER_EAST"),
                ("telescope", "TELESCOPE_PIER_SIDE", "PIER_WEST"),
            ):
                method = "getNumber" if args[1] == "CCD_TEMPERATURE" else "getSwitch"
                print(f"   {'.'.join(args)} = {await indi(method, *args)}")
    except Exception:
        failed = True
    finally:
        if kstars is not None and kstars.returncode is None:
            kstars.terminate()
            try:
                await asyncio.wait_for(kstars.wait(), 20)
            except TimeoutError:
                kstars.kill()
                await kstars.wait()
        for module in reversed(modules):
            await module.close()
        if not keep:
            shutil.rmtree(home, ignore_errors=True)
    print("\nsteps (wall seconds):")
    for name, seconds in steps.times.items():
        print(f"  {seconds:7.1f}  {name}")
    print(f"\nproperties Ekos asked for (getProperties): every device's {asked.get_all} time(s)")
    for name in sorted(asked.get):
        print(f"  {name}")
    print("properties Ekos set (new*Vector):")
    for name in sorted(asked.new):
        print(f"  {name}")
    return 1 if failed else 0


async def _has(path: str) -> bool:
    return "interface" in await introspect(path)


async def _tree() -> str:
    process = await asyncio.create_subprocess_exec(
        "gdbus",
        "introspect",
        *BUS,
        "--object-path",
        "/KStars/Ekos",
        "--recurse",
        stdout=asyncio.subprocess.PIPE,
    )
    out, _ = await process.communicate()
    return out.decode()


async def _slew(telescope: SimTelescope) -> None:
    mount = ("--object-path", "/KStars/Ekos/Mount", "--method")
    await gdbus(*mount, "org.kde.kstars.Ekos.Mount.unpark")
    await until("unparked", lambda: _not_parked(telescope), 120)
    ra, dec = altaz_to_radec(50.0, 180.0, SITE.latitude, SITE.longitude, telescope.clock.time())
    ra_now, dec_now = j2000_to_of_date(ra, dec, telescope.clock.time())
    print(f"   target J2000 {ra:.4f} {dec:.4f} deg, JNow {ra_now / 15.0:.5f} h {dec_now:.4f} deg")
    reply = await gdbus(*mount, "org.kde.kstars.Ekos.Mount.slew", str(ra_now / 15.0), str(dec_now))
    print(f"   Mount.slew -> {reply}")

    async def there() -> bool:
        status = await telescope.get_motion_status()
        return (
            status is MotionStatus.TRACKING
            and angular_separation(*await telescope.get_radec(), ra, dec) < 1 / 60
        )

    await until("telescope tracking at the target", there, 180)
    status = await gdbus(
        "--object-path",
        "/KStars/Ekos/Mount",
        "--method",
        "org.freedesktop.DBus.Properties.GetAll",
        "org.kde.kstars.Ekos.Mount",
    )
    print("   Ekos mount:", " ".join(status.split())[:400])


async def _not_parked(telescope: SimTelescope) -> bool:
    return await telescope.get_motion_status() not in (MotionStatus.PARKED, MotionStatus.INITIALIZING)


SEQUENCE = """<?xml version="1.0" encoding="UTF-8"?>
<SequenceQueue version='2.6'>
<GuideDeviation enabled='false'>2</GuideDeviation>
<Job>
<Exposure>1</Exposure>
<Format>Mono</Format>
<Encoding>FITS</Encoding>
<Binning><X>1</X><Y>1</Y></Binning>
<Frame><X>0</X><Y>0</Y><W>320</W><H>240</H></Frame>
<Temperature force='false'>0</Temperature>
<Filter>B</Filter>
<Type>Light</Type>
<Count>1</Count>
<Delay>0</Delay>
<TargetName>bench</TargetName>
<FITSDirectory>{directory}</FITSDirectory>
<PlaceholderFormat>/%t_%T_%e_%s3</PlaceholderFormat>
<PlaceholderSuffix>3</PlaceholderSuffix>
<UploadMode>0</UploadMode>
<Properties></Properties>
</Job>
</SequenceQueue>
"""


async def _capture(frames: Path) -> None:
    capture = ("--object-path", "/KStars/Ekos/Capture", "--method")
    sequence = frames.parent / "bench.esq"
    sequence.write_text(SEQUENCE.format(directory=frames))
    await gdbus(*capture, "org.kde.kstars.Ekos.Capture.clearSequenceQueue")
    loaded = await gdbus(*capture, "org.kde.kstars.Ekos.Capture.loadSequenceQueue", str(sequence))
    print(f"   loadSequenceQueue -> {loaded}")
    await gdbus(*capture, "org.kde.kstars.Ekos.Capture.start")

    async def written() -> bool:
        return any(frames.rglob("*.fits"))  # noqa: ASYNC240 - a small directory

    await until("a FITS file in " + str(frames), written, 120)
    path = next(frames.rglob("*.fits"))  # noqa: ASYNC240
    await asyncio.sleep(1.0)  # Ekos writes the file in one go; give it the moment to close it
    with fits.open(path) as hdus:
        header = hdus[0].header
        size = f"{header['NAXIS1']}x{header['NAXIS2']}"
        print(
            f"   {path.relative_to(frames)}: {size}, EXPTIME {header.get('EXPTIME')}, "
            f"XPIXSZ {header.get('XPIXSZ')}, IMAGETYP {header.get('IMAGETYP')}"
        )
    print(f"   queue status: {await gdbus(*capture, 'org.kde.kstars.Ekos.Capture.getSequenceQueueStatus')}")


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--out", type=Path, default=Path(tempfile.gettempdir()) / "nightcrew-ekos")
    parser.add_argument("--keep", action="store_true", help="keep KStars' home (profile, logs) in --out")
    args = parser.parse_args()
    missing = [
        tool for tool in ("kstars", "xvfb-run", "dbus-run-session", "gdbus") if shutil.which(tool) is None
    ]
    if missing:
        print(f"bench/ekos.py needs {', '.join(missing)} (make bench-ekos installs them)", file=sys.stderr)
        return 2
    if os.environ.get(_INSIDE) != "1":
        os.environ[_INSIDE] = "1"
        command = ["xvfb-run", "-a", "dbus-run-session", "--", sys.executable, *sys.argv]
        os.execvp(command[0], command)
    args.out.mkdir(parents=True, exist_ok=True)
    return asyncio.run(run(args.out.resolve(), args.keep))


if __name__ == "__main__":
    sys.exit(main())
