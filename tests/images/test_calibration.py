"""Calibration removes a synthetic bias, dark and flat pattern down to the noise.

Frames are made here from known patterns (a striped bias, a dark current with hot pixels, a
vignetting flat) plus Poisson and read noise, so the residual of a calibrated frame against the
true sky can be compared with the noise expected of it.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import numpy.typing as npt
import pytest

from nightcrew.images import Image, ImageDataError
from nightcrew.images.calibration import (
    Calibration,
    CalibrationCache,
    CalibrationError,
    MasterKind,
    build_master,
    calibrate_image,
    combine_frames,
    frame_key,
)
from nightcrew.vfs import LocalFile, VirtualFileSystem

SHAPE = (200, 240)
READ_NOISE = 5.0
RNG = np.random.default_rng(0)
_Y, _X = np.mgrid[: SHAPE[0], : SHAPE[1]]
BIAS = 1000.0 + 8.0 * np.sin(_X / 15.0) + 0.02 * _Y
DARK_RATE = 0.2 + (RNG.random(SHAPE) < 0.005) * 40.0  # e-/s, with hot pixels
FLAT = 1.0 - 0.25 * ((_X - 120.0) ** 2 + (_Y - 100.0) ** 2) / (120.0**2 + 100.0**2)


def raw(kind: str, exposure: float, sky: float = 0.0, *, filter_name: str = "R", seed: int) -> Image:
    """A raw frame (gain 1): bias + Poisson(sky * flat + dark * t) + read noise, with its header."""
    rng = np.random.default_rng(seed)
    electrons = rng.poisson(sky * FLAT + DARK_RATE * exposure) + rng.normal(0.0, READ_NOISE, SHAPE)
    header = {
        "IMAGETYP": kind,
        "EXPTIME": exposure,
        "XBINNING": 1,
        "YBINNING": 1,
        "FILTER": filter_name,
        "DATE-OBS": "2026-03-01T22:00:00",
    }
    return Image(np.clip(np.rint(BIAS + electrons), 0, 65535).astype(np.uint16), header=header)


@pytest.fixture(scope="module")
def masters() -> dict[MasterKind, Image]:
    bias = build_master(MasterKind.BIAS, [raw("bias", 0.0, seed=i) for i in range(12)])
    dark = build_master(MasterKind.DARK, [raw("dark", 120.0, seed=100 + i) for i in range(12)], bias=bias)
    flats = [raw("skyflat", 2.0, 20000.0 + 2000.0 * i, seed=200 + i) for i in range(9)]
    flat = build_master(MasterKind.FLAT, flats, bias=bias, dark=dark)
    return {MasterKind.BIAS: bias, MasterKind.DARK: dark, MasterKind.FLAT: flat}


def residual_in_sigma(calibrated: Image, sky: float, exposure: float) -> npt.NDArray[np.float64]:
    """(calibrated - truth) / expected noise per pixel; the truth is the sky at the flat's median level."""
    expected = sky * float(np.median(FLAT))  # the master flat is normalised to median 1
    noise = np.sqrt(sky * FLAT + DARK_RATE * exposure + READ_NOISE**2) / (FLAT / np.median(FLAT))
    return np.asarray((np.asarray(calibrated.data, np.float64) - expected) / noise, np.float64)


async def test_masters_remove_bias_dark_and_flat_to_the_noise(masters: dict[MasterKind, Image]) -> None:
    science = raw("object", 30.0, 400.0, seed=999)
    calibrated = calibrate_image(
        science, bias=masters[MasterKind.BIAS], dark=masters[MasterKind.DARK], flat=masters[MasterKind.FLAT]
    )
    z = residual_in_sigma(calibrated, 400.0, 30.0)
    assert abs(float(np.mean(z))) < 0.05  # no pattern left on average...
    assert 0.95 < float(np.std(z)) < 1.1  # ...and the scatter is the frame's own noise
    # the patterns themselves are gone: the residual does not follow the bias stripes or the flat
    assert abs(float(np.corrcoef(z.ravel(), BIAS.ravel())[0, 1])) < 0.03
    assert abs(float(np.corrcoef(z.ravel(), FLAT.ravel())[0, 1])) < 0.03
    hot = DARK_RATE > 1.0
    assert abs(float(np.mean(z[hot]))) < 0.3  # hot pixels scaled from 120 s darks to 30 s
    assert calibrated.header["CAL-DARK"].endswith("x12")


def test_master_headers_say_what_they_are(masters: dict[MasterKind, Image]) -> None:
    dark, flat = masters[MasterKind.DARK], masters[MasterKind.FLAT]
    assert dark.header["IMAGETYP"] == "master_dark" and dark.header["EXPTIME"] == 120.0
    assert flat.header["FILTER"] == "R" and flat.header["NCOMBINE"] == 9
    assert float(np.median(flat.data)) == pytest.approx(1.0, abs=1e-6)
    assert flat.uncertainty is not None and float(np.median(flat.uncertainty)) < 0.01


def test_combine_rejects_cosmic_rays() -> None:
    frames = [np.full((4, 4), 100.0) + i * 0.1 for i in range(7)]
    frames[3][1, 2] = 60000.0
    combined, error = combine_frames(frames)
    assert combined[1, 2] == pytest.approx(100.3, abs=0.06)
    assert combined.dtype == np.float32 and error.shape == (4, 4)


def test_combine_refuses_mixed_shapes() -> None:
    with pytest.raises(ImageDataError, match="one shape"):
        combine_frames([np.zeros((4, 4)), np.zeros((4, 5))])


def test_cache_is_bounded_and_least_recently_used() -> None:
    cache: CalibrationCache[str] = CalibrationCache(max_entries=2)
    cache.put("a", "A")
    cache.put("b", "B")
    assert cache.get("a") == "A"
    cache.put("c", "C")
    assert cache.get("b") is None and cache.get("a") == "A" and len(cache) == 2


def test_frame_key_assigns_after_midnight_frames_to_the_evening() -> None:
    key = frame_key(Image(np.zeros((2, 2)), header={"DATE-OBS": "2026-03-02T03:00:00", "XBINNING": 2}).header)
    assert str(key.night) == "2026-03-01" and key.binning == "2x2" and key.filter is None


async def test_processor_picks_masters_from_a_directory(
    masters: dict[MasterKind, Image], tmp_path: Path
) -> None:
    vfs = VirtualFileSystem({"cal": LocalFile(str(tmp_path))})
    for kind, master in masters.items():
        await master.to_vfs(vfs, f"/cal/masters/{kind.value}.fits")
    await vfs.write_bytes("/cal/masters/notes.fits", b"not a FITS file")
    processor = Calibration(masters="/cal/masters", require_flat=True, vfs=vfs)
    calibrated = await processor(raw("object", 30.0, 400.0, seed=7))
    assert abs(float(np.mean(residual_in_sigma(calibrated, 400.0, 30.0)))) < 0.05
    with pytest.raises(CalibrationError, match=r"no master flat .* filter V"):
        await processor(raw("object", 30.0, 400.0, filter_name="V", seed=8))
