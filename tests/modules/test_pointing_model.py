"""The pointing model on the simulated observatory: series, fit (the CLI), the telescope applying it,
the passive refit, and bad model files."""

from __future__ import annotations

import csv
from pathlib import Path

import pytest

from nightcrew.astro import altaz_to_radec, angular_separation
from nightcrew.cli.main import main
from nightcrew.errors import ConfigError
from nightcrew.images import Pipeline
from nightcrew.images.astrometry import CatalogAstrometry
from nightcrew.images.processors.detection import SepSourceDetection
from nightcrew.interfaces import ImageType
from nightcrew.modules.pointing import PassivePointingRefit, PointingSeries
from nightcrew.modules.pointing.series import CSV_COLUMNS, sky_grid
from nightcrew.modules.sim import SimCamera, SimTelescope
from nightcrew.testing import SITE, Observatory
from nightcrew.testing.solver import SimulatedSkyIndexes

DETECTOR = {"chip_width": 512, "chip_height": 512, "cosmic_rays_per_s": 0.0}
DEPTH, SEED = 17.0, 5
#: A few arcminutes each (within the catalog matcher's 15' search), arcsec.
TERMS = {"IH": 300.0, "ID": -240.0, "CH": 180.0, "MA": 240.0, "ME": -200.0}
#: The mount's random miss per slew and drift made small, so the terms dominate.
QUIET = {"pointing_error": 0.01, "drift_rate": 0.0, "periodic_amplitude": 0.0}


def test_the_sky_grid_spreads_points_above_the_limit() -> None:
    points = sky_grid(40, 25.0, 80.0)
    assert len(points) == 40
    assert all(25.0 <= alt <= 80.0 for alt, _ in points)
    quadrants = {int(az // 90.0) for _, az in points}
    assert quadrants == {0, 1, 2, 3}


async def start_devices(observatory: Observatory, model: Path) -> SimTelescope:
    telescope = await observatory.start(
        SimTelescope,
        "telescope",
        init_time=0.0,
        settle_time=1.0,
        seed=7,
        pointing_terms=TERMS,
        pointing_model=str(model),
        **QUIET,
    )
    await telescope.init()
    await observatory.start(
        SimCamera,
        "camera",
        focuser=None,
        filters=None,
        roof=None,
        weather=None,
        detector=DETECTOR,
        catalog_depth=DEPTH,
        seed=SEED,
        readout_time=0.5,
    )
    return telescope


def solver() -> Pipeline:
    indexes = SimulatedSkyIndexes(seed=SEED, depth=DEPTH)
    return Pipeline([SepSourceDetection(), indexes, CatalogAstrometry(index_dir=indexes.directory)])


async def pointing_miss(telescope: SimTelescope, ra: float, dec: float) -> float:
    """Arcsec between a target and where the telescope sent there really points (the sim's truth)."""
    await telescope.move_radec(ra, dec)
    true_ra, true_dec = await telescope.get_true_radec()
    return angular_separation(ra, dec, true_ra, true_dec) * 3600.0


async def test_series_fit_and_model_bring_the_pointing_error_to_arcseconds(
    observatory: Observatory, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    model = tmp_path / "pointing-model.yaml"
    telescope = await start_devices(observatory, model)  # no model file yet: uncorrected
    target = (200.0, 30.0)
    before = await pointing_miss(telescope, *target)
    assert before > 300.0

    series = await observatory.start(
        PointingSeries,
        "pointing",
        solver=solver(),
        pattern="sky",
        points=6,
        min_altitude=35.0,
        alt_range=(35.0, 75.0),
        exposure_time=1.0,
        filename="/cache/pointing-{time}.csv",
    )
    rows = await observatory.vfs.read_csv(await series.start_pointing_series())
    table = tmp_path / "series.csv"
    with table.open("w", newline="") as stream:
        writer = csv.DictWriter(stream, fieldnames=CSV_COLUMNS)
        writer.writeheader()
        writer.writerows(rows)

    # As the docs tell a user: fit the series, write the model the telescope's pointing_model names.
    assert (
        main(
            [
                "pointing",
                "fit",
                str(table),
                "--mount",
                "telescope",
                "--output",
                str(model),
                "--terms",
                "IH,ID,CH,MA,ME",
            ]
        )
        == 0
    )
    printed = capsys.readouterr().out
    assert "RMS before" in printed and "MA" in printed

    after = await pointing_miss(telescope, *target)  # the telescope read the new file
    assert after < 5.0, (before, after)
    # get_radec says where it really points, and the frames carry the mount's own position.
    header = {
        key: value
        for key, (value, _) in (await telescope.get_fits_header_before()).items()
        if isinstance(value, float)
    }
    true_ra, true_dec = await telescope.get_true_radec()
    assert angular_separation(header["RA"], header["DEC"], true_ra, true_dec) * 3600.0 < 5.0
    assert angular_separation(header["MNT-RA"], header["MNT-DEC"], *target) * 3600.0 > 300.0
    print(f'pointing model: miss before {before:.0f}", after {after:.1f}"')


async def test_the_passive_refit_learns_the_model_from_science_frames(
    observatory: Observatory, tmp_path: Path
) -> None:
    model = tmp_path / "pointing-model.yaml"
    telescope = await start_devices(observatory, model)
    await observatory.start(
        PassivePointingRefit,
        "refit",
        model=str(model),
        solver=solver(),
        rule={"terms": ["IH", "ID", "CH", "MA", "ME"], "min_pairs": 6, "every": 6},
    )
    camera = observatory.module("camera", SimCamera)
    for alt, az in sky_grid(6, 35.0, 75.0):  # routine science frames, each announced
        when = observatory.clock.time()
        await telescope.move_radec(*altaz_to_radec(alt, az, SITE.latitude, SITE.longitude, when))
        await camera.grab_data(True, ImageType.OBJECT)
    await observatory.wait_for(model.exists, 600.0, interval=1.0, message="no refit written")
    assert await pointing_miss(telescope, 200.0, 30.0) < 5.0


def write(path: Path, text: str) -> str:
    path.write_text(text)
    return str(path)


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("mount: other\nlatitude: 50\nterms: {IH: 10}\n", "is for mount 'other', not 'telescope'"),
        ("mount: telescope\nlatitude: 50\nterms: {IH: 10, ZZ: 3}\n", "unknown pointing term.*ZZ"),
    ],
)
def test_a_model_file_that_does_not_fit_is_one_clear_config_error(
    tmp_path: Path, text: str, message: str
) -> None:
    path = write(tmp_path / "model.yaml", text)
    with pytest.raises(ConfigError, match=message) as caught:
        SimTelescope(name="telescope", site=SITE, pointing_model=path)
    assert str(caught.value).startswith(path)


def test_unknown_injected_terms_are_a_config_error() -> None:
    with pytest.raises(ConfigError, match=r"key 'pointing_terms': unknown pointing term.*QQ"):
        SimTelescope(name="telescope", site=SITE, pointing_terms={"IH": 1.0, "QQ": 2.0})


def test_the_cli_names_a_csv_that_is_not_a_series(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    table = write(tmp_path / "other.csv", "a,b\n1,2\n")
    assert main(["pointing", "fit", table, "--mount", "telescope", "--output", str(tmp_path / "m.yaml")]) == 2
    assert "line 2: no column" in capsys.readouterr().err
    assert not (tmp_path / "m.yaml").exists()
