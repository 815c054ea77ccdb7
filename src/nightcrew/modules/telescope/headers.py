"""FITS cards describing where a telescope points, as a pure function of its state."""

from __future__ import annotations

from nightcrew.astro import (
    airmass,
    angular_separation,
    format_dec,
    format_ra,
    moon_radec,
    radec_to_altaz,
)
from nightcrew.interfaces import FitsCard, PierSide
from nightcrew.site import Site

__all__ = ["pier_side_cards", "pointing_cards"]


def pointing_cards(
    *,
    radec: tuple[float, float],
    altaz: tuple[float, float],
    target: tuple[float, float] | None,
    offsets_radec: tuple[float, float],
    offsets_altaz: tuple[float, float],
    site: Site,
    unix_time: float,
) -> dict[str, FitsCard]:
    """Header cards for the current pointing.

    Args:
        radec: Where the telescope reports to point (ICRS, degrees, offsets included).
        altaz: The same as (alt, az).
        target: The RA/Dec target without offsets, None when not tracking one.
        offsets_radec: (dra, ddec) in degrees; offsets_altaz: (dalt, daz) in degrees.
    """
    ra, dec = radec
    alt, az = altaz
    cards: dict[str, FitsCard] = {
        "RA": (round(ra, 6), "Telescope right ascension [deg]"),
        "DEC": (round(dec, 6), "Telescope declination [deg]"),
        "RADESYS": ("ICRS", "Reference frame of RA/DEC"),
        "EQUINOX": (2000.0, "Equinox of RA/DEC [yr]"),
        "TEL-ALT": (round(alt, 5), "Telescope altitude [deg]"),
        "TEL-AZ": (round(az, 5), "Telescope azimuth, east of north [deg]"),
        "RAOFF": (round(offsets_radec[0], 6), "Offset along the RA axis [deg]"),
        "DECOFF": (round(offsets_radec[1], 6), "Offset along the Dec axis [deg]"),
        "ALTOFF": (round(offsets_altaz[0], 6), "Offset along the altitude axis [deg]"),
        "AZOFF": (round(offsets_altaz[1], 6), "Offset along the azimuth axis [deg]"),
    }
    if target is not None:
        cards["OBJCTRA"] = (format_ra(target[0]), "Target right ascension [hh mm ss]")
        cards["OBJCTDEC"] = (format_dec(target[1]), "Target declination [dd mm ss]")
    mass = airmass(alt)
    if mass is not None:
        cards["AIRMASS"] = (round(mass, 4), "Airmass at start of exposure")
    moon_ra, moon_dec = moon_radec(unix_time)
    moon_alt, _ = radec_to_altaz(moon_ra, moon_dec, site.latitude, site.longitude, unix_time)
    cards["MOONSEP"] = (round(angular_separation(ra, dec, moon_ra, moon_dec), 2), "Moon separation [deg]")
    cards["MOONALT"] = (round(moon_alt, 2), "Moon altitude [deg]")
    return cards


def pier_side_cards(side: PierSide) -> dict[str, FitsCard]:
    """The PIERSIDE card (EAST or WEST, ASCOM's SideOfPier); none when the mount cannot tell."""
    if side is PierSide.UNKNOWN:
        return {}
    return {"PIERSIDE": (side.upper(), "Side of pier (ASCOM SideOfPier: EAST looks west)")}
