"""astrometry.net's ``solve-field`` as an async subprocess, on a star list or on pixels.

:class:`SolveField` writes its input into a fresh temporary directory, runs ``solve-field`` there
with the hints it is given (position, pixel scale) and a hard timeout, and reads the WCS back as a
FITS header. A star list ("xylist": a FITS table of x, y, flux) is much faster than pixels, since
solve-field does not need to find the stars itself.

Pixel positions passed in are 0-based; xylists are written 1-based (the FITS convention that
solve-field assumes), and the returned header is in FITS convention like any WCS header.
"""

from __future__ import annotations

import asyncio
import contextlib
import logging
import os
import shutil
import signal
import tempfile
import warnings
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import numpy.typing as npt
from astropy.io import fits  # type: ignore[import-untyped]
from astropy.table import Table  # type: ignore[import-untyped]
from astropy.wcs import WCS, FITSFixedWarning  # type: ignore[import-untyped]

from nightcrew.images.astrometry._errors import AstrometryError, NoSolutionError, SolverUnavailableError

__all__ = ["SolveField", "SolveHints"]

log = logging.getLogger(__name__)

_TAIL = 1500  # characters of solve-field's output quoted in an error


@dataclass(frozen=True)
class SolveHints:
    """What is known before solving; each hint narrows the search (and speeds it up a lot).

    Attributes:
        ra_deg, dec_deg: Approximate field centre (ICRS degrees), or None for a blind search.
        radius_deg: How far the true centre may be from (``ra_deg``, ``dec_deg``).
        pixel_scale_arcsec: Approximate pixel scale, or None for any scale.
        scale_tolerance: Relative uncertainty of the pixel scale.
    """

    ra_deg: float | None = None
    dec_deg: float | None = None
    radius_deg: float = 1.0
    pixel_scale_arcsec: float | None = None
    scale_tolerance: float = 0.1

    def __post_init__(self) -> None:
        if (self.ra_deg is None) != (self.dec_deg is None):
            raise ValueError("give both ra_deg and dec_deg, or neither")
        if self.radius_deg <= 0:
            raise ValueError(f"radius_deg must be positive, got {self.radius_deg}")
        if self.pixel_scale_arcsec is not None and self.pixel_scale_arcsec <= 0:
            raise ValueError(f"pixel_scale_arcsec must be positive, got {self.pixel_scale_arcsec}")
        if not 0.0 < self.scale_tolerance < 1.0:
            raise ValueError(f"scale_tolerance must be within (0, 1), got {self.scale_tolerance}")

    def arguments(self) -> list[str]:
        """solve-field command-line arguments for these hints."""
        args: list[str] = []
        if self.ra_deg is not None and self.dec_deg is not None:
            args += [
                "--ra",
                f"{self.ra_deg:.6f}",
                "--dec",
                f"{self.dec_deg:.6f}",
                "--radius",
                f"{self.radius_deg:g}",
            ]
        if self.pixel_scale_arcsec is not None:
            low = self.pixel_scale_arcsec * (1.0 - self.scale_tolerance)
            high = self.pixel_scale_arcsec * (1.0 + self.scale_tolerance)
            args += [
                "--scale-units",
                "arcsecperpix",
                "--scale-low",
                f"{low:.6g}",
                "--scale-high",
                f"{high:.6g}",
            ]
        return args


class SolveField:
    """Runs astrometry.net's ``solve-field`` (see the module docstring).

    Args:
        executable: Name or path of ``solve-field``; looked up on ``PATH`` when the solve starts.
        timeout_s: Wall-clock limit of one solve; the process group is killed after it.
        cpu_limit_s: solve-field's own ``--cpulimit`` (it gives up cleanly after this).
        max_stars: Brightest stars handed to the solver (``--objs``).
        tweak_order: Order of the SIP distortion fit; 0 for a pure TAN solution.
        downsample: Downsampling before solve-field's own star finding (pixel input only).
        config: An ``astrometry.cfg`` (index paths) instead of the system one.
        index_dir: A directory of index files (``index-*.fits``) to solve with instead of the system
            config's (a config naming only this directory is written for each solve); not with
            ``config``.
    """

    def __init__(
        self,
        *,
        executable: str = "solve-field",
        timeout_s: float = 120.0,
        cpu_limit_s: float = 60.0,
        max_stars: int = 200,
        tweak_order: int = 2,
        downsample: int = 2,
        config: str | None = None,
        index_dir: str | None = None,
    ) -> None:
        if timeout_s <= 0 or cpu_limit_s <= 0:
            raise ValueError(
                f"timeouts must be positive, got timeout_s={timeout_s}, cpu_limit_s={cpu_limit_s}"
            )
        if max_stars < 10:
            raise ValueError(f"max_stars must be >= 10, got {max_stars}")
        if tweak_order < 0:
            raise ValueError(f"tweak_order must be >= 0, got {tweak_order}")
        if config is not None and index_dir is not None:
            raise ValueError(
                "config and index_dir exclude each other: name the index directory in the config"
            )
        if downsample < 1:
            raise ValueError(f"downsample must be >= 1, got {downsample}")
        self.executable = executable
        self.timeout_s = timeout_s
        self.cpu_limit_s = cpu_limit_s
        self.max_stars = max_stars
        self.tweak_order = tweak_order
        self.downsample = downsample
        self.config = config
        self.index_dir = None if index_dir is None else str(Path(index_dir).expanduser())

    def find_executable(self) -> str:
        """The full path of solve-field.

        Raises:
            SolverUnavailableError: it is not installed.
        """
        path = shutil.which(self.executable)
        if path is None:
            raise SolverUnavailableError(
                f"{self.executable} not found: install astrometry.net and an index "
                "(Debian: apt-get install astrometry.net astrometry-data-tycho2)"
            )
        return path

    async def solve_stars(
        self,
        x: npt.ArrayLike,
        y: npt.ArrayLike,
        flux: npt.ArrayLike,
        *,
        shape: tuple[int, int],
        hints: SolveHints,
    ) -> fits.Header:
        """Solve a star list (0-based ``x``, ``y`` and ``flux``) of a ``shape`` (rows, cols) frame.

        Returns the WCS as FITS header cards. Raises :class:`NoSolutionError` when there is none,
        :class:`SolverUnavailableError` when solve-field is missing, :class:`AstrometryError` when it
        fails or times out.
        """
        table = Table(
            {
                "X": np.asarray(x, dtype=np.float64) + 1.0,
                "Y": np.asarray(y, dtype=np.float64) + 1.0,
                "FLUX": np.asarray(flux, dtype=np.float64),
            }
        )
        good = np.isfinite(table["X"]) & np.isfinite(table["Y"]) & np.isfinite(table["FLUX"])
        if int(good.sum()) < 4:
            raise NoSolutionError(f"solve-field needs at least 4 stars, got {int(good.sum())}")
        rows, cols = shape
        extra = ["--width", str(cols), "--height", str(rows), "--x-column", "X", "--y-column", "Y"]
        extra += ["--sort-column", "FLUX"]
        return await self._solve(
            lambda path: table[good].write(path, format="fits"), "stars.xyls", extra, hints
        )

    async def solve_image(self, data: npt.ArrayLike, *, hints: SolveHints) -> fits.Header:
        """Solve pixels (solve-field finds the stars itself; slower than :meth:`solve_stars`)."""
        pixels = np.asarray(data, dtype=np.float32)
        extra = ["--downsample", str(self.downsample), "--no-remove-lines"]
        return await self._solve(lambda path: fits.writeto(path, pixels), "image.fits", extra, hints)

    def command(self, executable: str, input_path: Path, extra: list[str], hints: SolveHints) -> list[str]:
        """The full solve-field command line (without running it)."""
        out = input_path.parent
        command = [executable, "--overwrite", "--no-plots", "--no-verify", "--crpix-center"]
        command += ["--dir", str(out), "--temp-dir", str(out), "--cpulimit", f"{self.cpu_limit_s:g}"]
        command += ["--objs", str(self.max_stars), "--wcs", str(out / "solution.wcs")]
        for option in ("--new-fits", "--index-xyls", "--rdls", "--corr", "--match"):
            command += [option, "none"]
        command += ["--no-tweak"] if self.tweak_order == 0 else ["--tweak-order", str(self.tweak_order)]
        if self.config is not None:
            command += ["--config", self.config]
        elif self.index_dir is not None:
            command += ["--config", str(out / "astrometry.cfg")]
        return [*command, *extra, *hints.arguments(), str(input_path)]

    async def _solve(
        self, write: Callable[[Path], None], name: str, extra: list[str], hints: SolveHints
    ) -> fits.Header:
        executable = self.find_executable()
        with tempfile.TemporaryDirectory(prefix="nightcrew-solve-") as workdir:
            input_path = Path(workdir) / name
            await asyncio.to_thread(write, input_path)
            if self.index_dir is not None:
                await asyncio.to_thread(
                    _blocking_write_config, Path(workdir) / "astrometry.cfg", self.index_dir
                )
            command = self.command(executable, input_path, extra, hints)
            output = await self._run(command)
            solution = Path(workdir) / "solution.wcs"
            if not solution.exists():
                raise NoSolutionError(f"solve-field found no solution:\n{output[-_TAIL:]}")
            return await asyncio.to_thread(_blocking_read_wcs, solution)

    async def _run(self, command: list[str]) -> str:
        """Run ``command`` in its own process group; kill the group on timeout or cancellation."""
        log.debug("running %s", " ".join(command))
        process = await asyncio.create_subprocess_exec(
            *command,
            stdin=asyncio.subprocess.DEVNULL,
            stdout=asyncio.subprocess.PIPE,
            stderr=asyncio.subprocess.STDOUT,
            start_new_session=True,  # solve-field starts helpers; a timeout must stop them all
        )
        try:
            stdout, _ = await asyncio.wait_for(process.communicate(), self.timeout_s)
        except TimeoutError:
            _kill_group(process.pid)
            await process.wait()
            raise AstrometryError(f"solve-field did not finish within {self.timeout_s:g} s") from None
        except asyncio.CancelledError:
            _kill_group(process.pid)
            await process.wait()
            raise
        text = stdout.decode(errors="replace")
        if process.returncode != 0:
            raise AstrometryError(f"solve-field failed (exit code {process.returncode}):\n{text[-_TAIL:]}")
        return text


def _blocking_write_config(path: Path, index_dir: str) -> None:
    """An astrometry.cfg that loads the index files of ``index_dir`` (and no others)."""
    if not any(Path(index_dir).glob("index-*.fits")):
        raise SolverUnavailableError(f"no astrometry.net index files (index-*.fits) in {index_dir}")
    path.write_text(f"add_path {index_dir}\nautoindex\n")


def _kill_group(pid: int) -> None:
    with contextlib.suppress(ProcessLookupError):
        os.killpg(pid, signal.SIGKILL)


def _blocking_read_wcs(path: Path) -> fits.Header:
    """The celestial WCS cards of solve-field's ``.wcs`` file (TAN or TAN-SIP)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", FITSFixedWarning)  # astropy notes harmless header repairs
        wcs = WCS(fits.getheader(path))
    if not wcs.has_celestial:
        raise AstrometryError(f"solve-field wrote no celestial WCS to {path.name}")
    header: fits.Header = wcs.to_header(relax=True)
    return header
