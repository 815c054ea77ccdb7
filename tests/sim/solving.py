"""Plate solving a FITS file with astrometry.net's solve-field, for tests (see test_solve_field)."""

from __future__ import annotations

import subprocess
from pathlib import Path

import numpy as np
from astropy.io import fits  # type: ignore[import-untyped]
from astropy.wcs import WCS  # type: ignore[import-untyped]

from .test_solve_field import solve_field_executable

__all__ = ["offset_arcsec", "solve_field", "solve_field_executable"]


def solve_field(
    image: Path,
    *,
    scale_arcsec: float,
    workdir: Path,
    hint: tuple[float, float] | None = None,
    hint_radius_deg: float = 2.0,
) -> WCS:
    """The WCS solve-field finds for ``image`` (pixel scale known to 10 %, optional RA/Dec hint).

    Skips the test when solve-field is missing (fails on CI); asserts that a solution was found.
    """
    command = [
        solve_field_executable(),
        "--overwrite",
        "--no-plots",
        "--scale-units",
        "arcsecperpix",
        "--scale-low",
        f"{0.9 * scale_arcsec}",
        "--scale-high",
        f"{1.1 * scale_arcsec}",
        "--cpulimit",
        "60",
        "--dir",
        str(workdir),
    ]
    if hint is not None:
        command += ["--ra", f"{hint[0]}", "--dec", f"{hint[1]}", "--radius", f"{hint_radius_deg}"]
    result = subprocess.run(
        [*command, str(image)],
        capture_output=True,
        text=True,
        timeout=240,
        stdin=subprocess.DEVNULL,
        check=False,
    )
    solution = workdir / f"{image.stem}.wcs"
    assert solution.exists(), f"not solved:\n{result.stdout[-2000:]}\n{result.stderr[-2000:]}"
    header = fits.getheader(solution)
    # The .wcs file describes the image's two axes but has no data of its own (NAXIS = 0).
    header["NAXIS"] = 2
    return WCS(header)


def offset_arcsec(wcs: WCS, shape: tuple[int, int], ra: float, dec: float) -> float:
    """Distance from (ra, dec) to the sky position ``wcs`` gives the centre of an image of ``shape``."""
    rows, cols = shape
    centre_ra, centre_dec = wcs.all_pix2world([(cols - 1) / 2.0], [(rows - 1) / 2.0], 0)
    d_ra = ((float(centre_ra[0]) - ra + 180.0) % 360.0 - 180.0) * np.cos(np.radians(dec))
    return 3600.0 * float(np.hypot(d_ra, float(centre_dec[0]) - dec))
