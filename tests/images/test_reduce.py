"""``nightcrew reduce`` end to end on a directory of rendered frames (1k x 1k to stay fast).

The night: 3 biases, 3 darks (20 s), 3 twilight flats (R), 2 science frames (R, 20 s) whose
header RA/DEC is 5' off the true pointing, and one broken file. The reduced science frames must be
plate-solved to within 1" of the renderer's true WCS; a second run must redo nothing.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from astropy.io import fits  # type: ignore[import-untyped]
from astropy.table import Table  # type: ignore[import-untyped]
from astropy.wcs import WCS  # type: ignore[import-untyped]

from nightcrew.cli.main import main
from nightcrew.images import Image
from nightcrew.images.reduce import GroupKey, group_frames, read_entry
from nightcrew.sim.catalog import STAR_DTYPE, StarCatalog
from nightcrew.sim.projection import Pointing, wcs_header
from nightcrew.sim.render import (
    CameraModel,
    Conditions,
    Exposure,
    Optics,
    field_radius_deg,
    frame_geometry,
    render_frame,
)
from nightcrew.testing.solver import simulated_sky_indexes

CAMERA = CameraModel(chip_width=1024, chip_height=1024)
OPTICS = Optics()
POINTINGS = [Pointing(80.0, 25.0, 0.0), Pointing(80.4, 25.2, 0.0)]
SCALE = OPTICS.pixel_scale_arcsec(CAMERA.pixel_size_um)


def write_frame(
    path: Path, kind: str, exposure: float, *, seed: int, pointing: Pointing | None = None
) -> None:
    conditions = Conditions(seeing_arcsec=2.0)
    stars = np.zeros(0, STAR_DTYPE)
    header: dict[str, object] = {"IMAGETYP": kind, "EXPTIME": exposure, "XBINNING": 1, "YBINNING": 1}
    header["DATE-OBS"] = f"2026-02-10T{20 + seed % 4:02d}:{seed % 60:02d}:00"
    if kind == "skyflat":
        conditions = Conditions(sun_altitude_deg=-3.0 - 0.2 * seed % 3)  # bright twilight sky, no stars
        header["FILTER"] = "R"
    if pointing is not None:
        geometry = frame_geometry(CAMERA, OPTICS, Exposure(exposure))
        stars = StarCatalog().query(
            pointing.ra_deg, pointing.dec_deg, field_radius_deg(geometry), epoch=2026.1
        )
        header["FILTER"] = "R"
        header["RA"] = pointing.ra_deg + 5.0 / 60.0 / math.cos(math.radians(pointing.dec_deg))
        header["DEC"] = pointing.dec_deg
    frame = render_frame(
        stars,
        pointing=pointing or POINTINGS[0],
        focus=0.0,
        camera=CAMERA,
        optics=OPTICS,
        conditions=conditions,
        exposure=Exposure(exposure, shutter_open=kind not in ("bias", "dark")),
        rng=np.random.default_rng(seed),
    )
    fits.writeto(path, frame.data, header=fits.Header(header.items()))


@pytest.fixture(scope="module")
def raw_night(tmp_path_factory: pytest.TempPathFactory) -> Path:
    raw = tmp_path_factory.mktemp("raw")
    for i in range(3):
        write_frame(raw / f"bias-{i}.fits", "bias", 0.0, seed=i)
        write_frame(raw / f"dark-{i}.fits", "dark", 20.0, seed=10 + i)
        write_frame(raw / f"flat-{i}.fits", "skyflat", 1.0, seed=20 + i)
    for i, pointing in enumerate(POINTINGS):
        write_frame(raw / f"science-{i}.fits", "object", 20.0, seed=30 + i, pointing=pointing)
    (raw / "broken.fits").write_bytes(b"SIMPLE  =                    T" + b"\0" * 100)
    (raw / "notes.txt").write_text("not a frame")
    return raw


def test_frames_group_by_role_binning_filter_and_exposure(raw_night: Path) -> None:
    groups = group_frames(read_entry(p) for p in sorted(raw_night.glob("*.fits")))
    assert list(groups) == [
        GroupKey("bias", "1x1"),
        GroupKey("dark", "1x1", exposure_s=20.0),
        GroupKey("flat", "1x1", filter="R"),
    ]
    assert GroupKey("dark", "1x1", exposure_s=20.0).file_name == "master_dark_1x1_20s.fits"


def test_reduce_a_night_then_rerun_without_redoing_work(
    raw_night: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "reduced"
    width = CAMERA.chip_width * SCALE / 60.0
    index_dir = str(simulated_sky_indexes([(p.ra_deg, p.dec_deg) for p in POINTINGS], width_arcmin=width))
    options = ["--index-dir", index_dir, "--no-solve-field"]
    assert main(["reduce", str(raw_night), str(out), "--pixel-scale", str(SCALE), *options]) == 0
    stdout, stderr = capsys.readouterr()
    assert "12 files: 2 reduced (2 plate-solved), 9 calibration, 0 failed, 1 broken" in stdout
    assert "broken.fits: broken: not a readable FITS file" in stdout
    assert "5/5 science-" in stderr  # the progress bar: 3 masters, 2 science frames (done in any order)

    summary = Table.read(out / "summary.ecsv")
    science = summary[summary["status"] == "reduced"]
    assert list(science["solver"]) == ["catalog", "catalog"]
    assert all(science["rms_arcsec"] < 0.5) and all(science["stars"] > 30)
    for row, pointing in zip(science, POINTINGS, strict=True):
        image = Image.from_bytes((out / row["output"]).read_bytes())
        assert image.catalog is not None and {"x", "y", "flux", "ra", "dec"} <= set(image.catalog.colnames)
        assert _max_error_arcsec(image, pointing) < 1.0
        assert image.header["CAL-FLAT"] and image.header["BUNIT"] == "adu"
    assert sorted(p.name for p in (out / "masters").iterdir()) == [
        "master_bias_1x1.fits",
        "master_dark_1x1_20s.fits",
        "master_flat_1x1_R.fits",
    ]

    written = {p: p.stat().st_mtime_ns for p in out.rglob("*.fits")}
    assert main(["reduce", str(raw_night), str(out), "--quiet", *options]) == 0
    assert {p: p.stat().st_mtime_ns for p in out.rglob("*.fits")} == written  # nothing redone
    again = Table.read(out / "summary.ecsv")
    assert list(again["status"]) == list(summary["status"])
    assert np.array_equal(again["rms_arcsec"], summary["rms_arcsec"], equal_nan=True)
    assert list(again["message"]) == list(summary["message"])


def _max_error_arcsec(image: Image, pointing: Pointing) -> float:
    geometry = frame_geometry(CAMERA, OPTICS, Exposure(20.0))
    true, solved = WCS(wcs_header(pointing, geometry)), image.wcs
    assert solved is not None
    gx, gy = np.meshgrid(np.linspace(0, 1023, 5), np.linspace(0, 1023, 5))
    t = np.array(true.all_pix2world(gx.ravel(), gy.ravel(), 0))
    s = np.array(solved.all_pix2world(gx.ravel(), gy.ravel(), 0))
    d_ra = (s[0] - t[0]) * math.cos(math.radians(pointing.dec_deg))
    return float(np.max(3600.0 * np.hypot(d_ra, s[1] - t[1])))


def test_a_sim_output_directory_is_read_from_its_frames_and_an_empty_one_is_an_error(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    from nightcrew.errors import ConfigError
    from nightcrew.images.reduce import find_raw_frames

    (tmp_path / "sim-output" / "frames").mkdir(parents=True)
    (tmp_path / "sim-output" / "report.html").write_text("<html></html>")
    with pytest.raises(
        ConfigError, match=r"no raw frames \(.fits, .*\) in .*sim-output or .*sim-output/frames$"
    ):
        find_raw_frames(tmp_path / "sim-output")
    assert main(["reduce", str(tmp_path / "sim-output"), str(tmp_path / "out")]) != 0
    assert "no raw frames" in capsys.readouterr().err and not (tmp_path / "out").exists()
    frame = tmp_path / "sim-output" / "frames" / "a-object-V.fits"
    fits.PrimaryHDU(np.zeros((4, 4), np.uint16)).writeto(frame)
    assert find_raw_frames(tmp_path / "sim-output") == [frame]
