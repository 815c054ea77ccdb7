"""Observatory builds modules on one network with one clock, site and VFS; EventRecorder listens."""

from __future__ import annotations

import pytest

from nightcrew.clock import RealClock
from nightcrew.events import RoofClosedEvent, RoofOpenedEvent
from nightcrew.interfaces import IRoof, ModuleState, MotionStatus
from nightcrew.modules.sim import SimRoof, SimTelescope
from nightcrew.testing import EPOCH, SITE, EventRecorder, Observatory


async def test_modules_share_the_clock_site_and_network_and_are_closed_last_first() -> None:
    async with Observatory(speed=100.0) as obs:
        assert obs.clock.now().isoformat().startswith(EPOCH[:16])
        roof = await obs.start(SimRoof, "roof", open_time=60.0)
        telescope = await obs.start(SimTelescope, "telescope")
        assert roof.clock is obs.clock and roof.vfs is obs.vfs and telescope.site == SITE
        proxy = await telescope.comm.proxy("roof", IRoof)
        assert await proxy.get_motion_status() is MotionStatus.PARKED
        assert obs.module("roof", SimRoof) is roof and obs.modules == [roof, telescope]
        with pytest.raises(TypeError, match="module 'roof' is a SimRoof, not a SimTelescope"):
            obs.module("roof", SimTelescope)
        with pytest.raises(LookupError, match="no module 'dome' started; started: roof, telescope"):
            obs.module("dome", SimRoof)
    assert (roof.state, telescope.state) == (ModuleState.CLOSED, ModuleState.CLOSED)
    await obs.close()  # safe twice


async def test_a_given_clock_is_used_and_the_wait_is_on_it() -> None:
    clock = RealClock()
    async with Observatory(clock=clock) as obs:
        roof = await obs.start(SimRoof, "roof", open_time=0.5)
        assert roof.clock is clock
        await roof.open_roof()
        assert await obs.wait_for(lambda: roof.opened == 1.0, 1.0) == pytest.approx(0.0, abs=0.1)


async def test_the_recorder_hears_events_with_sender_and_time_and_waits_for_them() -> None:
    async with Observatory(speed=100.0) as obs:
        recorder = await obs.start(EventRecorder, "recorder", types=[RoofOpenedEvent, RoofClosedEvent])
        roof = await obs.start(SimRoof, "roof", open_time=60.0, close_time=60.0)
        start = obs.clock.time()
        await roof.open_roof()
        event = await recorder.wait_for_event(RoofOpenedEvent, 10.0, sender="roof")
        assert event == RoofOpenedEvent() and recorder.of(RoofOpenedEvent, sender="other") == []
        assert recorder.times(RoofOpenedEvent)[0] - start >= 60.0
        with pytest.raises(AssertionError, match="recorder heard no matching RoofClosedEvent: not within 5"):
            await recorder.wait_for_event(RoofClosedEvent, 5.0)
        recorder.clear()
        assert recorder.events == [] and recorder.arrivals == []
