"""``nightcrew sim --quick``: the one night engine runs a short task list; its frames are complete and solve.

The scheduler and the mastermind run it as any night (the focus is a real focus series); the
whole robotic night (the default) is tested in ``test_sim_night.py``.
"""

from __future__ import annotations

import shutil
from datetime import UTC, date, datetime, timedelta
from pathlib import Path

import pytest
from astropy.io import fits  # type: ignore[import-untyped]

from nightcrew.astro import moon_illumination, sun_altitude
from nightcrew.cli.main import main
from nightcrew.night.fields import FAMOUS_FIELDS, choose_targets, night_start, quick_groups
from nightcrew.site import Site

from ..sim.solving import offset_arcsec, solve_field

SITE = Site(latitude=51.56, longitude=9.94, elevation=201.0)
HEADER_KEYS = (
    "DATE-OBS",
    "EXPTIME",
    "IMAGETYP",
    "FILTER",
    "RA",
    "DEC",
    "OBJCTRA",
    "AIRMASS",
    "FOCUS",
    "GAIN",
    "PIXSCALE",
    "SITELAT",
    "SIM-RA",
    "SIM-DEC",
)


@pytest.fixture(scope="module")
def night(tmp_path_factory: pytest.TempPathFactory) -> tuple[int, Path]:
    """One short night for all tests here: 2 biases, 2 darks, then two fields in V and R, 30 s each."""
    out = tmp_path_factory.mktemp("night")
    code = main(
        [
            "sim",
            "--quick",
            "--out",
            str(out),
            "--targets",
            "2",
            "--filters",
            "V,R",
            "--calibration-frames",
            "2",
        ]
    )
    return code, out


def test_the_night_exits_cleanly_and_writes_one_file_per_exposure(night: tuple[int, Path]) -> None:
    code, out = night
    assert code == 0
    files = sorted((out / "frames").glob("*-object-*.fits"))
    assert len(files) == 4
    filters = []
    for path in files:
        header = fits.getheader(path)
        missing = [key for key in HEADER_KEYS if key not in header]
        assert not missing, f"{path.name} lacks {missing}"
        assert header["EXPTIME"] == 30.0 and header["IMAGETYP"] == "object"
        # After dusk (17:50 UTC) on the default night, within the short run.
        assert "2026-11-10T17:50" <= header["DATE-OBS"] < "2026-11-10T19:00"
        filters.append(header["FILTER"])
    assert sorted(filters) == ["R", "R", "V", "V"]


def test_calibration_frames_come_first_with_the_roof_closed(night: tuple[int, Path]) -> None:
    _, out = night
    headers = [fits.getheader(path) for path in sorted((out / "frames").glob("*.fits"))]
    kinds = [(h["IMAGETYP"], h["EXPTIME"]) for h in sorted(headers, key=lambda h: h["DATE-OBS"])]
    assert kinds[:4] == [("bias", 0.0), ("bias", 0.0), ("dark", 30.0), ("dark", 30.0)]
    # Then the mastermind's own focus series, then the fields.
    assert {kind for kind, _ in kinds[4:]} == {"focus", "object"}


def test_the_camera_is_cooled_before_the_first_frame_and_every_frame_says_so(night: tuple[int, Path]) -> None:
    # The night starts after dusk with a warm camera (robotic/cooling.yaml: -10 °C, 3 °C/min): the
    # biases wait for the cooler, so no frame is off its set point (docs/observatory.md, Cooling).
    _, out = night
    headers = [fits.getheader(path) for path in sorted((out / "frames").glob("*.fits"))]
    assert headers
    for header in headers:
        assert header["SET-TEMP"] == -10.0 and 0.0 < header["COOLPOW"] < 100.0
        assert abs(header["CCD-TEMP"] + 10.0) <= 0.5 and header["TEMP-OK"] is True


def test_the_night_can_be_reduced(
    night: tuple[int, Path], tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    _, out = night
    assert main(["reduce", str(out / "frames"), str(tmp_path)]) == 0
    summary = capsys.readouterr().out
    assert "4 reduced (4 plate-solved)" in summary and "0 failed" in summary
    assert "no master flat" in summary  # the simulated night takes no flats yet: said, not fatal
    reduced = sorted(tmp_path.glob("*_red.fits"))
    assert len(reduced) == 4
    header = fits.getheader(reduced[0])
    assert "CAL-BIAS" in header and "CAL-DARK" in header


def test_progress_and_summary(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    code = main(
        [
            "sim",
            "--quick",
            "--out",
            str(tmp_path),
            "--targets",
            "1",
            "--filters",
            "V",
            "--calibration-frames",
            "1",
        ]
    )
    out, err = capsys.readouterr()
    assert code == 0
    assert "17:49 UTC" in err and "Sun -20.4°" in err
    assert "night complete:" in out and "2 tasks started, weather clear" in out
    assert "17:49-18:49 UTC on virtual time" in out
    # The summary counts the files the night wrote, the focus frames (not announced) among them.
    written = [str(fits.getheader(path)["IMAGETYP"]) for path in (tmp_path / "frames").glob("*.fits")]
    science = sum(1 for t in written if t in ("object", "bias", "dark", "skyflat"))
    focus = sum(1 for t in written if t in ("focus", "acquisition"))
    assert science == 3 and focus >= 4 and science + focus == len(written)  # 1 object, 1 bias, 1 dark
    assert (
        f"night complete: {len(written)} frames ({science} science and calibration, "
        f"{focus} focus and acquisition), 2 tasks started" in out
    )
    assert len(list((tmp_path / "frames").glob("*-object-V.fits"))) == 1
    assert (tmp_path / "report.html").is_file()


@pytest.mark.parametrize(
    ("argument", "message"),
    [
        (["--date", "2026-13-01"], "not a date"),
        (["--speed", "0"], "must be > 0"),
        (["--targets", "0"], "must be >= 1"),
        (["--weather", "hail"], "invalid choice: 'hail'"),
        (["--hours", "-1"], "must be > 0"),
        (["--start", "25:00"], "not a time (HH:MM)"),
    ],
)
def test_bad_arguments_are_one_clear_error(
    argument: list[str], message: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    with pytest.raises(SystemExit) as exit_info:
        main(["sim", "--out", str(tmp_path), *argument])
    assert exit_info.value.code == 2
    assert message in capsys.readouterr().err


def test_an_unknown_filter_is_refused_before_the_night(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    code = main(["sim", "--quick", "--out", str(tmp_path), "--targets", "1", "--filters", "Halpha"])
    _, err = capsys.readouterr()
    assert code == 2
    assert "--filters: unknown filter 'Halpha'; known filters: B, V, R, I, clear" in err
    assert not (tmp_path / "events.jsonl").exists()


@pytest.mark.solver
def test_a_frame_solves_to_the_true_pointing(night: tuple[int, Path], tmp_path: Path) -> None:
    _, out = night
    image = tmp_path / "frame.fits"
    shutil.copy(sorted((out / "frames").glob("*-V.fits"))[0], image)
    header = fits.getheader(image)
    wcs = solve_field(
        image, scale_arcsec=header["PIXSCALE"], workdir=tmp_path, hint=(header["RA"], header["DEC"])
    )
    # The mount missed its target by about an arcminute; the solution finds where it really points.
    assert offset_arcsec(wcs, (header["NAXIS2"], header["NAXIS1"]), header["SIM-RA"], header["SIM-DEC"]) < 5.0


def test_the_default_night_is_dark_and_its_fields_are_high() -> None:
    start = night_start(date(2026, 11, 10), SITE)
    t = start.timestamp()
    assert sun_altitude(SITE.latitude, SITE.longitude, t) < -18.0
    assert moon_illumination(t) < 0.05
    targets = choose_targets(SITE, t, 3)
    assert [target.name for target in targets] == ["M52", "M39", "Sadr"]  # ordered by azimuth
    end = start + timedelta(hours=1)
    groups = quick_groups(targets, ["V", "R"], 30.0, start=start, end=end, calibration_frames=3)
    assert [g.name for g in groups] == ["Quick bias and darks", "Quick M52", "Quick M39", "Quick Sadr"]
    calibration = groups[0].requests[0].configurations
    assert [(c.type, c.instrument_configs[0].exposure_count) for c in calibration] == [
        ("BIAS", 3),
        ("DARK", 3),
    ]
    fields = [c for g in groups[1:] for c in g.requests[0].configurations]
    assert sum(len(c.instrument_configs) for c in fields) == 6


def test_without_astronomical_night_the_start_is_solar_midnight() -> None:
    start = night_start(date(2026, 6, 21), SITE)
    assert start.astimezone(UTC).hour == 23  # 9.94° east: solar midnight at 23:20 UTC
    assert len(choose_targets(SITE, start.timestamp(), 20)) < len(FAMOUS_FIELDS)
    assert start > datetime(2026, 6, 21, 12, tzinfo=UTC)
