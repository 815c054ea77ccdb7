"""docs/mounts.md, "A simulated German-equatorial observatory", run as written: a copy of the bundled
observatory with ``gem:`` in its telescope.yaml, and a short night in which M52 crosses the
meridian. The mount flips once between two frames (within 3 clock minutes), the acquisition centres
M52 again (checked on the first frame after the flip by its own plate solution), PIERSIDE is right
on every frame and no frame comes near the pier limit."""

from __future__ import annotations

import logging
import re
import shlex
import shutil
import subprocess
from datetime import datetime
from pathlib import Path

import pytest
from astropy.coordinates import SkyCoord  # type: ignore[import-untyped]
from astropy.io import fits  # type: ignore[import-untyped]

from nightcrew.astro.pier import counterweight_up, hour_angle
from nightcrew.cli.main import main
from nightcrew.config import build_object
from nightcrew.images import Image, Pipeline
from nightcrew.interfaces import PierSide
from nightcrew.night.build import bundled_observatory, load_in_process

from ..sim.solving import offset_arcsec

DOC = (Path(__file__).parents[2] / "docs/mounts.md").read_text(encoding="utf-8")
SECTION = DOC[DOC.index("### A simulated German-equatorial observatory") :]
FLIP_GOAL_S = 180.0  # issue 27: last frame before the flip to the first after it


def _lines() -> list[str]:
    block = re.search(r"^```sh\n(.*?)^```", SECTION, flags=re.M | re.S)
    assert block is not None, "no sh block in the section"
    return block.group(1).splitlines()


@pytest.fixture(scope="module")
def gem_night(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, list[fits.Header], list[str]]:
    """The documented lines run in a fresh directory: the copy (as the first line, without the
    repository's run-time leftovers), the ``cat >>`` by bash, the night by ``main``."""
    here = tmp_path_factory.mktemp("gem")
    copy, *edit, night = _lines()
    assert copy == "cp -r examples/observatory my-gem"
    ignore = shutil.ignore_patterns("frames", "xmpp", "logs", "*.sqlite*", "*.jsonl")
    shutil.copytree(bundled_observatory(), here / "my-gem", ignore=ignore)
    subprocess.run(["bash", "-e", "-c", "\n".join(edit) + "\n"], cwd=here, check=True, timeout=30)
    assert night.startswith("nightcrew sim ")
    handler = _Errors()
    logging.getLogger("nightcrew").addHandler(handler)
    try:
        arguments = shlex.split(night.removeprefix("nightcrew "))
        arguments = [str(here / a) if a in ("my-gem", "gem-night") else a for a in arguments]
        assert main(arguments) == 0
    finally:
        logging.getLogger("nightcrew").removeHandler(handler)
    frames = sorted((here / "gem-night" / "frames").glob("*.fits"))
    return here, [fits.getheader(path) for path in frames], handler.messages


class _Errors(logging.Handler):
    def __init__(self) -> None:
        super().__init__(logging.ERROR)
        self.messages: list[str] = []

    def emit(self, record: logging.LogRecord) -> None:
        self.messages.append(record.getMessage())


def _start(header: fits.Header) -> float:
    return datetime.fromisoformat(f"{header['DATE-OBS']}+00:00").timestamp()


def test_the_mount_flips_once_between_two_frames_and_every_frame_is_on_its_side(
    gem_night: tuple[Path, list[fits.Header], list[str]],
) -> None:
    here, headers, errors = gem_night
    telescope = load_in_process(here / "my-gem" / "telescope.yaml")
    assert telescope["gem"]["counterweight_up"] == 15.0
    science = [h for h in headers if h["IMAGETYP"] == "object"]
    sides = [h["PIERSIDE"] for h in science]
    assert sides == ["WEST", "WEST", "EAST", "EAST"], sides
    assert [h["EXPTIME"] for h in science] == [600.0] * 4  # set up again after the acquisition
    site = telescope["site"]
    for header in science:  # each frame on the side with its target, counterweight at most 5° up
        end = _start(header) + header["EXPTIME"]
        ha = hour_angle(header["RA"], header["DEC"], site["longitude"], end)
        assert counterweight_up(ha, PierSide(header["PIERSIDE"].lower())) <= 5.0, (header["PIERSIDE"], ha)
    gap = _start(science[2]) - (_start(science[1]) + science[1]["EXPTIME"])
    assert 180.0 / 4.0 < gap <= FLIP_GOAL_S  # the hour axis turned half round, then centring
    between = [h["IMAGETYP"] for h in headers if _start(science[1]) < _start(h) < _start(science[2])]
    assert between and set(between) == {"acquisition"}
    assert not [m for m in errors if "pier limit" in m]  # no collision


async def test_the_first_frame_after_the_flip_is_centred_by_its_own_plate_solution(
    gem_night: tuple[Path, list[fits.Header], list[str]],
) -> None:
    # Solved as the acquisition solves (its pipeline, on the index files of the simulated sky the
    # night built), but on the science frame after the flip, not on the acquisition's own frames.
    here, headers, _ = gem_night
    first = next(h for h in headers if h["IMAGETYP"] == "object" and h["PIERSIDE"] == "EAST")
    acquisition = load_in_process(here / "my-gem" / "robotic" / "acquisition.yaml")
    pipeline = build_object(acquisition["pipeline"], Pipeline)
    path = next(
        p for p in (here / "gem-night" / "frames").glob("*-object-*.fits") if fits.getheader(p) == first
    )
    wcs = (await pipeline(Image.from_bytes(path.read_bytes()))).wcs
    assert wcs is not None, "the frame after the flip did not solve"
    target = SkyCoord(first["OBJCTRA"], first["OBJCTDEC"], unit=("hourangle", "deg"))
    offset = offset_arcsec(wcs, (first["NAXIS2"], first["NAXIS1"]), target.ra.deg, target.dec.deg)
    assert offset < acquisition["tolerance"], offset
