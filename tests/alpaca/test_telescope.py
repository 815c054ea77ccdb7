"""AlpacaTelescope beyond the contract: tracking, tracking rates, sync, pier side, Alt/Az vs RA/Dec
tracking, and an Alpaca error during a slew."""

from __future__ import annotations

from collections.abc import AsyncIterator
from typing import Any

import numpy as np
import pytest

from nightcrew.astro import altaz_to_radec, angular_separation
from nightcrew.clock import RealClock
from nightcrew.comm.rpc import RpcServer
from nightcrew.errors import InvalidArgumentError, MoveError
from nightcrew.interfaces import MotionStatus, PierSide
from nightcrew.modules.alpaca import AlpacaTelescope
from nightcrew.modules.alpaca.telescope import of_date
from nightcrew.testing import Observatory
from nightcrew.testing.alpaca import SIMULATOR_SITE, AlpacaSimulator
from tests.alpaca.faulty_server import FaultyServer, alpaca_error, value


@pytest.fixture
async def telescope(alpaca_simulator: AlpacaSimulator) -> AsyncIterator[AlpacaTelescope]:
    async with Observatory(clock=RealClock(), site=SIMULATOR_SITE) as obs:
        module = await obs.start(AlpacaTelescope, "telescope", server=alpaca_simulator.url)
        await module.init()
        yield module


async def test_radec_slews_track_and_altaz_slews_do_not(telescope: AlpacaTelescope) -> None:
    await telescope.move_altaz(50.0, 200.0)
    assert await telescope.device.get("tracking") is False
    assert await telescope.get_config_value("tracking") is False
    ra, dec = await telescope.get_radec()
    await telescope.move_radec(ra, dec)
    assert await telescope.device.get("tracking") is True
    assert await telescope.get_motion_status() is MotionStatus.TRACKING
    assert abs(await telescope.device.get("rightascension") * 15.0 - ra) < 0.01  # hours on the wire


async def test_pier_side_and_destination_side_come_from_the_mount(telescope: AlpacaTelescope) -> None:
    # alpaca-simulators keeps SideOfPier as set (as a mount that flipped would report it) and answers
    # DestinationSideOfPier by RA alone (WEST above 12 h): enough to check what travels on the wire.
    try:
        for raw, side in ((1, PierSide.WEST), (0, PierSide.EAST), (-1, PierSide.UNKNOWN)):
            await telescope.device.put("sideofpier", SideOfPier=raw)
            assert await telescope.get_pier_side() is side
            assert await telescope.get_config_value("pier_side") == str(side)
            header = await telescope.get_fits_header_before()
            assert header.get("PIERSIDE", (None,))[0] == (None if side is PierSide.UNKNOWN else side.upper())
    finally:
        await telescope.device.put("sideofpier", SideOfPier=0)
    assert await telescope.get_destination_pier_side(200.0, 20.0) is PierSide.WEST
    assert await telescope.get_destination_pier_side(100.0, 20.0) is PierSide.EAST
    with pytest.raises(InvalidArgumentError, match=r"ra must be within 0\.\.360"):
        await telescope.get_destination_pier_side(400.0, 20.0)


async def test_tracking_rates_sync_and_pier_side(telescope: AlpacaTelescope) -> None:
    assert "sidereal" in await telescope.get_config_value_options("tracking_rate")
    await telescope.set_config_value("tracking_rate", "lunar")
    assert await telescope.get_config_value("tracking_rate") == "lunar"
    assert await telescope.device.get("trackingrate") == 1
    await telescope.set_config_value("tracking_rate", "sidereal")
    with pytest.raises(InvalidArgumentError, match="unknown tracking rate 'warp'"):
        await telescope.set_config_value("tracking_rate", "warp")
    await telescope.set_config_value("tracking", False)
    assert await telescope.device.get("tracking") is False
    assert await telescope.get_config_value("pier_side") in ("east", "west", "unknown")

    await telescope.move_altaz(60.0, 180.0)
    ra, dec = await telescope.get_radec()
    await telescope.move_radec(ra, dec)
    await telescope.sync_radec((ra + 0.5) % 360.0, dec)
    synced_ra, _ = await telescope.get_radec()
    assert abs((synced_ra - ra - 0.5 + 180.0) % 360.0 - 180.0) < 0.05
    with pytest.raises(InvalidArgumentError):
        await telescope.sync_radec(400.0, 0.0)
    assert "ISyncRaDec" in RpcServer(telescope).interface_names  # other modules can sync it


def as_mount(server: FaultyServer, **members: Any) -> None:
    """Make ``server`` answer as an unparked mount at the simulator's site, plus ``members``."""
    mount: dict[str, Any] = {"connecting": False, "atpark": False, "slewing": False, "tracking": True}
    mount.update(sitelatitude=SIMULATOR_SITE.latitude, sitelongitude=SIMULATOR_SITE.longitude, **members)
    server.replies.update({member: value(v) for member, v in mount.items()})


async def test_an_alpaca_error_during_a_slew_is_a_move_error_naming_device_and_call(
    faulty: FaultyServer,
) -> None:
    as_mount(faulty)
    faulty.replies["slewtoaltazasync"] = alpaca_error(0x408, "the mount is parked")
    async with Observatory(clock=RealClock(), site=SIMULATOR_SITE) as obs:
        telescope = await obs.start(AlpacaTelescope, "telescope", server=faulty.url)
        await telescope.init()
        with pytest.raises(MoveError, match=r"telescope 0 at .*: PUT slewtoaltazasync: InvalidWhileParked"):
            await telescope.move_altaz(45.0, 90.0)
        assert await telescope.get_motion_status() is MotionStatus.ERROR


def test_of_date_is_fk5_precession() -> None:
    from astropy import units as u  # type: ignore[import-untyped]
    from astropy.coordinates import FK5, SkyCoord  # type: ignore[import-untyped]
    from astropy.time import Time  # type: ignore[import-untyped]

    unix_time = 1_795_000_000.0  # 2026-11-19
    for ra, dec in ((10.0, 20.0), (250.0, -60.0), (83.6, 22.0)):
        ra_d, dec_d = of_date(ra, dec, unix_time)
        expected = SkyCoord(ra * u.deg, dec * u.deg, frame=FK5(equinox="J2000")).transform_to(
            FK5(equinox=Time(unix_time, format="unix"))
        )
        assert abs((ra_d - expected.ra.deg + 180) % 360 - 180) * np.cos(np.radians(dec)) < 1 / 3600
        assert abs(dec_d - expected.dec.deg) < 1 / 3600
        assert of_date(ra_d, dec_d, unix_time, inverse=True) == pytest.approx((ra, dec), abs=1e-9)


async def test_a_jnow_mount_gets_and_gives_positions_of_date(faulty: FaultyServer) -> None:
    as_mount(faulty, equatorialsystem=1)
    async with Observatory(clock=RealClock(), site=SIMULATOR_SITE) as obs:
        telescope = await obs.start(AlpacaTelescope, "telescope", server=faulty.url)
        await telescope.init()
        alt_az_ra, alt_az_dec = altaz_to_radec(
            70.0, 180.0, SIMULATOR_SITE.latitude, SIMULATOR_SITE.longitude, obs.clock.time()
        )
        ra, dec = float(alt_az_ra) % 360.0, float(alt_az_dec)
        await telescope.move_radec(ra, dec)
        (fields,) = [f for _, member, f in faulty.requests if member == "slewtocoordinatesasync"]
        sent = (float(fields["RightAscension"]) * 15.0, float(fields["Declination"]))
        assert sent == pytest.approx(of_date(ra, dec, obs.clock.time()), abs=1e-3)
        # 27 years of precession (0.38 deg along the ecliptic, over 0.2 deg at any RA for this
        # Dec), not J2000; the Dec alone barely moves near RA 6h and 18h, where "now" may point.
        assert angular_separation(sent[0], sent[1], ra, dec) > 0.1
        faulty.replies["rightascension"] = value(sent[0] / 15.0)
        faulty.replies["declination"] = value(sent[1])
        assert await telescope.get_radec() == pytest.approx((ra, dec), abs=1e-3)
