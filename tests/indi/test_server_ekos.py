"""IndiServer serves what KStars/Ekos asks for, with INDI's names and semantics.

``EKOS_ASKED`` are the properties KStars 3.6.2 (Debian ``kstars``) set or read in ``bench/ekos.py``
against IndiServer (its log of ``new*Vector``, and the INDI reads of the bench); the others are
those Ekos' modules use by their standard names (mount control, guiding, capture, focus, dome).
Checked with indi_getprop/indi_setprop (indi-bin) and, where the answer is a message, a raw socket.
"""

from __future__ import annotations

import asyncio
import contextlib

import pytest

from nightcrew.astro import altaz_to_radec, angular_separation, j2000_to_of_date
from nightcrew.bridges.indi import IndiClient
from nightcrew.clock import RealClock
from nightcrew.interfaces import MotionStatus
from nightcrew.modules.indi import IndiTelescope
from nightcrew.modules.indi.server import IndiServer
from nightcrew.modules.indi.server_guiding import SIDEREAL_DEG_PER_S
from nightcrew.testing import Observatory
from nightcrew.testing import wait_for as wait_until
from nightcrew.testing.indi import IndiServer as IndiSimulators
from tests.indi.served import SITE, Served
from tests.indi.server_clients import PATIENCE, getprop, require_clients, setprop, wait_for

#: What Ekos sent or read in bench/ekos.py (see its output in docs/indi.md).
EKOS_ASKED = {
    "telescope": {"TIME_UTC", "TELESCOPE_PARK", "EQUATORIAL_EOD_COORD", "TELESCOPE_PIER_SIDE"},
    "camera": {"CCD_EXPOSURE", "CCD_TEMPERATURE", "CCD_COOLER"},
}
#: What Ekos' modules use besides (mount control, guider, capture, focus and dome modules).
STANDARD = {
    "telescope": {
        "TELESCOPE_INFO",
        "TELESCOPE_SLEW_RATE",
        "TELESCOPE_MOTION_NS",
        "TELESCOPE_MOTION_WE",
        "TELESCOPE_TIMED_GUIDE_NS",
        "TELESCOPE_TIMED_GUIDE_WE",
        "GUIDE_RATE",
        "ON_COORD_SET",
        "TELESCOPE_ABORT_MOTION",
        "TELESCOPE_TRACK_STATE",
        "HORIZONTAL_COORD",
    },
    "camera": {
        "CCD_INFO",
        "CCD_FRAME",
        "CCD_BINNING",
        "CCD_FRAME_TYPE",
        "CCD_COOLER_POWER",
        "CCD_CFA",
        "CCD_COMPRESSION",
        "UPLOAD_MODE",
        "CCD_ABORT_EXPOSURE",
        "CCD1",
    },
    "focuser": {
        "ABS_FOCUS_POSITION",
        "REL_FOCUS_POSITION",
        "FOCUS_MOTION",
        "FOCUS_MAX",
        "FOCUS_TEMPERATURE",
        "FOCUS_ABORT_MOTION",
    },
    "dome": {"DOME_PARK", "DOME_MOTION", "DOME_SHUTTER", "ABS_DOME_POSITION", "DOME_ABORT_MOTION"},
}


async def test_every_property_ekos_asks_for_is_served(served: Served) -> None:
    client = IndiClient("127.0.0.1", int(served.port))  # nightcrew's own INDI client: waits on events
    await client.open()
    try:
        await client.wait_connected(within=PATIENCE)
        for wanted in (EKOS_ASKED, STANDARD):
            for device, names in wanted.items():
                for name in names:
                    await client.wait_defined(device, name, PATIENCE)
    finally:
        await client.close()
    # CCD_INFO has the pixel sizes from the first frame on (the camera's FITS says XPIXSZ = 9 µm).
    await setprop(served.port, "camera.CCD_EXPOSURE.CCD_EXPOSURE_VALUE=0.5")
    await wait_for(
        served.port,
        [
            "camera.CCD_INFO.CCD_PIXEL_SIZE",
            "camera.CCD_INFO.CCD_PIXEL_SIZE_X",
            "camera.CCD_INFO.CCD_PIXEL_SIZE_Y",
        ],
        lambda v: set(v.values()) == {"9.0"},
    )


async def _tracking_south(served: Served) -> tuple[float, float]:
    await served.telescope.init()
    ra, dec = altaz_to_radec(50.0, 180.0, SITE.latitude, SITE.longitude, served.clock.time())
    await served.telescope.move_radec(ra, dec)
    return ra, dec


async def test_guide_pulses_and_hand_motions_move_by_the_offsets(served: Served) -> None:
    port = served.port
    await _tracking_south(served)
    # A 0.4-s pulse north at 0.5x sidereal: 3" in Dec; Busy during the pulse, then Ok and 0 again.
    await setprop(port, "telescope.TELESCOPE_TIMED_GUIDE_NS.TIMED_GUIDE_N=400")
    await wait_for(
        port,
        ["telescope.TELESCOPE_TIMED_GUIDE_NS._STATE", "telescope.TELESCOPE_TIMED_GUIDE_NS.TIMED_GUIDE_N"],
        lambda v: (
            v["telescope.TELESCOPE_TIMED_GUIDE_NS._STATE"] == "Ok"
            and v["telescope.TELESCOPE_TIMED_GUIDE_NS.TIMED_GUIDE_N"] == "0.0"
        ),
    )
    dra, ddec = await served.telescope.get_offsets_radec()
    assert (dra, ddec) == pytest.approx((0.0, 0.5 * SIDEREAL_DEG_PER_S * 0.4))
    # West at 0.25x: RA lower by a quarter of sidereal rate x 0.2 s.
    await setprop(port, "telescope.GUIDE_RATE.GUIDE_RATE_WE=0.25")
    await setprop(port, "telescope.TELESCOPE_TIMED_GUIDE_WE.TIMED_GUIDE_W=200")
    await wait_for(
        port,
        ["telescope.TELESCOPE_TIMED_GUIDE_WE._STATE"],
        lambda v: v["telescope.TELESCOPE_TIMED_GUIDE_WE._STATE"] == "Ok",
    )
    assert (await served.telescope.get_offsets_radec())[0] == pytest.approx(-0.25 * SIDEREAL_DEG_PER_S * 0.2)

    # The hand paddle: east at the centering rate until switched off; the offset grows, then stays.
    await setprop(port, "telescope.TELESCOPE_MOTION_WE.MOTION_EAST=On")
    await wait_for(
        port,
        ["telescope.TELESCOPE_MOTION_WE._STATE"],
        lambda v: v["telescope.TELESCOPE_MOTION_WE._STATE"] == "Busy",
    )
    before = (await served.telescope.get_offsets_radec())[0]
    loop = asyncio.get_running_loop()
    deadline = loop.time() + 30.0
    while (await served.telescope.get_offsets_radec())[0] <= before:
        assert loop.time() < deadline, "the motion east did not raise the RA offset"
        await asyncio.sleep(0.05)
    await setprop(port, "telescope.TELESCOPE_MOTION_WE.MOTION_EAST=Off")
    await wait_for(
        port,
        ["telescope.TELESCOPE_MOTION_WE._STATE"],
        lambda v: v["telescope.TELESCOPE_MOTION_WE._STATE"] == "Ok",
    )

    async def tracking() -> bool:  # the last step's offset slew ends by itself
        return await served.telescope.get_motion_status() is MotionStatus.TRACKING

    await wait_until(tracking, PATIENCE, clock=served.clock, message="tracking after the motion")


async def _answers(port: str, requests: dict[bytes, bytes]) -> None:
    """Send each request on one connection and read until its expected answer arrives."""
    reader, writer = await asyncio.open_connection("127.0.0.1", int(port))
    seen = bytearray()
    try:
        for request, answer in requests.items():
            writer.write(request + b"\n")
            async with asyncio.timeout(30):
                while answer not in seen:
                    chunk = await reader.read(65536)
                    assert chunk, f"connection closed before {answer!r}"
                    seen += chunk
    finally:
        writer.close()
        with contextlib.suppress(ConnectionError):
            await writer.wait_closed()


async def test_what_cannot_be_done_is_alert_with_the_reason(served: Served) -> None:
    await _tracking_south(served)
    await _answers(
        served.port,
        {
            # The simulated mount has no ISyncRaDec: a SYNC is refused, not turned into a slew.
            b'<newSwitchVector device="telescope" name="ON_COORD_SET">'
            b'<oneSwitch name="SYNC">On</oneSwitch></newSwitchVector>': b'name="ON_COORD_SET" state="Ok"',
            b'<newNumberVector device="telescope" name="EQUATORIAL_EOD_COORD">'
            b'<oneNumber name="RA">3</oneNumber><oneNumber name="DEC">20</oneNumber></newNumberVector>': (
                b"cannot sync (it offers no ISyncRaDec)"
            ),
            b'<newNumberVector device="telescope" name="TELESCOPE_TIMED_GUIDE_NS">'
            b'<oneNumber name="TIMED_GUIDE_N">-5</oneNumber></newNumberVector>': (
                b"telescope.TELESCOPE_TIMED_GUIDE_NS.TIMED_GUIDE_N=-5 is outside 0..60000"
            ),
            b'<newNumberVector device="telescope" name="TELESCOPE_TIMED_GUIDE_NS">'
            b'<oneNumber name="TIMED_GUIDE_N">100</oneNumber>'
            b'<oneNumber name="TIMED_GUIDE_S">100</oneNumber></newNumberVector>': b"one direction per pulse",
            b'<newSwitchVector device="camera" name="UPLOAD_MODE">'
            b'<oneSwitch name="UPLOAD_LOCAL">On</oneSwitch></newSwitchVector>': (
                b"only UPLOAD_CLIENT is offered"
            ),
            b'<newSwitchVector device="camera" name="CCD_COMPRESSION">'
            b'<oneSwitch name="CCD_COMPRESS">On</oneSwitch></newSwitchVector>': b"only CCD_RAW is offered",
            b'<newNumberVector device="camera" name="CCD_TEMPERATURE">'
            b'<oneNumber name="CCD_TEMPERATURE_VALUE">-99</oneNumber></newNumberVector>': (
                b"camera.CCD_TEMPERATURE.CCD_TEMPERATURE_VALUE=-99 is outside -60..40"
            ),
            b'<newTextVector device="telescope" name="TIME_UTC">'
            b'<oneText name="UTC">2030-01-01T00:00:00</oneText><oneText name="OFFSET">0</oneText>'
            b"</newTextVector>": b"nightcrew keeps its own clock",
        },
    )
    assert (await served.telescope.get_offsets_radec()) == (0.0, 0.0)  # no pulse ran


async def test_cooling_focuser_steps_and_dome_parking(served: Served) -> None:
    port = served.port
    await setprop(port, "camera.CCD_TEMPERATURE.CCD_TEMPERATURE_VALUE=-10")
    await setprop(port, "focuser.FOCUS_MOTION.FOCUS_OUTWARD=On")
    start = float((await getprop(port, "focuser.ABS_FOCUS_POSITION.FOCUS_ABSOLUTE_POSITION")).popitem()[1])
    await setprop(port, "focuser.REL_FOCUS_POSITION.FOCUS_RELATIVE_POSITION=1500")
    await setprop(port, "dome.DOME_PARK.UNPARK=On")
    done = {
        "camera.CCD_COOLER.COOLER_ON": "On",
        "focuser.ABS_FOCUS_POSITION.FOCUS_ABSOLUTE_POSITION": f"{start + 1500:.1f}",
        "focuser.REL_FOCUS_POSITION._STATE": "Ok",
        "dome.DOME_PARK.UNPARK": "On",
        "dome.DOME_PARK._STATE": "Ok",
        "dome.DOME_SHUTTER.SHUTTER_OPEN": "On",
    }
    await wait_for(port, list(done), lambda v: all(v[k] == want for k, want in done.items()))
    cooling = await served.camera.get_cooling()
    assert (cooling.enabled, cooling.setpoint) == (True, -10.0)
    temperature = await getprop(port, "focuser.FOCUS_TEMPERATURE.TEMPERATURE")
    ambient = (await served.focuser.get_temperatures())["ambient"]
    assert float(temperature["focuser.FOCUS_TEMPERATURE.TEMPERATURE"]) == pytest.approx(ambient, abs=0.01)

    await setprop(port, "dome.DOME_MOTION.DOME_CW=On")
    await wait_for(
        port,
        ["dome.ABS_DOME_POSITION.DOME_ABSOLUTE_POSITION", "dome.DOME_MOTION._STATE"],
        lambda v: (
            v["dome.DOME_MOTION._STATE"] == "Ok"
            and float(v["dome.ABS_DOME_POSITION.DOME_ABSOLUTE_POSITION"]) > 0
        ),
    )
    assert await served.dome.get_azimuth() == pytest.approx(90.0)
    await setprop(port, "dome.DOME_PARK.PARK=On")
    await wait_for(
        port,
        ["dome.DOME_PARK.PARK", "dome.DOME_PARK._STATE"],
        lambda v: v["dome.DOME_PARK.PARK"] == "On" and v["dome.DOME_PARK._STATE"] == "Ok",
    )
    assert await served.dome.get_motion_status() is MotionStatus.PARKED


async def test_sync_through_the_server_reaches_a_mount_that_can_sync(indi_server: IndiSimulators) -> None:
    """ON_COORD_SET SYNC then EQUATORIAL_EOD_COORD: sync_radec() of the served telescope - here an
    IndiTelescope on indi-bin's simulator, so the chain is Ekos-like client, IndiServer, nightcrew,
    INDI driver."""
    require_clients()
    async with Observatory(clock=RealClock()) as obs:
        telescope = await obs.start(
            IndiTelescope,
            "telescope",
            host=indi_server.host,
            port=indi_server.port,
            device="Telescope Simulator",
        )
        server = await obs.start(IndiServer, "indi", port=0, telescope="telescope", poll_interval=0.2)
        port = str(server.port)
        await telescope.init()
        ra, dec = await telescope.get_radec()
        now = j2000_to_of_date(ra, dec + 0.5, obs.clock.time())
        await setprop(port, "telescope.ON_COORD_SET.SYNC=On")
        await setprop(port, f"telescope.EQUATORIAL_EOD_COORD.RA;DEC={now[0] / 15.0};{now[1]}")
        await wait_for(
            port,
            ["telescope.EQUATORIAL_EOD_COORD.DEC", "telescope.EQUATORIAL_EOD_COORD._STATE"],
            lambda v: (
                v["telescope.EQUATORIAL_EOD_COORD._STATE"] == "Ok"
                and abs(float(v["telescope.EQUATORIAL_EOD_COORD.DEC"]) - now[1]) < 1 / 60
            ),
        )
        assert angular_separation(*await telescope.get_radec(), ra, dec + 0.5) < 1 / 60
        assert await telescope.get_motion_status() is not MotionStatus.SLEWING  # synced, not slewed
