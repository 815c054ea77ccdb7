"""A camera whose field is smaller than the installed index files can solve is refused, in one line.

Debian's Tycho-2 index files start at 22' quads: ``nightcrew solver --field 19.8`` and
``nightcrew check`` on an observatory with a 1024 px camera at 1.16"/px (19.8') refuse and say
which index series to install; a 40' camera passes, and so does the simulated sky's own directory.
"""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from nightcrew.cli.main import main
from nightcrew.images.astrometry import index_coverage_problem

TYCHO2 = Path("/usr/share/astrometry")


@pytest.fixture
def tycho2() -> Path:
    if not any(TYCHO2.glob("index-tycho2-*.fits")):
        pytest.skip("astrometry-data-tycho2 is not installed")
    return TYCHO2


def test_a_20_arcmin_field_is_too_small_for_the_tycho2_indexes(tycho2: Path) -> None:
    problem = index_coverage_problem(tycho2, 19.8)
    assert problem is not None
    assert problem.startswith(
        "the camera's 19.8' field is too small for the index files in /usr/share/astrometry"
    )
    assert "smallest quads 22')" in problem and "index-5204..index-5205 or index-4204..index-4205" in problem
    assert index_coverage_problem(tycho2, 39.6) is None
    assert (
        index_coverage_problem(tycho2.parent / "no-such-dir", 19.8) is None
    )  # nothing installed: not this check's


def test_the_solver_refuses_a_field_its_indexes_cannot_solve(
    tycho2: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    pytest.importorskip("astrometry")
    assert main(["solver", "--index-dir", str(tycho2), "--field", "19.8", "--port", "0"]) == 2
    (line,) = capsys.readouterr().err.strip().splitlines()
    assert "19.8' field is too small" in line and "index-5204" in line


CAMERA = """\
class: nightcrew.modules.sim.SimCamera
detector: {{chip_width: {pixels}, chip_height: {pixels}, pixel_size_um: 9.0}}
optics: {{focal_length_mm: 1600}}
"""
ACQUISITION = """\
class: nightcrew.modules.pointing.Acquisition
camera: camera
telescope: telescope
pipeline:
  class: nightcrew.images.Pipeline
  steps:
    - {class: nightcrew.images.processors.detection.SepSourceDetection}
    - {class: nightcrew.images.astrometry.CatalogAstrometry}
"""


@pytest.mark.parametrize(("pixels", "refused"), [(1024, True), (2048, False)])
def test_check_refuses_a_camera_field_the_index_files_cannot_solve(
    tycho2: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str], pixels: int, refused: bool
) -> None:
    (tmp_path / "camera.yaml").write_text(CAMERA.format(pixels=pixels))
    (tmp_path / "acquisition.yaml").write_text(ACQUISITION)
    assert main(["check", str(tmp_path)]) == (2 if refused else 0)
    errors = capsys.readouterr().err.strip().splitlines()
    if refused:
        (line,) = errors
        assert line.startswith("nightcrew: error: the camera's 19.8' field is too small")
    else:
        assert errors == []


@pytest.mark.usefixtures("bundled_xmpp_files")  # what the files' comm needs (shared/comm.yaml)
def test_the_bundled_observatory_passes_check(capsys: pytest.CaptureFixture[str]) -> None:
    if shutil.which("solve-field") is None:
        pytest.skip("astrometry.net is not installed")
    assert main(["check", "examples/sim"]) == 0, capsys.readouterr().err
