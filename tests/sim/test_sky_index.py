"""The `make sim` night's science frames solve with astrometry.net's own tools and the sky's index files.

Index files of the simulated sky (:mod:`nightcrew.sim.sky_index`, built once per session by the
``night_index_dir`` fixture) are all the solvers get: ``solve-field`` and ``nightcrew solver`` solve
one 20' frame of each of the night's fields (:mod:`tests.sim.night_fields`) with a position hint
(the header's pointing, up to 3' off) and a scale hint. At least 95 % must solve within 5" of
the true pointing (read from the simulator: this is a test). Skipped without astrometry.net,
except under ``CI=true``.
"""

from __future__ import annotations

import math
import os
import shutil
import statistics
import subprocess
import sys
import time
from collections.abc import Awaitable, Callable
from pathlib import Path

import pytest
from astropy.io import fits  # type: ignore[import-untyped]
from astropy.wcs import WCS  # type: ignore[import-untyped]

from nightcrew.images.astrometry import AstrometryError, RemoteSolver, SolveField, SolveHints
from nightcrew.testing.solver import RenderedField, rendered_field, running_solver, sky_distance_arcsec
from tests.sim.night_fields import NIGHT_CHIP_PX, NIGHT_SKY, NightField, night_fields

pytestmark = [pytest.mark.solver, pytest.mark.timeout(900)]

REQUIRED_FRACTION = 0.95
MAX_ERROR_ARCSEC = 5.0


def require_astrometry_net() -> None:
    if shutil.which("solve-field") is None or shutil.which("build-astrometry-index") is None:
        if os.environ.get("CI") == "true":
            pytest.fail("astrometry.net is missing on CI: apt-get install astrometry.net")
        pytest.skip("astrometry.net is not installed")


@pytest.fixture(scope="module")
def frames() -> list[tuple[NightField, RenderedField]]:
    rendered = []
    for index, field in enumerate(night_fields()):
        frame = rendered_field(
            field.ra_deg,
            field.dec_deg,
            seed=index,
            exposure_s=60.0,
            chip_px=NIGHT_CHIP_PX,
            catalog=NIGHT_SKY(),
            seeing_arcsec=1.5,
        )
        rendered.append((field, frame))
    return rendered


def hints(field: NightField, frame: RenderedField) -> SolveHints:
    return SolveHints(
        ra_deg=field.header_ra_deg,
        dec_deg=field.header_dec_deg,
        radius_deg=1.0,
        pixel_scale_arcsec=frame.pixel_scale_arcsec,
        scale_tolerance=0.1,
    )


def centre_error_arcsec(cards: fits.Header, frame: RenderedField) -> float:
    rows, cols = frame.shape
    ra, dec = WCS(cards).all_pix2world([(cols - 1) / 2.0], [(rows - 1) / 2.0], 0)
    return sky_distance_arcsec(float(ra[0]), float(dec[0]), frame.true_ra_deg, frame.true_dec_deg)


Solve = Callable[[RenderedField, SolveHints], Awaitable[fits.Header]]


async def solve_all(solver: str, solve: Solve, frames: list[tuple[NightField, RenderedField]]) -> int:
    """Solve every frame, print the figures; the number of frames solved within the limit."""
    errors, seconds = [], []
    for field, frame in frames:
        started = time.perf_counter()
        try:
            errors.append(centre_error_arcsec(await solve(frame, hints(field, frame)), frame))
        except AstrometryError as exc:
            print(f"{solver}: {field.name} not solved: {str(exc)[:200]}", file=sys.stderr)
            errors.append(math.inf)
        seconds.append(time.perf_counter() - started)
    good = sum(error <= MAX_ERROR_ARCSEC for error in errors)
    worst = max((e for e in errors if math.isfinite(e)), default=math.inf)
    print(
        f'{solver}: {good}/{len(errors)} within {MAX_ERROR_ARCSEC:g}" (worst {worst:.2f}"), '
        f"median {statistics.median(seconds):.3f} s, slowest {max(seconds):.3f} s",
        file=sys.stderr,
    )
    return good


async def test_solve_field_solves_the_nights_frames(
    night_index_dir: Path, frames: list[tuple[NightField, RenderedField]]
) -> None:
    require_astrometry_net()
    solver = SolveField(index_dir=str(night_index_dir), cpu_limit_s=30.0, timeout_s=120.0)

    async def solve(frame: RenderedField, hints: SolveHints) -> fits.Header:
        return await solver.solve_stars(frame.x, frame.y, frame.flux, shape=frame.shape, hints=hints)

    good = await solve_all("solve-field", solve, frames)
    assert len(frames) >= 10
    assert good >= math.ceil(REQUIRED_FRACTION * len(frames))


async def test_nightcrew_solver_solves_the_nights_frames(
    night_index_dir: Path, frames: list[tuple[NightField, RenderedField]]
) -> None:
    require_astrometry_net()
    with running_solver(index_dir=night_index_dir) as url:
        client = RemoteSolver(url)

        async def solve(frame: RenderedField, hints: SolveHints) -> fits.Header:
            return await client.solve_stars(frame.x, frame.y, frame.flux, shape=frame.shape, hints=hints)

        good = await solve_all("nightcrew solver", solve, frames)
    assert good >= math.ceil(REQUIRED_FRACTION * len(frames))


DOCS = Path(__file__).parents[2] / "docs" / "pipeline.md"


def documented_solve_field_commands(index_dir: Path) -> list[str]:
    """The two lines of docs/pipeline.md that solve a frame of the night with solve-field."""
    lines = [
        line
        for line in DOCS.read_text().splitlines()
        if line.startswith(("printf 'add_path", "solve-field --config sky.cfg"))
    ]
    assert len(lines) == 2, lines
    # The docs name the default cache; the fixture's directory is that unless NIGHTCREW_CACHE_DIR moves it.
    return [line.replace("~/.cache/nightcrew/indexes/seed42-G16", str(index_dir)) for line in lines]


def test_the_documented_solve_field_command_solves_frames_of_the_night(
    night_index_dir: Path, frames: list[tuple[NightField, RenderedField]], tmp_path: Path
) -> None:
    require_astrometry_net()
    commands = documented_solve_field_commands(night_index_dir)
    for index, (field, frame) in enumerate(frames[::4]):  # five fields, as FITS files of pixels
        workdir = tmp_path / f"frame{index}"
        workdir.mkdir()
        fits.writeto(workdir / "FRAME.fits", frame.data)
        script = "\n".join([*commands[:1], commands[1] + " --overwrite --no-plots --cpulimit 60"])
        result = subprocess.run(
            ["bash", "-ec", script], cwd=workdir, capture_output=True, text=True, timeout=300, check=False
        )
        solution = workdir / "FRAME.wcs"
        assert solution.is_file(), f"{field.name} not solved:\n{result.stdout[-1500:]}{result.stderr[-500:]}"
        header = fits.getheader(solution)
        header["NAXIS"], header["NAXIS1"], header["NAXIS2"] = 2, frame.shape[1], frame.shape[0]
        assert centre_error_arcsec(header, frame) <= MAX_ERROR_ARCSEC
