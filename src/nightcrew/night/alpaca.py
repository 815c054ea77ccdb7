"""``nightcrew sim --alpaca PORT``: the simulated observatory as Alpaca devices, until Ctrl-C.

Instead of running a night, the bundled (or ``--configs``) devices run on a clock at real speed
(``--speed`` to change it) that starts at dusk of ``--date`` (or ``--start``), and an AlpacaServer
serves them on 127.0.0.1:PORT: telescope, camera (frames are also written to ``--out``), roof as
Dome, focuser, filter wheel, the weather station (``conditions.yaml``) as ObservingConditions, the
weather verdict of ``robotic/weather.yaml`` as SafetyMonitor, and any rotator, switch box or flat
panel among the ``--configs`` modules.
Any Alpaca client (N.I.N.A., SharpCap, alpyca scripts) can then drive the simulated sky; it finds
the server by Alpaca discovery on loopback (``--alpaca-discovery-port``). On Ctrl-C or SIGTERM the
telescope parks, the roof closes and everything stops.
"""

from __future__ import annotations

import asyncio
import sys
from datetime import UTC, datetime, timedelta
from pathlib import Path

from nightcrew.clock import AcceleratedClock
from nightcrew.comm.local import LocalComm, LocalNetwork
from nightcrew.config import build_object, to_plain, validate_config
from nightcrew.errors import ConfigError
from nightcrew.interfaces import ICoverCalibrator, IRotator, ISwitch
from nightcrew.modules import Module
from nightcrew.modules.alpaca.server import AlpacaServer
from nightcrew.night.build import (
    CAMERA,
    FILTERS,
    FOCUSER,
    FRAMES,
    ROOF,
    SIM_RPC_GRACE,
    TELESCOPE,
    build_observatory,
    bundled_observatory,
    data_environ,
    images_vfs,
    load_in_process,
    observatory_site,
    park_and_close,
)
from nightcrew.night.fields import night_start
from nightcrew.night.options import SimOptions
from nightcrew.night.running import quiet_module_logs, stop_on_signals
from nightcrew.sim.render import CameraModel

__all__ = ["STATION", "VERDICT", "serve_alpaca"]

#: The weather verdict module (robotic/weather.yaml) served as the SafetyMonitor.
VERDICT = "weather"
#: The weather station (conditions.yaml) served as ObservingConditions.
STATION = "conditions"


def serve_alpaca(options: SimOptions) -> int:
    """``--alpaca PORT``: serve the devices until Ctrl-C."""
    if options.alpaca is None:
        raise ConfigError("serving to Alpaca clients needs a port (--alpaca PORT)")
    directory: Path = options.configs or bundled_observatory()
    site = observatory_site(directory)
    start = night_start(options.date, site)
    if options.start is not None:
        day = options.date if options.start.hour >= 12 else options.date + timedelta(days=1)
        start = datetime.combine(day, options.start, tzinfo=UTC)
    clock = AcceleratedClock(start, speed=options.speed or 1.0)
    with quiet_module_logs(options.show_logs):
        asyncio.run(_serve(directory, options, clock))
    return 0


async def _serve(directory: Path, options: SimOptions, clock: AcceleratedClock) -> None:
    assert options.alpaca is not None  # checked by serve_alpaca
    network = LocalNetwork(rpc_grace=SIM_RPC_GRACE)
    # The VFS of the modules without their own: the server reads the camera's frames from it.
    vfs = images_vfs(options.out / FRAMES)
    environ = data_environ(options.out)
    modules = build_observatory(
        directory, clock=clock, vfs=vfs, seed=options.seed, network=network, environ=environ
    )
    devices: dict[str, str | list[str]] = {
        "telescope": TELESCOPE,
        "camera": CAMERA,
        "dome": ROOF,
        "focuser": FOCUSER,
        "filterwheel": FILTERS,
    }
    if any(module.name == STATION for module in modules):
        devices["observingconditions"] = STATION
    devices.update(_more_devices(modules))
    verdict = directory / "robotic" / f"{VERDICT}.yaml"
    if verdict.is_file():
        config = load_in_process(verdict, environ)
        validate_config(config, Module)
        config.update({"comm": LocalComm(VERDICT, network=network), "clock": clock, "vfs": vfs})
        modules.append(build_object(config, Module))
        devices["safetymonitor"] = VERDICT
    server = AlpacaServer(
        comm=LocalComm("alpaca", network=network),
        clock=clock,
        vfs=vfs,
        site=next((m.site for m in modules if m.site is not None), None),
        devices=devices,
        pixel_sizes={CAMERA: _pixel_size(directory)},
        port=options.alpaca,
        discovery_port=options.alpaca_discovery_port,
    )
    driver = Module(comm=LocalComm("sim-alpaca", network=network), clock=clock)
    opened: list[Module] = []
    async with stop_on_signals() as stop:
        try:
            for module in [*modules, server, driver]:
                await module.open()
                opened.append(module)
            discovery = server.discovery_port
            print(
                f"serving the simulated observatory as Alpaca devices at {server.url}"
                + (f" (discovery on UDP port {discovery})" if discovery is not None else "")
                + f"; clock from {clock.now():%Y-%m-%d %H:%M} UTC at {clock.speed:g}x; Ctrl-C stops",
                flush=True,
            )
            for device in server.devices:
                print(f"  {device.type_name} {device.number}: module {device.module}", flush=True)
            await stop.wait()
            print("stopping: parking the telescope and closing the roof", file=sys.stderr, flush=True)
            await park_and_close(driver)
        finally:
            for module in reversed(opened):
                await module.close()
            await vfs.close()


def _more_devices(modules: list[Module]) -> dict[str, str | list[str]]:
    """Rotators, switch boxes and flat panels among ``modules`` (a ``--configs`` directory may
    have them), by Alpaca device type; numbered in the order of their files."""
    kinds = (("rotator", IRotator), ("switch", ISwitch), ("covercalibrator", ICoverCalibrator))
    found = {kind: [m.name for m in modules if isinstance(m, interface)] for kind, interface in kinds}
    return {kind: names for kind, names in found.items() if names}


def _pixel_size(directory: Path) -> float:
    """The simulated camera's pixel size in µm (its detector's pixel_size_um)."""
    path = directory / f"{CAMERA}.yaml"
    config = load_in_process(path) if path.is_file() else {}
    detector = to_plain(config.get("detector") or {})
    size = detector.get("pixel_size_um") if isinstance(detector, dict) else None
    return float(size) if isinstance(size, int | float) else CameraModel().pixel_size_um
