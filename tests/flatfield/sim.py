"""A small simulated observatory at twilight for the flat-field tests.

Frames are 128x128 (a 256² chip binned 2x2) so that rendering stays in the milliseconds; on the
virtual clock the ~30 minutes of useful twilight cost only the wall time of those renders.
"""

from __future__ import annotations

import asyncio
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

from nightcrew.clock import AcceleratedClock, Clock, VirtualClock
from nightcrew.interfaces import Binning
from nightcrew.modules.flatfield import FlatField, FlatFieldPointing
from nightcrew.modules.sim import SimCamera, SimFilterWheel, SimRoof, SimTelescope, SimWeatherStation
from nightcrew.sim.catalog_data import load_reference_stars
from nightcrew.testing import Observatory
from nightcrew.vfs import LocalFile, VirtualFileSystem

#: 2024-01-15 at Göttingen: the Sun is at -4.9° at 16:12 UTC (dusk) and -9.5° at 06:17 UTC (dawn).
DUSK = datetime(2024, 1, 15, 16, 12, tzinfo=UTC)
DAWN = datetime(2024, 1, 16, 6, 17, tzinfo=UTC)
TARGET, BIAS = 30000.0, 1000.0
BINNING = Binning(2, 2)
DETECTOR = {"chip_width": 256, "chip_height": 256, "cosmic_rays_per_s": 0.0}
#: B lets through a quarter of V: it needs 4x the exposure, so at dusk its flats must come first.
THROUGHPUTS = {"V": 0.8, "R": 0.85, "B": 0.2}
#: Deliberately not the simulator's truth (about exp(-0.92*(h + 5.5)) for V, 2x2): the test
#: exposure and the sky factor must make up for it. B: V's shifted by ln(4) / 0.8.
FUNCTIONS = {
    "V": {"2x2": "exp(-0.8*(h + 5.2))"},
    "R": {"2x2": "exp(-0.8*(h + 5.3))"},
    "B": {"2x2": "exp(-0.8*(h + 3.47))"},
}


class TwilightObservatory(Observatory):
    """The modules' test observatory, but at a chosen twilight and with files on disk; on a virtual
    clock, or with ``speed`` an accelerated one."""

    def __init__(self, start: datetime, directory: Path, speed: float | None = None) -> None:
        super().__init__(epoch=start, speed=speed)
        self.start_time, self.speed = start, speed
        self.vfs = VirtualFileSystem({"cache": LocalFile(str(directory))})
        self.directory = directory

    async def restart_clock(self) -> None:
        """Load the star catalog (seconds of wall time: many minutes of twilight on a fast clock),
        then start the clock at the chosen time; before any module is started."""
        await asyncio.to_thread(load_reference_stars)
        self.clock = _clock(self.start_time, self.speed)


async def start_flat_observatory(obs: TwilightObservatory, **flat_options: Any) -> FlatField:
    """Telescope initialised, roof open, clear sky, V in the beam; a FlatField with its pointing."""
    await obs.restart_clock()
    telescope = await obs.start(SimTelescope, "telescope", init_time=0.0, settle_time=1.0, slew_rate=10.0)
    await telescope.init()
    roof = await obs.start(SimRoof, "roof", open_time=1.0)
    await roof.open_roof()
    await obs.start(SimFilterWheel, "filters", filters=["V", "R", "B"], filter_name="V", change_time=1.0)
    await obs.start(SimWeatherStation, "weather", scenario=[{"at": 0, "clouds": 0.0}])
    await obs.start(
        SimCamera, "camera", detector=DETECTOR, filter_throughputs=THROUGHPUTS, catalog_depth=12.0,
        readout_time=2.0, seed=5, filename_pattern="/cache/{DATE-OBS}-{IMAGETYP}-{FILTER}.fits",
        focuser=None,
    )  # fmt: skip

    await obs.start(FlatFieldPointing, "flatpointing", telescope="telescope")
    options: dict[str, Any] = {
        "camera": "camera",
        "filters": "filters",
        "pointing": "flatpointing",
        "functions": FUNCTIONS,
        "target": TARGET,
        "bias": BIAS,
        "min_exposure": 1.0,
        "max_exposure": 30.0,
        **flat_options,
    }
    return await obs.start(FlatField, "flatfield", **options)


def _clock(start: datetime, speed: float | None) -> Clock:
    return VirtualClock(start) if speed is None else AcceleratedClock(start, speed=speed)
