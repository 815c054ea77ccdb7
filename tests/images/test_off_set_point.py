"""Frames taken off their cooling set point go into no master."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from astropy.io import fits  # type: ignore[import-untyped]

from nightcrew.images.calibration import off_set_point
from nightcrew.images.reduce import GroupKey, ReduceOptions, group_frames, read_entry, reduce_night


def write(path: Path, **cards: object) -> Path:
    header = fits.Header({"IMAGETYP": "flat", "FILTER": "R", "EXPTIME": 2.0, "XBINNING": 1, "YBINNING": 1})
    header.update(cards)
    fits.writeto(path, np.full((8, 8), 20000, np.uint16), header=header)
    return path


def test_the_margin_decides_and_an_uncooled_frame_is_never_off() -> None:
    assert not off_set_point({"CCD-TEMP": -9.6, "SET-TEMP": -10.0})
    assert off_set_point({"CCD-TEMP": -9.4, "SET-TEMP": -10.0})
    assert not off_set_point({"CCD-TEMP": -9.4, "SET-TEMP": -10.0}, margin=1.0)
    assert off_set_point({"CCD-TEMP": -10.0, "SET-TEMP": -10.0, "TEMP-OK": False})  # the camera's word
    assert not off_set_point({"CCD-TEMP": 12.0})


def test_flats_off_the_set_point_are_left_out_of_the_master(tmp_path: Path) -> None:
    good = [write(tmp_path / f"flat-{i}.fits", **{"CCD-TEMP": -10.1, "SET-TEMP": -10.0}) for i in range(2)]
    warm = write(tmp_path / "flat-warm.fits", **{"CCD-TEMP": -4.0, "SET-TEMP": -10.0, "TEMP-OK": False})
    entries = [read_entry(p) for p in [*good, warm]]
    assert [e.off_set_point for e in entries] == [False, False, True]
    groups = group_frames(entries)
    assert [e.path for e in groups[GroupKey("flat", "1x1", filter="R")]] == good


async def test_reduce_leaves_an_off_set_point_bias_out_and_says_so(tmp_path: Path) -> None:
    raw, out = tmp_path / "raw", tmp_path / "out"
    raw.mkdir()
    cold = {"IMAGETYP": "bias", "EXPTIME": 0.0, "CCD-TEMP": -10.0, "SET-TEMP": -10.0}
    for i in range(2):
        write(raw / f"bias-{i}.fits", **cold)
    write(raw / "bias-warm.fits", **{**cold, "CCD-TEMP": -8.0})
    rows = {row.file: row for row in await reduce_night(raw, out, options=ReduceOptions(workers=1))}
    assert rows["bias-warm.fits"].status == "ignored"
    assert "off its cooling set point" in rows["bias-warm.fits"].message
    assert {rows[f"bias-{i}.fits"].status for i in range(2)} == {"calibration"}
    assert fits.getheader(out / "masters" / "master_bias_1x1.fits")["NCOMBINE"] == 2
