"""A small simulated observatory with a WebConsole, and logging in to it in a real browser.

The modules are the package's own simulated devices on an in-process network with one fast
clock; the console serves on 127.0.0.1 with a free port. Two accounts: an operator and a viewer.
"""

from __future__ import annotations

import functools
from typing import Any, TypeVar

from playwright.async_api import Page, expect

from nightcrew.clock import AcceleratedClock
from nightcrew.comm.local import LocalComm, LocalNetwork
from nightcrew.modules import Module
from nightcrew.modules.console import WebConsole
from nightcrew.modules.sim import SimCamera, SimFilterWheel, SimFocuser, SimRoof, SimTelescope
from nightcrew.security import hash_password
from nightcrew.site import Site
from nightcrew.vfs import MemoryFile, VirtualFileSystem

M = TypeVar("M", bound=Module)

EPOCH = "2024-01-15T22:00:00+00:00"  # a winter night: the Pleiades are high, the Sun is down
SITE = Site(latitude=51.56, longitude=9.94, elevation=201.0, name="Göttingen")
PLEIADES = (56.75, 24.12)
OPERATOR = ("olga", "night-shift-42")
VIEWER = ("victor", "just-looking-7")
#: A small chip keeps a frame quick to render in the tests.
DETECTOR = {"chip_width": 256, "chip_height": 256, "cosmic_rays_per_s": 0.0}


@functools.cache
def accounts() -> dict[str, dict[str, str]]:
    """The console's accounts (hashed once per test run: scrypt is slow on purpose)."""
    return {
        OPERATOR[0]: {"password_hash": hash_password(OPERATOR[1]), "role": "operator"},
        VIEWER[0]: {"password_hash": hash_password(VIEWER[1]), "role": "viewer"},
    }


class Observatory:
    """Modules on one network, clock and in-memory VFS; the console among them; closes all after."""

    def __init__(self, speed: float = 100.0) -> None:
        self.clock = AcceleratedClock(EPOCH, speed=speed)
        self.vfs = VirtualFileSystem({"cache": MemoryFile()})
        self.network = LocalNetwork()
        self.modules: dict[str, Module] = {}
        self.console: WebConsole | None = None

    async def start(self, cls: type[M], name: str, **kwargs: Any) -> M:
        kwargs.setdefault("clock", self.clock)
        kwargs.setdefault("site", SITE)
        kwargs.setdefault("vfs", self.vfs)
        module = cls(name=name, comm=LocalComm(name, network=self.network), **kwargs)
        await module.open()
        self.modules[name] = module
        return module

    async def stop(self, name: str) -> None:
        await self.modules.pop(name).close()

    async def start_console(self, **options: Any) -> WebConsole:
        options.setdefault("accounts", accounts())
        options.setdefault("port", 0)
        options.setdefault("status_interval", 0.5)
        self.console = await self.start(WebConsole, "console", **options)
        return self.console

    @property
    def url(self) -> str:
        assert self.console is not None
        return self.console.url

    async def start_devices(self) -> None:
        """Telescope (initialised, parked at the start), roof, focuser, filter wheel and camera."""
        telescope = await self.start(SimTelescope, "telescope", init_time=0.0, settle_time=1.0, seed=1)
        await telescope.init()
        await self.start(SimRoof, "roof", open_time=1.0)
        await self.start(SimFocuser, "focuser", focus=25.0, best_focus=25.0)
        await self.start(SimFilterWheel, "filters", filters=["V", "R"], filter_name="V")
        await self.start(
            SimCamera,
            "camera",
            detector=DETECTOR,
            catalog_depth=12.0,
            seed=3,
            filter_throughputs={"V": 0.8, "R": 0.9},
            readout_time=0.5,
        )

    async def close(self) -> None:
        for name in reversed(list(self.modules)):
            await self.stop(name)


async def login(page: Page, url: str, account: tuple[str, str] = OPERATOR) -> None:
    """Open the console and log in; returns once the frame with the user's name shows."""
    await page.goto(url)
    await page.fill("#login-user", account[0])
    await page.fill("#login-password", account[1])
    await page.click("#login-submit")
    await expect(page.locator("#whoami")).to_contain_text(account[0])
