"""The simulated sky's astrometry.net index files for the night's fields, built once per session."""

from __future__ import annotations

import sys
import time
from pathlib import Path

import pytest

from tests.sim.night_fields import NIGHT_SKY, NIGHT_WIDTH_ARCMIN, night_fields


@pytest.fixture(scope="session")
def night_index_dir() -> Path:
    """Index files of the `make sim` night's sky around its fields, in the user's cache (kept across runs).

    The first build takes under 2 s per field (the night's 20 fields: 33 s on 2 busy cores, 8 MB);
    later runs find the files and take no time.
    """
    from nightcrew.sim.sky_index import SkyIndexBuilder

    started = time.perf_counter()
    builder = SkyIndexBuilder(NIGHT_SKY(), progress=lambda line: print(line, file=sys.stderr))
    fields = [(f.header_ra_deg, f.header_dec_deg) for f in night_fields()]  # what the night knows
    directory = builder.blocking_build(fields, width_arcmin=[NIGHT_WIDTH_ARCMIN])
    print(f"sky indexes ready in {time.perf_counter() - started:.1f} s: {directory}", file=sys.stderr)
    return directory
