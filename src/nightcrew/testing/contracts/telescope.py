"""The telescope contract: what every ITelescope module shows, whatever mount it drives."""

from __future__ import annotations

from typing import Any, ClassVar

import pytest

from nightcrew.astro import altaz_to_radec, angular_separation
from nightcrew.errors import DeviceBusyError, InvalidArgumentError, MoveError
from nightcrew.events import MoveAltAzEvent, MoveRaDecEvent, OffsetsRaDecEvent
from nightcrew.interfaces import (
    IFitsHeaderBefore,
    IOffsetsRaDec,
    IPierSide,
    ITelescope,
    MotionStatus,
    PierSide,
)
from nightcrew.testing.contracts._base import ContractSetup, DeviceContract, timed_call

__all__ = ["TelescopeContract"]

#: Statuses in which a telescope must refuse to move.
_NOT_READY = (MotionStatus.PARKED, MotionStatus.ERROR, MotionStatus.UNKNOWN)


class TelescopeContract(DeviceContract):
    """Contract of an :class:`~nightcrew.interfaces.ITelescope` module (see :mod:`nightcrew.testing`).

    Each test starts by ``init()`` and a move to a *work position* near where the mount is: its
    altitude clamped into :attr:`work_altitudes`. Moves from there are :attr:`step` degrees (or
    :attr:`long_step` for the ones the suite interrupts), so a real mount passes quickly.
    """

    interface = ITelescope
    #: Degrees between a target and where the mount reports to point once there.
    pointing_tolerance: ClassVar[float] = 1.0 / 60.0
    #: Degrees of a small move.
    step: ClassVar[float] = 2.0
    #: Degrees of a move the suite interrupts (busy, park, stop_motion); long enough to catch it.
    long_step: ClassVar[float] = 20.0
    #: Altitudes (degrees) the suite works at; must lie above the mount's own altitude limit.
    work_altitudes: ClassVar[tuple[float, float]] = (30.0, 70.0)
    #: Size of the RA/Dec offset, degrees.
    offset: ClassVar[float] = 0.05

    # --- steps ---------------------------------------------------------------------------------

    async def _work_position(self, contract: ContractSetup[Any]) -> tuple[float, float]:
        """Initialise and move to the work position; return it as (alt, az)."""
        telescope = await contract.proxy(ITelescope)
        await telescope.init()
        alt, az = await telescope.get_altaz()
        low, high = self.work_altitudes
        work = (min(high, max(low, round(alt, 3))), round(az, 3) % 360.0)
        await telescope.move_altaz(*work)
        return work

    def _next_altitude(self, alt: float, step: float) -> float:
        """An altitude ``step`` away from ``alt``, towards the middle of the work altitudes."""
        low, high = self.work_altitudes
        return alt + step if alt < (low + high) / 2.0 else alt - step

    def _assert_near(self, where: tuple[float, float], target: tuple[float, float], what: str) -> None:
        # (lon, lat) order: (ra, dec) or (az, alt); the great-circle distance treats both alike.
        miss = angular_separation(where[0], where[1], target[0], target[1])
        assert miss <= self.pointing_tolerance, (
            f'{what}: reported {where} is {miss * 3600:.1f}" from the target {target} '
            f'(tolerance {self.pointing_tolerance * 3600:.1f}")'
        )

    async def _status(self, contract: ContractSetup[Any]) -> MotionStatus:
        return await (await contract.proxy(ITelescope)).get_motion_status()

    async def _slewing(self, contract: ContractSetup[Any]) -> bool:
        return await self._status(contract) is MotionStatus.SLEWING

    # --- tests ---------------------------------------------------------------------------------

    async def test_a_parked_telescope_refuses_to_move_until_init(self, contract: ContractSetup[Any]) -> None:
        telescope = await contract.proxy(ITelescope)
        alt, az = await self._work_position(contract)
        await telescope.park()
        assert await telescope.get_motion_status() is MotionStatus.PARKED
        assert not await telescope.is_ready()
        with pytest.raises(MoveError, match="init"):
            await telescope.move_altaz(alt, az)
        ra, dec = await telescope.get_radec()
        with pytest.raises(MoveError, match="init"):
            await telescope.move_radec(ra, dec)
        await telescope.init()
        assert await telescope.get_motion_status() not in _NOT_READY
        assert await telescope.is_ready()
        await contract.wait_for(
            lambda: MotionStatus.PARKED in contract.statuses() and contract.statuses()[-1] not in _NOT_READY,
            self.timeout,
            "MotionStatusChangedEvent to PARKED and back to ready",
        )

    async def test_move_altaz_gets_there_and_announces_it(self, contract: ContractSetup[Any]) -> None:
        telescope = await contract.proxy(ITelescope)
        alt, az = await self._work_position(contract)
        contract.probe.clear()
        target = (self._next_altitude(alt, self.step), az)
        await telescope.move_altaz(*target)
        assert await telescope.get_motion_status() is MotionStatus.IDLE
        reported = await telescope.get_altaz()
        self._assert_near((reported[1], reported[0]), (target[1], target[0]), "move_altaz")
        event = await contract.probe.wait_for_event(MoveAltAzEvent, self.timeout, sender=contract.name)
        assert (event.alt, event.az) == pytest.approx(target)
        await contract.wait_for(
            lambda: contract.statuses()[-2:] == [MotionStatus.SLEWING, MotionStatus.IDLE],
            self.timeout,
            "MotionStatusChangedEvent SLEWING, then IDLE",
        )

    async def test_move_radec_tracks_the_target_and_announces_it(self, contract: ContractSetup[Any]) -> None:
        telescope = await contract.proxy(ITelescope)
        await self._work_position(contract)
        ra, dec = await telescope.get_radec()
        target = ((ra + self.step) % 360.0, dec)
        contract.probe.clear()
        await telescope.move_radec(*target)
        assert await telescope.get_motion_status() is MotionStatus.TRACKING
        self._assert_near(await telescope.get_radec(), target, "move_radec")
        event = await contract.probe.wait_for_event(MoveRaDecEvent, self.timeout, sender=contract.name)
        assert (event.ra, event.dec) == pytest.approx(target)
        await contract.wait_for(
            lambda: contract.statuses()[-2:] == [MotionStatus.SLEWING, MotionStatus.TRACKING],
            self.timeout,
            "MotionStatusChangedEvent SLEWING, then TRACKING",
        )
        # Tracking: a while later it still points at the target.
        await contract.clock.sleep(2.0)
        self._assert_near(await telescope.get_radec(), target, "tracking")

    async def test_targets_below_the_horizon_are_refused_and_nothing_moves(
        self, contract: ContractSetup[Any]
    ) -> None:
        telescope = await contract.proxy(ITelescope)
        alt, az = await self._work_position(contract)
        site = contract.module.site
        assert site is not None, f"{contract.name} has no site: a telescope needs one"
        contract.probe.clear()
        with pytest.raises(MoveError, match="below"):
            await telescope.move_altaz(-10.0, az)
        low_ra, low_dec = altaz_to_radec(-30.0, az, site.latitude, site.longitude, contract.clock.time())
        with pytest.raises(MoveError, match="below"):
            await telescope.move_radec(float(low_ra) % 360.0, float(low_dec))
        assert await telescope.get_motion_status() is MotionStatus.IDLE
        reported = await telescope.get_altaz()
        self._assert_near((reported[1], reported[0]), (az, alt), "after refused moves")
        assert contract.events(MoveAltAzEvent) == [] and contract.events(MoveRaDecEvent) == []

    @pytest.mark.parametrize(
        ("method", "args"),
        [("move_radec", (400.0, 0.0)), ("move_radec", (10.0, 95.0)), ("move_altaz", (95.0, 0.0))],
    )
    async def test_impossible_coordinates_are_invalid_arguments(
        self, contract: ContractSetup[Any], method: str, args: tuple[float, float]
    ) -> None:
        telescope = await contract.proxy(ITelescope)
        await self._work_position(contract)
        before = await telescope.get_radec()
        with pytest.raises(InvalidArgumentError):
            await getattr(telescope, method)(*args)
        assert await telescope.get_motion_status() is MotionStatus.IDLE
        self._assert_near(await telescope.get_radec(), before, "after the refused call")

    async def test_a_second_move_while_slewing_is_busy(self, contract: ContractSetup[Any]) -> None:
        telescope = await contract.proxy(ITelescope)
        alt, az = await self._work_position(contract)
        target = (self._next_altitude(alt, self.long_step), az)
        slew = await self._start_interruptible(
            contract, lambda: telescope.move_altaz(*target), lambda: self._slewing(contract), "a long slew"
        )
        with pytest.raises(DeviceBusyError):
            await telescope.move_altaz(alt, az)
        await slew  # the first move is not disturbed
        reported = await telescope.get_altaz()
        self._assert_near((reported[1], reported[0]), (target[1], target[0]), "the first move")

    async def test_park_aborts_a_slew(self, contract: ContractSetup[Any]) -> None:
        telescope = await contract.proxy(ITelescope)
        alt, az = await self._work_position(contract)
        target = (self._next_altitude(alt, self.long_step), az)
        slew = await self._start_interruptible(
            contract, lambda: telescope.move_altaz(*target), lambda: self._slewing(contract), "a long slew"
        )
        await telescope.park()
        await self._expect_aborted(slew)
        assert await telescope.get_motion_status() is MotionStatus.PARKED

    async def test_stop_motion_stops_a_slew(self, contract: ContractSetup[Any]) -> None:
        telescope = await contract.proxy(ITelescope)
        alt, az = await self._work_position(contract)
        target = (self._next_altitude(alt, self.long_step), az)
        slew = await self._start_interruptible(
            contract, lambda: telescope.move_altaz(*target), lambda: self._slewing(contract), "a long slew"
        )
        await telescope.stop_motion()
        await self._expect_aborted(slew)
        assert await telescope.get_motion_status() is MotionStatus.IDLE
        # Stopped means stopped: it stays where it is.
        here = await telescope.get_altaz()
        await contract.clock.sleep(2.0)
        again = await telescope.get_altaz()
        self._assert_near((again[1], again[0]), (here[1], here[0]), "after stop_motion")

    async def test_radec_offsets_move_the_pointing_and_are_announced(
        self, contract: ContractSetup[Any]
    ) -> None:
        if not isinstance(contract.module, IOffsetsRaDec):
            pytest.skip(f"{contract.name} offers no IOffsetsRaDec")
        telescope = await contract.proxy(ITelescope)
        offsets = await contract.proxy(IOffsetsRaDec)
        await self._work_position(contract)
        ra, dec = await telescope.get_radec()
        await telescope.move_radec(ra, dec)
        contract.probe.clear()
        await offsets.set_offsets_radec(0.0, self.offset)
        assert await offsets.get_offsets_radec() == pytest.approx((0.0, self.offset))
        self._assert_near(await telescope.get_radec(), (ra, dec + self.offset), "with offsets")
        event = await contract.probe.wait_for_event(OffsetsRaDecEvent, self.timeout, sender=contract.name)
        assert (event.dra, event.ddec) == pytest.approx((0.0, self.offset))
        await telescope.move_radec(ra, dec)  # a new target resets the offsets
        assert await offsets.get_offsets_radec() == (0.0, 0.0)

    async def test_fits_header_tells_where_it_points_and_on_which_side(
        self, contract: ContractSetup[Any]
    ) -> None:
        assert isinstance(contract.module, IFitsHeaderBefore), f"{contract.name} gives no FITS header"
        telescope = await contract.proxy(ITelescope)
        await self._work_position(contract)
        ra, dec = await telescope.get_radec()
        await telescope.move_radec(ra, dec)
        cards = await (await contract.proxy(IFitsHeaderBefore)).get_fits_header_before()
        assert {"RA", "DEC", "TEL-ALT", "TEL-AZ", "OBJCTRA", "OBJCTDEC", "AIRMASS"} <= set(cards)
        self._assert_near(
            (float(cards["RA"][0] or 0), float(cards["DEC"][0] or 0)), (ra, dec), "RA/DEC cards"
        )
        # The pier side, where the mount knows it, is in the header too (ASCOM's EAST or WEST).
        pier = await contract.proxy(IPierSide)
        side = await pier.get_pier_side()
        assert isinstance(side, PierSide), f"get_pier_side() gave {side!r}"
        assert cards.get("PIERSIDE", (None,))[0] == (None if side is PierSide.UNKNOWN else side.upper())
        assert isinstance(await pier.get_destination_pier_side(ra, dec), PierSide)

    async def test_bad_weather_parks_the_telescope(self, contract: ContractSetup[Any]) -> None:
        telescope = await contract.proxy(ITelescope)
        await self._work_position(contract)
        await contract.probe.send_bad_weather("contract suite: rain")

        async def parked() -> bool:
            return await telescope.get_motion_status() is MotionStatus.PARKED

        await contract.wait_for(parked, self.timeout, "the telescope parking on bad weather")
        await contract.probe.send_good_weather()

    async def test_motions_end_within_the_timeouts_they_announce(self, contract: ContractSetup[Any]) -> None:
        alt, az = await self._work_position(contract)
        for method, args in (
            ("park", ()),
            ("init", ()),
            ("move_altaz", (self._next_altitude(alt, self.long_step), az)),
            ("move_altaz", (alt, az)),
        ):
            announced, took = await timed_call(contract, method, *args)
            assert took < announced, f"{method}{args} took {took:.1f} s but announced {announced:g} s"
