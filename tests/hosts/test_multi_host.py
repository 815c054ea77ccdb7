"""A short night across three simulated hosts, then the office-dome link is cut.

See observatory_hosts.py for who runs where. Frames go camera → its file cache → (office) image
writers → the dome's OpenSSH and Samba. The test checks that every copy arrives whole on both
servers; that a cut link really cuts (no copy crosses it); that the dome closes by itself while
the office is cut off (the watchdog misses the office's mastermind); and that once the link is
mended every module is back, the roof opens again and the frame taken during the cut is copied.
"""

from __future__ import annotations

import asyncio
import os
import time

import pytest

from nightcrew.interfaces import IMotion
from tests.hosts.night_driver import NightDriver, check_copies, copies, copy_name, wait_copied
from tests.hosts.observatory_hosts import (
    MODULES,
)

pytestmark = pytest.mark.xmpp
#: Wall seconds the office-dome link stays cut at least (and until the dome has closed): more than
#: six times the office's limits - XMPP pings 2 s apart with 4 s to answer (OFFICE_PINGS), SSH
#: keepalives 2 s apart, 3 unanswered - as issue 16's two minutes are against the default pings'
#: 20 s; twice the watchdog's silence limit. NIGHTCREW_CUT_SECONDS=120 runs the two minutes.
CUT_SECONDS = float(os.environ.get("NIGHTCREW_CUT_SECONDS", "40"))
#: Wall seconds for the dome to close by itself after the cut (it takes ~21 s: the silence limit).
CLOSE_WITHIN = 120.0
OFFICE = ["writer-ssh", "writer-smb", "mastermind"]


async def dome_closed(night: NightDriver) -> bool:
    proxy = night.driver.comm.proxy
    roof, telescope = await proxy("roof", IMotion), await proxy("telescope", IMotion)
    return str(await roof.get_motion_status()) == "parked" == str(await telescope.get_motion_status())


async def test_a_night_across_three_hosts_survives_a_cut_link(night: NightDriver) -> None:
    observatory = night.observatory
    startup = await night.wait_ready(MODULES)
    await night.prepare(MODULES)
    frames = [await night.grab(), await night.grab()]
    first = await wait_copied(observatory, frames)
    check_copies(observatory, frames)

    logged_before_cut = {name: len(observatory.log(name)) for name in OFFICE}
    observatory.hosts.cut("office", "dome")
    cut_at = time.monotonic()
    during = await night.grab()  # camera and dome still talk
    # The watchdog on the dome misses the office's mastermind: the dome closes by itself.
    while not await dome_closed(night):
        assert time.monotonic() - cut_at < CLOSE_WITHIN, "the dome did not close while the office was cut off"
        await asyncio.sleep(0.2)
    closed = time.monotonic() - cut_at
    await asyncio.sleep(max(0.0, CUT_SECONDS - (time.monotonic() - cut_at)))  # the fault's length
    cut_for = time.monotonic() - cut_at
    assert len(copies(observatory.ssh_copies)) == 2, "a copy crossed a cut link"
    assert len(copies(observatory.smb_copies)) == 2, "a copy crossed a cut link"
    observatory.hosts.restore("office", "dome")
    restored = time.monotonic()

    back = await night.wait_ready(OFFICE, within=120)
    await night.prepare(MODULES)  # the alarm clears, the roof opens again
    reopened = time.monotonic() - restored
    await wait_copied(observatory, [during])  # its event was lost with the link: the sweep finds it
    late = time.monotonic() - restored
    frames += [during, await night.grab()]
    after = await wait_copied(observatory, frames)
    check_copies(observatory, frames)
    noticed = [  # by the pings after the cut, not by a ping slow to be answered before it
        name
        for name in OFFICE
        if "the XMPP server is silent" in observatory.log(name)[logged_before_cut[name] :]
    ]
    assert noticed, "no office module noticed the silent link by its pings"
    print(
        f"\nstart-up {startup:.1f} s; the first two frames copied within {first:.1f} s; link cut "
        f"{cut_for:.1f} s; roof closed and telescope parked {closed:.1f} s after the cut; the "
        f"office back in the room {back:.1f} s after the restore, the roof open again after "
        f"{reopened:.1f} s; the frame taken during the cut copied within {late:.1f} s of the restore; a new "
        f"frame copied within {after:.1f} s; pings noticed the cut in {noticed}; "
        f"copy of the frame from the cut: {copy_name(during)}"
    )
