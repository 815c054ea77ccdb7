"""The Pipeline module reduces each new object frame with the newest masters and writes it with
the reduction headers to its output directory (a local root here; an ArchiveFile root in use)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from nightcrew.config import build_object
from nightcrew.errors import ConfigError
from nightcrew.events import NewImageEvent
from nightcrew.images import Image
from nightcrew.images.calibration import MasterKind, build_master
from nightcrew.interfaces import ImageType
from nightcrew.modules import Module
from nightcrew.modules.image import Pipeline
from nightcrew.testing import Observatory
from nightcrew.testing.solver import rendered_field, sky_distance_arcsec
from nightcrew.vfs import LocalFile, MemoryFile, VirtualFileSystem

HEADER = {
    "IMAGETYP": "object",
    "XBINNING": 1,
    "YBINNING": 1,
    "EXPTIME": 30.0,
    "DATE-OBS": "2026-01-01T22:00:00",
}


async def test_a_new_object_frame_is_reduced_solved_and_written(
    fast_observatory: Observatory, tmp_path: Path, solver_url: str
) -> None:
    obs = fast_observatory
    vfs = VirtualFileSystem({"cache": MemoryFile(), "data": LocalFile(str(tmp_path))})
    rng = np.random.default_rng(1)
    biases = [
        Image(rng.normal(100.0, 3.0, (2048, 2048)).astype(np.float32), header={**HEADER, "IMAGETYP": "bias"})
        for _ in range(3)
    ]
    await build_master(MasterKind.BIAS, biases).to_vfs(vfs, "/data/masters/master_bias_1x1.fits")
    await vfs.write_bytes("/data/masters/notes.fits", b"not a FITS file")  # skipped, not fatal
    field = rendered_field(100.0, 30.0, rotation_deg=10.0)
    # The telescope believes it points 6' off; the simulated sky of seed 0 is the catalog's.
    header = {**HEADER, "RA": 100.1, "DEC": 30.05, "PIXSCALE": field.pixel_scale_arcsec, "SIM-SEED": 0}
    await Image(field.data, header=header).to_vfs(vfs, "/cache/raw/frame-001.fits")
    await Image(field.data, header={**header, "IMAGETYP": "skyflat"}).to_vfs(vfs, "/cache/raw/flat.fits")

    pipeline = await obs.start(
        Pipeline, "pipeline", vfs=vfs, masters="/data/masters", output="/data/reduced", solver_url=solver_url
    )
    camera = await obs.start(Module, "camera", vfs=vfs)
    await camera.comm.send_event(NewImageEvent(filename="/cache/raw/flat.fits", image_type=ImageType.SKYFLAT))
    await camera.comm.send_event(
        NewImageEvent(filename="/cache/raw/frame-001.fits", image_type=ImageType.OBJECT)
    )
    await obs.wait_for(lambda: bool(pipeline.reduced or pipeline.failed), 600.0, interval=1.0)

    assert pipeline.reduced == ["/data/reduced/frame-001_red.fits"] and not pipeline.failed
    reduced = Image.from_bytes((tmp_path / "reduced" / "frame-001_red.fits").read_bytes())
    assert reduced.header["RLEVEL"] == 91 and reduced.header["RAWFILE"] == "frame-001.fits"
    assert reduced.header["BIASFILE"] == "master_bias_1x1.fits"
    assert "DARKFILE" not in reduced.header and "FLATFILE" not in reduced.header
    ra, dec = reduced.pixel_to_sky([1023.5], [1023.5])
    assert sky_distance_arcsec(float(ra[0]), float(dec[0]), 100.0, 30.0) < 1.0
    assert reduced.catalog is not None and len(reduced.catalog) > 100
    assert set(pipeline.times.seconds) >= {"calibrate", "detect", "solve", "photometry"}


@pytest.mark.parametrize(
    ("change", "key"),
    [
        ({"masters": "masters"}, "masters"),
        ({"solver_url": "localhost:8091"}, "solver_url"),
        ({"max_queue": 0}, "max_queue"),
        ({"observatory_code": "Z9"}, "observatory_code"),
    ],
)
def test_a_bad_option_is_a_config_error_naming_its_key(change: dict[str, object], key: str) -> None:
    config = {
        "class": "nightcrew.modules.image.Pipeline",
        "name": "p",
        "masters": "/m",
        "output": "/o",
        **change,
    }
    with pytest.raises(ConfigError) as info:
        build_object(config)
    assert info.value.key == key


def test_the_example_config_builds_a_pipeline() -> None:
    from nightcrew.config import load_config

    example = Path(__file__).resolve().parents[3] / "examples" / "pipeline.yaml"
    assert isinstance(build_object({**load_config(example), "name": "pipeline"}, Module), Pipeline)
