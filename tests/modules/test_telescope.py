"""BaseTelescope through SimTelescope: refusals leave the state alone, slews take time, truth differs."""

from __future__ import annotations

import asyncio

import pytest

from nightcrew.astro import angular_separation
from nightcrew.errors import (
    AbortedError,
    ConfigError,
    DeviceBusyError,
    InvalidArgumentError,
    MoveError,
    RemoteTimeoutError,
)
from nightcrew.events import MotionStatusChangedEvent, MoveRaDecEvent
from nightcrew.interfaces import ITelescope, MotionStatus
from nightcrew.modules import Module
from nightcrew.modules.sim import ISimTelescopeTruth, SimTelescope
from nightcrew.testing import EventRecorder, Observatory

BETELGEUSE = (88.7929, 7.4071)  # about 46° up at the test epoch


async def _ready(observatory: Observatory, **kwargs: object) -> SimTelescope:
    telescope = await observatory.start(SimTelescope, "telescope", **kwargs)
    await telescope.init()
    return telescope


def test_a_telescope_needs_a_site_and_a_sane_altitude_limit() -> None:
    with pytest.raises(ConfigError, match="needs the observatory site"):
        SimTelescope(name="telescope")
    with pytest.raises(ConfigError, match=r"key 'min_altitude': min_altitude must be within 0..90"):
        SimTelescope(name="telescope", site={"latitude": 50, "longitude": 10}, min_altitude=95)


async def test_moves_while_parked_are_refused_until_init(observatory: Observatory) -> None:
    telescope = await observatory.start(SimTelescope, "telescope")
    assert await telescope.get_motion_status() is MotionStatus.PARKED
    before = await telescope.get_altaz()
    with pytest.raises(MoveError, match=r"cannot move: telescope is parked; call init\(\) first"):
        await telescope.move_radec(*BETELGEUSE)
    with pytest.raises(MoveError, match="call init"):
        await telescope.move_altaz(45.0, 180.0)
    assert await telescope.get_motion_status() is MotionStatus.PARKED
    assert await telescope.get_altaz() == pytest.approx(before)  # a parked mount does not track
    await telescope.init()
    await telescope.move_radec(*BETELGEUSE)
    assert await telescope.get_motion_status() is MotionStatus.TRACKING


async def test_targets_below_the_altitude_limit_are_refused_and_nothing_moves(
    observatory: Observatory,
) -> None:
    telescope = await _ready(observatory, min_altitude=20.0)
    await telescope.move_altaz(50.0, 120.0)
    with pytest.raises(
        MoveError, match=r"target alt=15.0000°, az=120.0000° is at altitude 15.00°, below the limit of 20°"
    ):
        await telescope.move_altaz(15.0, 120.0)
    with pytest.raises(
        MoveError, match=r"target ra=270.0000°, dec=-30.0000° is at altitude -\d+\.\d\d°, below"
    ):
        await telescope.move_radec(270.0, -30.0)
    alt, az = await telescope.get_altaz()
    assert alt == pytest.approx(50.0, abs=1e-6) and az == pytest.approx(120.0, abs=1e-6)
    assert await telescope.get_motion_status() is MotionStatus.IDLE


@pytest.mark.parametrize(
    ("call", "args", "message"),
    [
        (
            "move_radec",
            (360.0, 0.0),
            r"ra must be within 0..360 and dec within -90..90 degrees, got \(360.0, 0.0\)",
        ),
        ("move_radec", (10.0, 91.0), r"got \(10.0, 91.0\)"),
        (
            "move_altaz",
            (float("nan"), 0.0),
            r"alt must be within -90..90 degrees and az finite, got \(nan, 0.0\)",
        ),
        (
            "set_offsets_radec",
            (20.0, 0.0),
            r"offsets must be finite and within ±10 degrees, got \(20.0, 0.0\)",
        ),
    ],
)
async def test_bad_coordinates_are_invalid_arguments(
    observatory: Observatory, call: str, args: tuple[float, float], message: str
) -> None:
    telescope = await _ready(observatory)
    await telescope.move_radec(*BETELGEUSE)
    with pytest.raises(InvalidArgumentError, match=message):
        await getattr(telescope, call)(*args)
    assert await telescope.get_radec() == BETELGEUSE
    assert await telescope.get_offsets_radec() == (0.0, 0.0)


async def test_offsets_need_a_target_of_their_kind(observatory: Observatory) -> None:
    telescope = await _ready(observatory)
    with pytest.raises(MoveError, match=r"no RA/Dec target to offset from; call move_radec\(\) first"):
        await telescope.set_offsets_radec(0.01, 0.0)
    await telescope.move_radec(*BETELGEUSE)
    with pytest.raises(MoveError, match=r"no Alt/Az target to offset from; call move_altaz\(\) first"):
        await telescope.set_offsets_altaz(0.01, 0.0)
    await telescope.set_offsets_radec(0.01, -0.02)
    assert await telescope.get_offsets_radec() == (0.01, -0.02)
    ra, dec = await telescope.get_radec()
    assert (ra, dec) == pytest.approx((BETELGEUSE[0] + 0.01, BETELGEUSE[1] - 0.02))


async def test_slew_time_grows_with_distance(observatory: Observatory) -> None:
    telescope = await _ready(observatory, slew_rate=4.0, settle_time=3.0)
    durations = []
    for alt in (75.0, 45.0):  # 10° and 40° from the park position (85°, 0°)
        await telescope.park()
        await telescope.init()
        start = observatory.clock.time()
        await telescope.move_altaz(alt, 0.0)
        durations.append(observatory.clock.time() - start)
    # Never faster than the model; later only by event-loop latency (5 clock s = 50 ms of wall).
    assert 10 / 4 + 3 - 0.1 <= durations[0] < 10 / 4 + 3 + 5
    assert 40 / 4 + 3 - 0.1 <= durations[1] < 40 / 4 + 3 + 5


async def test_second_move_is_busy_and_park_aborts_a_slew(observatory: Observatory) -> None:
    telescope = await _ready(observatory, slew_rate=0.5)
    slew = asyncio.create_task(telescope.move_altaz(30.0, 180.0))
    await observatory.clock.sleep(5.0)
    assert await telescope.get_motion_status() is MotionStatus.SLEWING
    with pytest.raises(DeviceBusyError, match=r"busy \(move_altaz\); wait for it or stop the motion first"):
        await telescope.move_radec(*BETELGEUSE)
    await telescope.park()
    with pytest.raises(AbortedError, match="move_altaz was aborted"):
        await slew
    assert await telescope.get_motion_status() is MotionStatus.PARKED


async def test_stop_motion_leaves_the_telescope_between_start_and_target(observatory: Observatory) -> None:
    telescope = await _ready(observatory, slew_rate=1.0, settle_time=0.0)
    slew = asyncio.create_task(telescope.move_altaz(45.0, 0.0))
    await observatory.clock.sleep(20.0)
    await telescope.stop_motion()
    with pytest.raises(AbortedError):
        await slew
    alt, _ = await telescope.get_altaz()
    assert 45.0 < alt < 85.0
    assert await telescope.get_motion_status() is MotionStatus.IDLE


async def test_events_announce_moves_and_status_changes(observatory: Observatory) -> None:
    recorder = await observatory.start(
        EventRecorder, "recorder", types=[MoveRaDecEvent, MotionStatusChangedEvent]
    )
    telescope = await _ready(observatory)
    await telescope.move_radec(*BETELGEUSE)
    await observatory.clock.sleep(1.0)
    assert recorder.of(MoveRaDecEvent) == [MoveRaDecEvent(ra=BETELGEUSE[0], dec=BETELGEUSE[1])]
    statuses = [e.status for e in recorder.of(MotionStatusChangedEvent)]
    assert statuses == [
        MotionStatus.PARKED,
        MotionStatus.INITIALIZING,
        MotionStatus.IDLE,
        MotionStatus.SLEWING,
        MotionStatus.TRACKING,
    ]


async def test_header_has_pointing_airmass_and_moon(observatory: Observatory) -> None:
    telescope = await _ready(observatory)
    await telescope.move_radec(*BETELGEUSE)
    cards = await telescope.get_fits_header_before()
    assert cards["RA"][0] == pytest.approx(BETELGEUSE[0]) and cards["DEC"][0] == pytest.approx(BETELGEUSE[1])
    assert cards["OBJCTRA"][0] == "05 55 10.30" and cards["OBJCTDEC"][0] == "+07 24 25.6"
    assert 1.0 < float(cards["AIRMASS"][0] or 0) < 1.6
    assert 0 <= float(cards["MOONSEP"][0] or 0) <= 180
    assert {"TEL-ALT", "TEL-AZ", "RADESYS", "EQUINOX", "RAOFF", "DECOFF", "MOONALT"} <= set(cards)


async def test_true_pointing_misses_by_arcminutes_and_the_seed_repeats_it(observatory: Observatory) -> None:
    misses = []
    for name, seed in (("a", 7), ("b", 7), ("c", 8)):
        telescope = await observatory.start(SimTelescope, name, seed=seed, settle_time=0.0)
        await telescope.init()
        await telescope.move_radec(*BETELGEUSE)
        truth = await (await telescope.comm.proxy(name, ISimTelescopeTruth)).get_true_radec()
        misses.append(angular_separation(*BETELGEUSE, *truth) * 60.0)
        reported = await (await telescope.comm.proxy(name, ITelescope)).get_radec()
        assert reported == BETELGEUSE
    assert all(0.01 < miss < 6.0 for miss in misses)
    assert misses[0] == pytest.approx(misses[1], abs=0.01)  # drift/periodic error add little in 1 s
    assert misses[0] != pytest.approx(misses[2], abs=0.01)


async def test_an_offset_moves_the_true_pointing_by_the_offset_and_keeps_the_miss(
    observatory: Observatory,
) -> None:
    # Drift and periodic error off: what remains of the truth is the slew's miss.
    telescope = await _ready(observatory, pointing_error=5.0, drift_rate=0.0, periodic_amplitude=0.0)
    await telescope.move_radec(*BETELGEUSE)
    ra0, dec0 = await telescope.get_true_radec()
    await telescope.set_offsets_radec(0.0, 0.01)  # 36" north
    ra1, dec1 = await telescope.get_true_radec()
    assert (dec1 - dec0) * 3600 == pytest.approx(36.0, abs=0.01)
    assert (ra1 - ra0) * 3600 == pytest.approx(0.0, abs=0.01)
    # A slew to a new target draws a new miss: away and back does not land on the same spot.
    await telescope.move_radec(BETELGEUSE[0] + 1.0, BETELGEUSE[1])
    await telescope.move_radec(*BETELGEUSE)
    ra2, dec2 = await telescope.get_true_radec()
    assert angular_separation(ra2, dec2, ra0, dec0) * 3600 > 1.0


class _StuckTelescope(SimTelescope):
    """A mount whose Alt/Az slews never arrive (a driver waiting for a position it never reports)."""

    async def _hw_move_altaz(self, alt: float, az: float) -> None:
        await self.clock.sleep(1e9)


async def test_a_stuck_slew_is_noticed_after_its_length_at_the_mounts_rate(observatory: Observatory) -> None:
    # From the park position (alt 85°, az 0°) to alt 45°, az 180°: 50° over the zenith at 2°/s,
    # plus 3 s of settling: 28 s, announced with 30 s of margin and 10 wall seconds (clock speed 1)
    # - not the interface's 300 s.
    stuck = await observatory.start(_StuckTelescope, "stuck", slew_rate=2.0, settle_time=3.0)
    await stuck.init()
    caller = await observatory.start(Module, "caller")
    remote = await caller.comm.proxy("stuck", ITelescope)
    started = observatory.clock.time()
    with pytest.raises(RemoteTimeoutError, match=r"move_altaz\(\) did not finish within 68 s"):
        await remote.move_altaz(45.0, 180.0)
    assert 68 <= observatory.clock.time() - started < 80
