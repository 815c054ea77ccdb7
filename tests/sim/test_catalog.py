"""Star catalog: real stars, proper motion, synthetic faint stars, cells and caching."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from astropy.io import fits  # type: ignore[import-untyped]
from astropy.time import Time  # type: ignore[import-untyped]
from scipy.spatial import cKDTree  # type: ignore[import-untyped]

from nightcrew.sim.catalog import StarCatalog, cell_mag_limit, epoch_jyear
from nightcrew.sim.catalog_data import MAS_PER_RAD, load_reference_stars, propagate, unit_vectors
from nightcrew.sim.real_stars import TYCHO2_ID_OFFSET, load_real_stars
from nightcrew.sim.sky_cells import SkyGrid
from nightcrew.sim.tycho2 import read_tycho2_index

BARNARD_GAIA_ID = 4472832130942575872
BARNARD_J2016 = (269.44850253, 4.73942005)


@pytest.fixture(scope="module")
def catalog() -> StarCatalog:
    return StarCatalog(depth=15.0, seed=7)


def test_bundled_catalog_reads_real_stars_with_hipparcos_motions() -> None:
    ref = load_reference_stars()
    assert len(ref.ra) == 482_176
    assert ref.mag.max() < 10.0
    barnard = np.flatnonzero(ref.source_id == BARNARD_GAIA_ID)[0]
    assert ref.mag[barnard] == pytest.approx(8.19, abs=0.01)
    assert (ref.pmra[barnard], ref.pmdec[barnard]) == pytest.approx((-798.58, 10328.12))
    # Most bright stars are in Hipparcos, so most of them move.
    assert np.mean(ref.pmra[ref.mag < 7.0] != 0.0) > 0.9


def test_barnards_star_moves_with_its_proper_motion(catalog: StarCatalog) -> None:
    before = catalog.query(*BARNARD_J2016, 0.1, epoch=2016.0, mag_limit=9.0)
    after = catalog.query(*BARNARD_J2016, 0.1, epoch=Time("2026-01-01T12:00:00", scale="tt"), mag_limit=9.0)
    star0 = before[before["source_id"] == BARNARD_GAIA_ID][0]
    star1 = after[after["source_id"] == BARNARD_GAIA_ID][0]
    assert (star0["ra"], star0["dec"]) == pytest.approx(BARNARD_J2016, abs=1e-7)
    years = 10.0
    d_dec = (star1["dec"] - star0["dec"]) * 3600.0
    d_ra = (star1["ra"] - star0["ra"]) * 3600.0 * np.cos(np.radians(star0["dec"]))
    assert d_dec == pytest.approx(10.32812 * years, abs=0.05)
    assert d_ra == pytest.approx(-0.79858 * years, abs=0.05)


def test_propagation_moves_by_the_total_proper_motion_even_at_the_pole() -> None:
    ra, dec = np.array([10.0, 200.0, 0.0]), np.array([89.99, -89.995, 90.0])
    pmra, pmdec = np.array([5000.0, -3000.0, 1000.0]), np.array([-2000.0, 4000.0, 0.0])
    ra1, dec1 = propagate(ra, dec, pmra, pmdec, 50.0)
    start, end = unit_vectors(ra, dec), unit_vectors(ra1, dec1)
    moved_arcsec = np.degrees(np.arccos(np.clip(np.sum(start * end, axis=1), -1, 1))) * 3600.0
    expected = np.degrees(np.arctan(np.hypot(pmra, pmdec) * 50.0 / MAS_PER_RAD)) * 3600.0
    np.testing.assert_allclose(moved_arcsec, expected, rtol=1e-4)
    assert np.all(np.isfinite(ra1)) and np.all(np.abs(dec1) <= 90.0)


def test_query_is_a_cone_sorted_by_magnitude(catalog: StarCatalog) -> None:
    stars = catalog.query(83.8, -5.4, 0.4, mag_limit=13.0)
    assert len(stars) > 50
    assert np.all(np.diff(stars["mag"]) >= 0)
    assert stars["mag"].max() < 13.0
    sep = np.degrees(
        np.arccos(
            np.sin(np.radians(stars["dec"])) * np.sin(np.radians(-5.4))
            + np.cos(np.radians(stars["dec"]))
            * np.cos(np.radians(-5.4))
            * np.cos(np.radians(stars["ra"] - 83.8))
        )
    )
    assert sep.max() <= 0.4
    assert set(stars["synthetic"][stars["mag"] < 10.0]) == {False}
    assert stars["mag"][stars["synthetic"]].min() >= 10.0
    assert np.all(stars["source_id"][stars["synthetic"]] == 0)


def test_query_across_ra_zero_and_pole_finds_the_same_stars_as_a_brute_force_search() -> None:
    catalog = StarCatalog(depth=11.0, seed=1)
    for ra, dec in [(0.1, 30.0), (45.0, 89.5), (300.0, -88.0)]:
        stars = catalog.query(ra, dec, 2.0)
        wide = catalog.query(ra, dec, 6.0)
        centre = np.array(
            [
                np.cos(np.radians(dec)) * np.cos(np.radians(ra)),
                np.cos(np.radians(dec)) * np.sin(np.radians(ra)),
                np.sin(np.radians(dec)),
            ]
        )
        vec = np.stack(
            [
                np.cos(np.radians(wide["dec"])) * np.cos(np.radians(wide["ra"])),
                np.cos(np.radians(wide["dec"])) * np.sin(np.radians(wide["ra"])),
                np.sin(np.radians(wide["dec"])),
            ],
            axis=-1,
        )
        expected = np.count_nonzero(vec @ centre >= np.cos(np.radians(2.0)))
        assert len(stars) == expected > 0


def test_synthetic_stars_are_deterministic_per_seed() -> None:
    a = StarCatalog(depth=14.0, seed=3).query(120.0, 10.0, 0.5)
    b = StarCatalog(depth=14.0, seed=3).query(120.0, 10.0, 0.5)
    c = StarCatalog(depth=14.0, seed=4).query(120.0, 10.0, 0.5)
    np.testing.assert_array_equal(a, b)
    assert len(a) != len(c) or not np.array_equal(a["ra"], c["ra"])


def test_synthetic_number_counts_grow_by_the_configured_factor() -> None:
    stars = StarCatalog(depth=16.0, count_growth_per_mag=2.5, seed=0).query(200.0, 30.0, 3.0)
    # Below ~12.5 the real Tycho-2 stars count, not the model.
    counts, _ = np.histogram(stars["mag"], bins=[13.0, 14.0, 15.0, 16.0])
    ratios = counts[1:] / counts[:-1]
    np.testing.assert_allclose(ratios, 2.5, rtol=0.1)


def test_synthetic_density_follows_the_real_stars() -> None:
    catalog = StarCatalog(depth=14.0)
    plane = catalog.query(280.0, -5.0, 2.0)  # Milky Way in Aquila/Scutum
    pole = catalog.query(192.9, 27.1, 2.0)  # north galactic pole
    # Fainter than 13 both fields are synthetic (their real limits differ: ~11 and 12).
    faint_plane = np.count_nonzero(plane["synthetic"] & (plane["mag"] >= 13.0))
    faint_pole = np.count_nonzero(pole["synthetic"] & (pole["mag"] >= 13.0))
    assert faint_plane > 3 * faint_pole > 0


def test_epoch_accepts_time_or_julian_year() -> None:
    assert epoch_jyear(2024.5) == 2024.5
    assert epoch_jyear(Time(2024.5, format="jyear", scale="tt")) == pytest.approx(2024.5)


def test_sky_grid_cells_cover_the_sky_with_similar_areas() -> None:
    grid = SkyGrid(1.0)
    areas = np.array([grid.cell(i).area_deg2 for i in range(grid.n_cells)])
    assert areas.sum() == pytest.approx(4 * np.pi * (180 / np.pi) ** 2, rel=1e-9)
    assert np.median(areas) == pytest.approx(1.0, rel=0.05)
    rng = np.random.default_rng(0)
    ra, dec = rng.uniform(0, 360, 1000), np.degrees(np.arcsin(rng.uniform(-1, 1, 1000)))
    for cid, r, d in zip(grid.cell_ids(ra, dec), ra, dec, strict=True):
        cell = grid.cell(int(cid))
        assert cell.ra_min <= r < cell.ra_max + 1e-9 and cell.dec_min <= d <= cell.dec_max


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [({"depth": 30.0}, "depth must be within"), ({"count_growth_per_mag": 1.0}, "must be > 1")],
)
def test_invalid_catalog_options_are_refused(kwargs: dict[str, float], message: str) -> None:
    with pytest.raises(ValueError, match=message):
        StarCatalog(**kwargs)  # type: ignore[arg-type]


def test_invalid_query_is_refused(catalog: StarCatalog) -> None:
    with pytest.raises(ValueError, match="radius_deg must be within"):
        catalog.query(0.0, 0.0, 0.0)


def test_tycho2_index_stars_fill_the_sky_to_magnitude_12() -> None:
    ref = load_real_stars()
    tycho = ref.source_id <= -TYCHO2_ID_OFFSET
    # index-tycho2-07 holds 1.87 million stars, ~1.4 million of them fainter than Gaia's G = 10.
    assert 1_300_000 < np.count_nonzero(tycho) < 1_871_011
    assert np.median(ref.mag[tycho]) == pytest.approx(11.2, abs=0.3)
    # At the north galactic pole a 0.33 deg cone now holds real stars to G ~ 12, not only 10.
    stars = StarCatalog(depth=12.0).query(192.9, 27.1, 0.33)
    real = stars[~stars["synthetic"]]
    assert np.count_nonzero(real["mag"] > 10.0) > 3 * np.count_nonzero(real["mag"] <= 10.0)


def test_tycho2_stars_are_not_counted_twice_where_gaia_has_them() -> None:
    ref = load_real_stars()
    xyz = unit_vectors(ref.ra, ref.dec)
    pairs = cKDTree(xyz).query_pairs(np.radians(1.0 / 3600.0), output_type="ndarray")
    tycho = ref.source_id <= -TYCHO2_ID_OFFSET
    # A handful remain: fast movers that Gaia holds without a Hipparcos motion (> 3" since J2000).
    assert np.count_nonzero(tycho[pairs[:, 0]] != tycho[pairs[:, 1]]) < 20


def test_cell_limit_is_shallower_where_the_index_kept_only_the_brightest() -> None:
    ref = load_real_stars()
    grid = SkyGrid(1.0)
    ids = grid.cell_ids(ref.ra, ref.dec)
    plane = ref.mag[ids == grid.cell_ids(np.array([280.0]), np.array([-5.0]))[0]]
    pole = ref.mag[ids == grid.cell_ids(np.array([192.9]), np.array([27.1]))[0]]
    assert cell_mag_limit(plane) < cell_mag_limit(pole) == pytest.approx(12.0, abs=0.3)
    assert cell_mag_limit(np.zeros(0, np.float32)) == 12.0


def test_a_missing_index_file_is_named(tmp_path: Path) -> None:
    with pytest.raises(FileNotFoundError, match=r"index-tycho2-99\.fits: Tycho-2 index missing"):
        read_tycho2_index(tmp_path / "index-tycho2-99.fits")
    not_an_index = tmp_path / "plain.fits"
    fits.writeto(not_an_index, np.zeros((2, 2)))
    with pytest.raises(ValueError, match=r"plain\.fits: expected a little-endian index file"):
        read_tycho2_index(not_an_index)
