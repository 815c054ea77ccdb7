"""The simulated observatory of tests/modules with a mount whose pointing miss we choose.

SimTelescope draws a new pointing miss (and drift direction) on every move — including the small
moves that BaseTelescope makes to apply offsets. A real mount keeps its miss when offset by a few
arcminutes, and neither acquisition nor guiding can converge if every correction brings a fresh
miss of the slew's size, so :class:`OffsetKeepingSimTelescope` keeps the slew's miss and drift
across offsets; and while an offset settles it reports the position it tracked until then
(SimTelescope reports the alt/az where its previous slew ended, minutes stale, during any move).
A fix belongs in SimTelescope itself; this subclass only keeps three values.
"""

from __future__ import annotations

from typing import Any

from nightcrew.modules.sim import SimCamera, SimTelescope
from tests.modules.conftest import Observatory
from tests.modules.test_sim_camera import PLEIADES, observatory_module, start_observatory


class OffsetKeepingSimTelescope(SimTelescope):
    """A SimTelescope whose offsets shift the true pointing by exactly the offset."""

    _offsetting = False

    async def set_offsets_radec(self, dra: float, ddec: float) -> None:
        self._offsetting = True
        try:
            await super().set_offsets_radec(dra, ddec)
        finally:
            self._offsetting = False

    async def _travel(self, alt: float, az: float) -> None:
        if not self._offsetting:
            await super()._travel(alt, az)
            return
        miss, settled = self._slew_error, self._settled_at
        self._fixed_altaz = self._reported_altaz()
        await super()._travel(alt, az)
        self._slew_error, self._settled_at = miss, settled  # no await in between: never seen drawn


async def start_pointing_observatory(
    obs: Observatory, *, mount: dict[str, Any], **camera: Any
) -> tuple[SimCamera, OffsetKeepingSimTelescope]:
    """tests/modules' observatory with its telescope replaced by a "mount" with options ``mount``."""
    science = await start_observatory(obs, telescope="mount", **camera)
    # The camera now looks through "mount"; the stock telescope must not write headers any more.
    await observatory_module(obs, "telescope", SimTelescope).close()
    options: dict[str, Any] = {"init_time": 0.0, "settle_time": 0.5, **mount}
    telescope = await obs.start(OffsetKeepingSimTelescope, "mount", **options)
    await telescope.init()
    await telescope.move_radec(*PLEIADES)
    return science, telescope
