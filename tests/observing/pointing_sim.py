"""The simulated observatory of tests/modules with a mount ("mount") whose errors we choose.

Offsets keep the mount's pointing miss and drift (as a real mount's do), so acquisition and guiding
can converge on it.
"""

from __future__ import annotations

from typing import Any

from nightcrew.modules.sim import SimCamera, SimTelescope
from nightcrew.testing import Observatory
from tests.modules.sim_observatory import PLEIADES, start_observatory


async def start_pointing_observatory(
    obs: Observatory, *, mount: dict[str, Any], **camera: Any
) -> tuple[SimCamera, SimTelescope]:
    """tests/modules' observatory with its telescope replaced by a "mount" with options ``mount``."""
    science = await start_observatory(obs, telescope="mount", **camera)
    # The camera now looks through "mount"; the stock telescope must not write headers any more.
    await obs.module("telescope", SimTelescope).close()
    options: dict[str, Any] = {"init_time": 0.0, "settle_time": 0.5, **mount}
    telescope = await obs.start(SimTelescope, "mount", **options)
    await telescope.init()
    await telescope.move_radec(*PLEIADES)
    return science, telescope
