"""The mastermind's dusk focus on the simulated observatory: bright twilight sky, raw frames with hot
pixels and cosmic rays, the series of the sim night (7 frames 0.3 mm apart, 15 s, filter R).

Tolerance: the in-focus FWHM is 1.7" (seeing 1.5", optics 0.8") and defocus adds 15" per mm in
quadrature, so 0.05 mm off focus widens stars by 9 % - a fraction of the depth of focus (0.11 mm,
where stars are 41 % wider). A dusk focus must land within 0.05 mm of the simulator's truth.
"""

from __future__ import annotations

from collections.abc import AsyncIterator
from datetime import datetime
from itertools import pairwise

import pytest

from nightcrew.astro import altaz_to_radec
from nightcrew.astro.star_fields import StarFieldRules, choose_star_fields
from nightcrew.events import FocusFoundEvent
from nightcrew.modules.focus.series import AutoFocusSeries
from nightcrew.modules.sim import SimFilterWheel, SimFocuser
from nightcrew.robotic.mastermind import catalogue_stars
from nightcrew.testing import SITE, Observatory
from tests.modules.sim_observatory import start_observatory

#: The Sun at -10°: right after the sky flats, when the mastermind focuses.
DUSK = "2026-11-10T16:42:00+00:00"
_DUSK_UNIX = datetime.fromisoformat(DUSK).timestamp()


def dusk_field() -> tuple[float, float]:
    """Where the mastermind focuses then, tracked: the field its default rules choose from the
    catalogue nearest to where the flat-field pointing left the telescope (80° high in the east)."""
    (field,) = choose_star_fields(
        catalogue_stars(),
        altaz_to_radec(80.0, 90.0, SITE.latitude, SITE.longitude, _DUSK_UNIX),
        StarFieldRules(),
        latitude=SITE.latitude,
        longitude=SITE.longitude,
        unix_time=_DUSK_UNIX,
        limit=1,
    )
    return field.ra, field.dec


TOLERANCE_MM = 0.05


@pytest.fixture
async def dusk() -> AsyncIterator[Observatory]:
    obs = Observatory(epoch=DUSK)
    try:
        yield obs
    finally:
        await obs.close()


async def test_a_dusk_series_finds_the_true_focus(dusk: Observatory) -> None:
    await start_observatory(
        dusk,
        target=dusk_field(),
        # The sim night's camera: full 1k chip with hot pixels and cosmic rays, its optics and stars.
        detector={"chip_width": 1024, "chip_height": 1024},
        optics={"optics_fwhm_arcsec": 0.8, "defocus_arcsec_per_unit": 15.0},
        catalog_depth=16.0,
        seed=42,
    )
    await dusk.module("filters", SimFilterWheel).set_filter("R")
    focuser = dusk.module("focuser", SimFocuser)
    truth = await focuser.get_best_focus()
    await focuser.set_focus(truth - 0.25)
    autofocus = await dusk.start(AutoFocusSeries, "autofocus", camera="camera", focuser="focuser")
    found: list[FocusFoundEvent] = []

    async def on_focus(event: FocusFoundEvent, sender: str) -> bool:
        found.append(event)
        return True

    await focuser.comm.register_event(FocusFoundEvent, on_focus)

    focus, error = await autofocus.auto_focus(7, 0.3, 15.0)

    status = await autofocus.auto_focus_status()
    print(f"dusk focus {focus:.4f} ± {error:.4f} mm, truth {truth:.4f} mm; series {status['measurements']}")
    assert focus == pytest.approx(truth, abs=TOLERANCE_MM)
    assert error < TOLERANCE_MM
    assert await focuser.get_focus() == pytest.approx(focus, abs=1e-6)
    # Every frame measured, and the widths grow away from focus on both sides (a clean V).
    widths = [w for _, w in sorted(status["measurements"])]
    best = widths.index(min(widths))
    assert all(a > b for a, b in pairwise(widths[: best + 1]))
    assert all(a < b for a, b in pairwise(widths[best:]))
