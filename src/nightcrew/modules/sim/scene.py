"""What a simulated camera sees, as pure functions: the scene learnt from the devices, the
conditions at the site, and a cache of star fields.

:class:`Scene` holds what the camera asked the other modules at the start of an exposure;
:func:`conditions_at` turns it, with the site and the time, into the renderer's
:class:`~nightcrew.sim.render.Conditions`; :class:`StarFieldCache` keeps catalog cones so that
repeated exposures of one field do not query the catalog again.
"""

from __future__ import annotations

from collections import OrderedDict
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from nightcrew.astro import (
    airmass,
    angular_separation,
    moon_altitude,
    moon_illumination,
    radec_to_altaz,
    sun_altitude,
)
from nightcrew.sim.catalog import STAR_DTYPE, StarCatalog
from nightcrew.sim.render import Conditions
from nightcrew.site import Site

__all__ = ["Atmosphere", "Scene", "StarFieldCache", "conditions_at"]


@dataclass(frozen=True)
class Scene:
    """What the devices said at the start of an exposure.

    Attributes:
        true_radec: Where the telescope really points (ICRS degrees); None without a telescope.
        focus_error: Focuser position (with offset) minus the best focus, in focuser units (mm).
        filter_name: Filter in the beam; None without a filter wheel.
        throughput: The filter's throughput, 0..1.
        roof_open: Whether light reaches the telescope.
        cloud_cover: Fraction of the sky covered, 0..1.
        covered: Whether a closed cover keeps the sky out.
        panel: Brightness of a lit flat panel in front of the optics, 0..1 of its maximum.
        field_rotation: Position angle of the detector's +y (degrees): 180 on the west side of a
            German-equatorial mount's pier, where the field stands upside down after a flip.
        rates: The mount's offset rates (arcsec/s of RA and Dec) on top of sidereal tracking.
        followed: The moving target the mount follows (as a task gives it), if any.
    """

    true_radec: tuple[float, float] | None
    focus_error: float = 0.0
    filter_name: str | None = None
    throughput: float = 1.0
    roof_open: bool = True
    cloud_cover: float = 0.0
    covered: bool = False
    panel: float = 0.0
    field_rotation: float = 0.0
    rates: tuple[float, float] = (0.0, 0.0)
    followed: dict[str, Any] | None = None


@dataclass(frozen=True)
class Atmosphere:
    """The site's sky, from configuration: seeing, extinction and the darkest sky brightness."""

    seeing_arcsec: float = 1.5
    extinction_mag_per_airmass: float = 0.2
    dark_sky_mag: float = 21.0


def conditions_at(
    scene: Scene, site: Site | None, unix_time: float, atmosphere: Atmosphere, panel_e_per_s: float = 0.0
) -> Conditions:
    """The renderer's conditions for ``scene`` seen from ``site`` at ``unix_time``.

    No light reaches the detector when the roof is closed, when there is no telescope (the pointing
    is unknown) or when it points below the horizon. Without a site the sky is a dark night at
    airmass 1. Clouds dim starlight by the covered fraction (the sky background stays). A closed
    cover keeps the sky out; a lit panel gives ``panel_e_per_s`` at full brightness.
    """
    light = scene.roof_open and scene.true_radec is not None and not scene.covered
    mass, sun_alt, moon_alt, moon_lit = 1.0, -90.0, -90.0, 0.0
    if site is not None:
        sun_alt = sun_altitude(site.latitude, site.longitude, unix_time)
        moon_alt = moon_altitude(site.latitude, site.longitude, unix_time)
        moon_lit = moon_illumination(unix_time)
        if scene.true_radec is not None:
            alt, _ = radec_to_altaz(*scene.true_radec, site.latitude, site.longitude, unix_time)
            computed = airmass(alt)
            if computed is None:
                light = False
            else:
                mass = computed
    return Conditions(
        seeing_arcsec=atmosphere.seeing_arcsec,
        airmass=mass,
        extinction_mag_per_airmass=atmosphere.extinction_mag_per_airmass,
        sun_altitude_deg=sun_alt,
        moon_altitude_deg=moon_alt,
        moon_illumination=moon_lit,
        dark_sky_mag=atmosphere.dark_sky_mag,
        transmission=min(1.0, max(0.0, 1.0 - scene.cloud_cover)),
        roof_open=light,
        panel_e_per_s=panel_e_per_s * min(1.0, max(0.0, scene.panel)),
    )


class StarFieldCache:
    """Catalog cones around recent pointings; a cone is reused while it still covers the field.

    A query fetches a cone ``margin_deg`` wider than asked, so that small moves (pointing errors,
    drift, dithers) stay inside it. The ``size`` most recent cones are kept.
    """

    def __init__(self, catalog: StarCatalog, *, margin_deg: float = 0.25, size: int = 8) -> None:
        self._catalog = catalog
        self._margin = margin_deg
        self._size = size
        self._cones: OrderedDict[tuple[float, float, float, float], npt.NDArray[np.void]] = OrderedDict()

    def stars(self, ra: float, dec: float, radius_deg: float, epoch_jyear: float) -> npt.NDArray[np.void]:
        """Stars within at least ``radius_deg`` of (ra, dec), positions at ``epoch_jyear``."""
        for key, stars in self._cones.items():
            ra0, dec0, radius0, epoch0 = key
            covered = angular_separation(ra0, dec0, ra, dec) + radius_deg <= radius0
            # Proper motions move stars by < 1" per 0.1 yr: close enough for one night.
            if covered and abs(epoch0 - epoch_jyear) < 0.1:
                self._cones.move_to_end(key)
                return stars
        wide = min(30.0, radius_deg + self._margin)
        stars = self._catalog.query(ra, dec, wide, epoch=epoch_jyear)
        self._cones[(ra, dec, wide, epoch_jyear)] = stars
        while len(self._cones) > self._size:
            self._cones.popitem(last=False)
        return stars

    @staticmethod
    def empty() -> npt.NDArray[np.void]:
        """No stars (what a camera without a telescope sees)."""
        return np.zeros(0, STAR_DTYPE)
