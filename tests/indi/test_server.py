"""IndiServer checked by third-party INDI clients: indi_getprop and indi_setprop (Debian indi-bin).

The simulated observatory runs in this process on a fast clock; IndiServer serves it on a free
loopback port (no network namespace needed: it binds 127.0.0.1 only). Waits are bounded loops on
what the clients report, never fixed sleeps.
"""

from __future__ import annotations

import asyncio
import contextlib
from pathlib import Path

import pytest
from astropy.io import fits  # type: ignore[import-untyped]

from nightcrew.astro import altaz_to_radec, j2000_to_of_date
from nightcrew.comm.local import LocalComm
from nightcrew.interfaces import MotionStatus
from nightcrew.modules.indi.server import IndiServer
from nightcrew.vfs import VirtualFileSystem
from tests.indi.served import SITE, Served
from tests.indi.server_clients import PATIENCE, getprop, run, setprop, wait_for


async def test_getprop_lists_the_simulated_observatory_with_the_telescope_position(served: Served) -> None:
    # The telescope is also a guider (4): it takes timed guide pulses.
    kinds = {"telescope": "5", "camera": "2", "focuser": "8", "filters": "16", "dome": "32"}
    values = await getprop(served.port, *(f"{d}.DRIVER_INFO.DRIVER_INTERFACE" for d in kinds))
    assert values == {f"{d}.DRIVER_INFO.DRIVER_INTERFACE": bits for d, bits in kinds.items()}

    specs = [
        "telescope.EQUATORIAL_EOD_COORD.RA",
        "telescope.EQUATORIAL_EOD_COORD.DEC",
        "telescope.TELESCOPE_PARK.PARK",
    ]
    values = await getprop(served.port, *specs)
    ra, dec = await served.telescope.get_radec()
    ra_date, dec_date = j2000_to_of_date(ra, dec, served.clock.time())
    # Parked, the telescope points at a fixed alt/az: its declination stays, its RA moves with the sky.
    assert float(values[specs[1]]) == pytest.approx(dec_date, abs=1e-5)
    assert abs((float(values[specs[0]]) - ra_date / 15.0 + 12.0) % 24.0 - 12.0) < 0.05
    assert values[specs[2]] == "On"
    location = await getprop(served.port, "telescope.GEOGRAPHIC_COORD.LAT", "telescope.GEOGRAPHIC_COORD.LONG")
    assert float(location["telescope.GEOGRAPHIC_COORD.LAT"]) == pytest.approx(SITE.latitude)
    assert float(location["telescope.GEOGRAPHIC_COORD.LONG"]) == pytest.approx(SITE.longitude)


async def test_setprop_slews_the_telescope_and_nightcrew_sees_the_move(
    served: Served, tmp_path: Path
) -> None:
    port = served.port
    await setprop(port, "telescope.TELESCOPE_PARK.UNPARK=On")
    await wait_for(
        port,
        ["telescope.TELESCOPE_PARK.UNPARK", "telescope.TELESCOPE_PARK._STATE"],
        lambda v: (
            v["telescope.TELESCOPE_PARK.UNPARK"] == "On" and v["telescope.TELESCOPE_PARK._STATE"] == "Ok"
        ),
    )
    # A client watches the slew's state from before it starts to after it ends.
    watch = asyncio.create_task(
        run("indi_getprop", "-p", port, "-m", "-t", "4", "telescope.EQUATORIAL_EOD_COORD._STATE")
    )
    await wait_for(port, ["telescope.EQUATORIAL_EOD_COORD._STATE"], lambda v: True)

    ra, dec = altaz_to_radec(60.0, 180.0, SITE.latitude, SITE.longitude, served.clock.time())
    ra_date, dec_date = j2000_to_of_date(ra, dec, served.clock.time())
    await setprop(port, f"telescope.EQUATORIAL_EOD_COORD.RA;DEC={ra_date / 15.0:.8f};{dec_date:.8f}")

    move = await asyncio.wait_for(served.moves.get(), PATIENCE)
    assert (move.ra, move.dec) == pytest.approx((ra, dec), abs=2e-6)
    values = await wait_for(
        port,
        [
            "telescope.EQUATORIAL_EOD_COORD._STATE",
            "telescope.EQUATORIAL_EOD_COORD.RA",
            "telescope.EQUATORIAL_EOD_COORD.DEC",
        ],
        lambda v: v["telescope.EQUATORIAL_EOD_COORD._STATE"] == "Ok",
        "the slew's end (state Ok)",
    )
    assert float(values["telescope.EQUATORIAL_EOD_COORD.RA"]) == pytest.approx(ra_date / 15.0, abs=1e-6)
    assert float(values["telescope.EQUATORIAL_EOD_COORD.DEC"]) == pytest.approx(dec_date, abs=1e-5)
    assert await served.telescope.get_motion_status() is MotionStatus.TRACKING
    assert await served.telescope.get_radec() == pytest.approx((ra, dec), abs=2e-6)
    tracking = await getprop(port, "telescope.TELESCOPE_TRACK_STATE.TRACK_ON")
    assert tracking == {"telescope.TELESCOPE_TRACK_STATE.TRACK_ON": "On"}

    _, seen, _ = await watch
    states = [line.partition("=")[2] for line in seen.splitlines()]
    assert "Busy" in states, states
    assert "Ok" in states[states.index("Busy") :], states

    # Abort a second slew midway: the slew's property goes to Alert and the mount stops.
    far_ra, far_dec = altaz_to_radec(30.0, 90.0, SITE.latitude, SITE.longitude, served.clock.time())
    far = j2000_to_of_date(far_ra, far_dec, served.clock.time())
    await setprop(port, f"telescope.EQUATORIAL_EOD_COORD.RA;DEC={far[0] / 15.0:.8f};{far[1]:.8f}")
    await asyncio.wait_for(served.moves.get(), PATIENCE)
    await setprop(port, "telescope.TELESCOPE_ABORT_MOTION.ABORT=On")
    await wait_for(
        port,
        ["telescope.EQUATORIAL_EOD_COORD._STATE"],
        lambda v: v["telescope.EQUATORIAL_EOD_COORD._STATE"] == "Alert",
        "the aborted slew's Alert",
    )
    assert await served.telescope.get_motion_status() is MotionStatus.IDLE

    # A slew nightcrew itself makes (a script, the mastermind) is seen by the client too.
    ra, dec = altaz_to_radec(50.0, 150.0, SITE.latitude, SITE.longitude, served.clock.time())
    await served.telescope.move_radec(ra, dec)
    ra_date, dec_date = j2000_to_of_date(ra, dec, served.clock.time())
    values = await wait_for(
        port,
        ["telescope.EQUATORIAL_EOD_COORD.DEC", "telescope.TELESCOPE_TRACK_STATE.TRACK_ON"],
        lambda v: abs(float(v["telescope.EQUATORIAL_EOD_COORD.DEC"]) - dec_date) < 1e-5,
        "the position of nightcrew's own slew",
    )
    assert values["telescope.TELESCOPE_TRACK_STATE.TRACK_ON"] == "On"


async def test_an_exposure_reaches_the_client_as_a_fits_blob(served: Served, tmp_path: Path) -> None:
    port = served.port
    await setprop(port, "camera.CCD_BINNING.HOR_BIN;VER_BIN=2;2")
    await wait_for(port, ["camera.CCD_BINNING.HOR_BIN"], lambda v: v["camera.CCD_BINNING.HOR_BIN"] == "2.0")
    await setprop(port, "camera.CCD_FRAME_TYPE.FRAME_DARK=On")
    # indi_getprop enables BLOBs and writes each one it receives to device.property.element.format.
    monitor = asyncio.create_task(
        run("indi_getprop", "-p", port, "-m", "-t", "30", "camera.CCD1.CCD1", cwd=tmp_path)
    )
    await wait_for(port, ["camera.CCD_EXPOSURE._STATE"], lambda v: True)
    await setprop(port, "camera.CCD_EXPOSURE.CCD_EXPOSURE_VALUE=2.5")

    path = tmp_path / "camera.CCD1.CCD1.fits"
    loop = asyncio.get_running_loop()
    deadline = loop.time() + PATIENCE
    while not (path.exists() and path.stat().st_size >= 2 * 2880):
        assert loop.time() < deadline, "no FITS BLOB written by indi_getprop"
        await asyncio.sleep(0.1)
    monitor.cancel()
    await asyncio.gather(monitor, return_exceptions=True)
    await wait_for(port, ["camera.CCD_EXPOSURE._STATE"], lambda v: v["camera.CCD_EXPOSURE._STATE"] == "Ok")
    with fits.open(path) as hdul:
        header, data = hdul[0].header, hdul[0].data
        assert data.shape == (24, 32)  # 48 x 64 binned 2 x 2
        assert (header["EXPTIME"], header["IMAGETYP"], header["XBINNING"]) == (2.5, "dark", 2)


async def test_focuser_filter_wheel_and_dome(served: Served) -> None:
    port = served.port
    names = await getprop(port, *(f"filters.FILTER_NAME.FILTER_SLOT_NAME_{i}" for i in (1, 2, 3)))
    assert list(names.values()) == ["B", "V", "R"]
    await setprop(port, "filters.FILTER_SLOT.FILTER_SLOT_VALUE=3")
    await setprop(port, "focuser.ABS_FOCUS_POSITION.FOCUS_ABSOLUTE_POSITION=26500")
    await setprop(port, "dome.DOME_SHUTTER.SHUTTER_OPEN=On")
    await setprop(port, "dome.ABS_DOME_POSITION.DOME_ABSOLUTE_POSITION=120")
    done = {
        "filters.FILTER_SLOT.FILTER_SLOT_VALUE": "3.0",
        "filters.FILTER_SLOT._STATE": "Ok",
        "focuser.ABS_FOCUS_POSITION.FOCUS_ABSOLUTE_POSITION": "26500.0",
        "focuser.ABS_FOCUS_POSITION._STATE": "Ok",
        "dome.DOME_SHUTTER.SHUTTER_OPEN": "On",
        "dome.DOME_SHUTTER._STATE": "Ok",
        "dome.ABS_DOME_POSITION.DOME_ABSOLUTE_POSITION": "120.0",
        "dome.ABS_DOME_POSITION._STATE": "Ok",
    }
    await wait_for(port, list(done), lambda v: all(v[k] == want for k, want in done.items()))
    assert await served.filters.get_filter() == "R"
    assert await served.focuser.get_focus() == pytest.approx(26.5)
    assert await served.dome.get_motion_status() is MotionStatus.IDLE  # open
    assert await served.dome.get_azimuth() == pytest.approx(120.0)

    # Beyond the focuser's own range (0..50 mm): nightcrew refuses, the property goes to Alert.
    await setprop(port, "focuser.ABS_FOCUS_POSITION.FOCUS_ABSOLUTE_POSITION=80000")
    await wait_for(
        port,
        ["focuser.ABS_FOCUS_POSITION._STATE"],
        lambda v: v["focuser.ABS_FOCUS_POSITION._STATE"] == "Alert",
    )
    assert await served.focuser.get_focus() == pytest.approx(26.5)


async def read_until(reader: asyncio.StreamReader, needle: bytes, seen: bytearray) -> None:
    """Read into ``seen`` until it holds ``needle``; fail if the server hangs up or takes too long."""
    async with asyncio.timeout(PATIENCE):
        while needle not in seen:
            chunk = await reader.read(65536)
            assert chunk, f"the server hung up before sending {needle!r}"
            seen += chunk


async def hung_up(reader: asyncio.StreamReader) -> bool:
    """Whether the server closes the connection (within PATIENCE; a reset counts)."""
    async with asyncio.timeout(PATIENCE):
        try:
            while await reader.read(65536):
                pass
        except ConnectionResetError:
            pass  # closed with our unread request in its buffer
    return True


async def test_bad_client_input_is_answered_and_never_ends_the_service(served: Served) -> None:
    port = served.port
    seen = bytearray()
    requests = {
        b'<newNumberVector device="focuser" name="ABS_FOCUS_POSITION">'
        b'<oneNumber name="FOCUS_ABSOLUTE_POSITION">abc</oneNumber></newNumberVector>': (
            b"focuser.ABS_FOCUS_POSITION.FOCUS_ABSOLUTE_POSITION: not a number: 'abc'"
        ),
        b'<newNumberVector device="telescope" name="EQUATORIAL_EOD_COORD">'
        b'<oneNumber name="RA">25</oneNumber><oneNumber name="DEC">40</oneNumber></newNumberVector>': (
            b"telescope.EQUATORIAL_EOD_COORD.RA=25 is outside 0..24"
        ),
        b'<newNumberVector device="telescope" name="HORIZONTAL_COORD">'
        b'<oneNumber name="ALT">40</oneNumber></newNumberVector>': (
            b"telescope.HORIZONTAL_COORD is read-only"
        ),
        b'<newSwitchVector device="telescope" name="NOPE">'
        b'<oneSwitch name="X">On</oneSwitch></newSwitchVector>': (b"no property telescope.NOPE here"),
        b'<newSwitchVector device="nobody" name="NOPE">'
        b'<oneSwitch name="X">On</oneSwitch></newSwitchVector>': (b"no property nobody.NOPE here"),
        b'<newTextVector device="filters" name="FILTER_NAME">'
        b'<oneText name="FILTER_SLOT_NAME_1">U</oneText></newTextVector>': (
            b"filters.FILTER_NAME is read-only"
        ),
    }
    reader, writer = await asyncio.open_connection("127.0.0.1", int(port))
    try:
        for request, answer in requests.items():
            writer.write(request + b"\n")
            await read_until(reader, answer, seen)
        # What a client has no business sending is ignored; the connection stays usable.
        writer.write(
            b'<defNumberVector device="x" name="y"/><getProperties version="1.7" device="nobody"/>\n'
        )
        writer.write(b'<getProperties version="1.7" device="filters" name="FILTER_NAME"/>\n')
        await read_until(reader, b'<defTextVector device="filters" name="FILTER_NAME"', seen)
        # Malformed XML ends that client's connection, and only that.
        writer.write(b"<newSwitchVector device='telescope'><<>>\n")
        assert await hung_up(reader)
    finally:
        writer.close()
        with contextlib.suppress(ConnectionError):
            await writer.wait_closed()
    # So does an element that never ends.
    reader, writer = await asyncio.open_connection("127.0.0.1", int(port))
    try:
        writer.write(b"<newTextVector device='telescope' name='X'><oneText name='Y'>" + b"x" * (2 << 20))
        assert await hung_up(reader)
    finally:
        writer.close()
        with contextlib.suppress(ConnectionError):
            await writer.wait_closed()

    values = await getprop(port, "telescope.TELESCOPE_PARK.PARK", "telescope.EQUATORIAL_EOD_COORD._STATE")
    assert values == {"telescope.TELESCOPE_PARK.PARK": "On", "telescope.EQUATORIAL_EOD_COORD._STATE": "Alert"}
    assert served.moves.empty()
    assert await served.telescope.get_motion_status() is MotionStatus.PARKED
    assert await served.focuser.get_motion_status() is MotionStatus.IDLE


async def test_an_image_the_server_cannot_read_ends_the_exposure_in_alert(served: Served) -> None:
    """A server without the camera's VFS root: the exposure runs, the client learns why no BLOB came."""
    blind = IndiServer(
        port=0,
        camera="camera",
        poll_interval=0.2,
        comm=LocalComm("blind", network=served.network),
        clock=served.clock,
        vfs=VirtualFileSystem(),
    )
    await blind.open()
    try:
        port = str(blind.port)
        await wait_for(port, ["camera.CCD_EXPOSURE._STATE"], lambda v: True)
        reader, writer = await asyncio.open_connection("127.0.0.1", blind.port)
        try:
            writer.write(
                b'<newNumberVector device="camera" name="CCD_EXPOSURE">'
                b'<oneNumber name="CCD_EXPOSURE_VALUE">1</oneNumber></newNumberVector>\n'
            )
            seen = bytearray()
            await read_until(reader, b"unknown root '/cache'", seen)
            at = seen.index(b"unknown root '/cache'")
            answer = seen[seen.rindex(b"<setNumberVector", 0, at) : at]
            assert b'name="CCD_EXPOSURE" state="Alert"' in answer, answer
        finally:
            writer.close()
            with contextlib.suppress(ConnectionError):
                await writer.wait_closed()
        values = await getprop(port, "camera.CCD_EXPOSURE._STATE")
        assert values == {"camera.CCD_EXPOSURE._STATE": "Alert"}
    finally:
        await blind.close()


async def test_a_module_in_error_state_shows_as_alert_until_it_recovers(served: Served) -> None:
    port = served.port
    state = "telescope.CONNECTION._STATE"
    await wait_for(port, [state], lambda v: v[state] == "Ok")
    served.telescope.set_error("mount controller lost")
    await wait_for(port, [state], lambda v: v[state] == "Alert", "CONNECTION in Alert")
    # Requests meanwhile are refused by the module and end in Alert too.
    await setprop(port, "telescope.TELESCOPE_PARK.UNPARK=On")
    park = "telescope.TELESCOPE_PARK._STATE"
    await wait_for(port, [park], lambda v: v[park] == "Alert", "TELESCOPE_PARK in Alert")
    assert await served.telescope.reset_error()
    await wait_for(port, [state], lambda v: v[state] == "Ok", "CONNECTION back to Ok")
    assert await served.telescope.get_motion_status() is MotionStatus.PARKED
