"""ImageWriter copies each new image to a path made from its header, through the VFS."""

from __future__ import annotations

from pathlib import Path

import pytest

from nightcrew.config import build_object
from nightcrew.errors import ConfigError
from nightcrew.events import NewImageEvent
from nightcrew.modules.image import ImageWriter
from nightcrew.testing import Observatory
from nightcrew.vfs import MemoryFile, VirtualFileSystem
from tests.modules.devices import GradientCamera


async def test_new_images_are_copied_by_pattern(fast_observatory: Observatory) -> None:
    obs = fast_observatory
    # The writer sees the camera's /cache and an archive of its own.
    vfs = VirtualFileSystem({"cache": obs.vfs.roots["cache"], "archive": MemoryFile()})
    writer = await obs.start(
        ImageWriter,
        "writer",
        vfs=vfs,
        pattern="/archive/{IMAGETYP}/{DATE-OBS}-{EXPTIME:.1f}.fits",
        sources=["camera"],
    )
    camera = await obs.start(GradientCamera, "camera")
    await camera.set_exposure_time(2.0)
    original = await camera.grab_data()
    await obs.wait_for(lambda: bool(writer.written), 2000.0, interval=1.0)
    (copy,) = writer.written
    assert copy.startswith("/archive/object/2024-01-15T22-") and copy.endswith("-2.0.fits")
    assert await vfs.read_bytes(copy) == await obs.vfs.read_bytes(original)


def test_a_bad_pattern_is_a_config_error_naming_the_key() -> None:
    with pytest.raises(ConfigError, match="must be an absolute VFS file path") as info:
        build_object(
            {"class": "nightcrew.modules.image.ImageWriter", "name": "w", "pattern": "archive/x.fits"}
        )
    assert info.value.key == "pattern"


async def test_a_sweep_copies_images_whose_events_were_missed(
    fast_observatory: Observatory, tmp_path: Path
) -> None:
    obs = fast_observatory
    vfs = VirtualFileSystem({"cache": obs.vfs.roots["cache"], "archive": MemoryFile()})
    camera = await obs.start(GradientCamera, "camera")
    await camera.set_exposure_time(1.0)
    missed = [await camera.grab_data(), await camera.grab_data()]  # no writer running: events lost
    options = {
        "vfs": vfs,
        "pattern": "/archive/{DATE-OBS}.fits",
        "sweep": "/cache/**/*.fits",
        "sweep_interval": 10.0,
        "state_file": str(tmp_path / "writer.json"),
    }
    writer = await obs.start(ImageWriter, "writer", **options)
    await obs.wait_for(lambda: len(writer.written) == 2 and writer.waiting == 0, 2000.0, interval=1.0)
    for original, copy in zip(missed, writer.written, strict=True):
        assert await vfs.read_bytes(copy) == await obs.vfs.read_bytes(original)
    await writer.close()  # a restart: the state file says both are copied
    again = await obs.start(ImageWriter, "writer2", **options)
    third = await camera.grab_data()
    await obs.wait_for(lambda: len(again.written) == 1 and again.waiting == 0, 2000.0, interval=1.0)
    await obs.clock.sleep(30.0)  # three more sweeps: nothing copied twice
    assert len(again.written) == 1 and await vfs.read_bytes(again.written[0]) == await obs.vfs.read_bytes(
        third
    )


def test_a_sweep_needs_a_state_file() -> None:
    with pytest.raises(ConfigError, match="a sweep needs a state_file") as info:
        ImageWriter(name="w", pattern="/archive/{DATE-OBS}.fits", sweep="/cache/*.fits")
    assert info.value.key == "state_file"


async def test_an_original_that_is_no_fits_file_is_given_up_not_retried(
    fast_observatory: Observatory, caplog: pytest.LogCaptureFixture
) -> None:
    obs = fast_observatory
    vfs = VirtualFileSystem({"cache": MemoryFile(), "archive": MemoryFile()})
    await vfs.write_bytes("/cache/junk.fits", b"not a FITS file")
    writer = await obs.start(ImageWriter, "writer", vfs=vfs, pattern="/archive/{DATE-OBS}.fits")
    await writer.on_new_image(NewImageEvent(filename="/cache/junk.fits"), "camera")
    await writer.on_new_image(NewImageEvent(filename="/cache/gone.fits"), "camera")
    await obs.wait_for(lambda: writer.waiting == 0, 2000.0, interval=1.0)
    assert writer.written == []
    given_up = [r.getMessage() for r in caplog.records if "cannot copy" in r.getMessage()]
    assert len(given_up) == 2 and "not a FITS file" in given_up[0] and "gone.fits" in given_up[1]
    assert not [r for r in caplog.records if "trying again" in r.getMessage()]
