"""Frames that cost before they are refused: huge declared images, gzip bombs, thin frames, long ids."""

from __future__ import annotations

import gzip
import io
import tracemalloc
from pathlib import Path

import numpy as np
import pytest
from astropy.io import fits  # type: ignore[import-untyped]

from nightcrew.services.archive._files import blocking_thumbnail
from nightcrew.testing.archive import RunningArchive, fits_frame, running_archive

from .conftest import Client

HUGE = 100_000


def compressed_frame_claiming(side: int) -> bytes:
    """A tile-compressed frame of 64 x 64 pixels whose header claims ``side`` x ``side``."""
    primary = fits.open(io.BytesIO(fits_frame()))[0].header
    hdus = fits.HDUList([fits.PrimaryHDU(header=primary), fits.CompImageHDU(np.zeros((64, 64), np.int16))])
    out = io.BytesIO()
    hdus.writeto(out)
    data = out.getvalue()
    for key in (b"ZNAXIS1", b"ZNAXIS2"):
        card = key.ljust(8) + b"= " + b"64".rjust(20)
        assert data.count(card) == 1
        data = data.replace(card, key.ljust(8) + b"= " + str(side).encode().rjust(20))
    return data


def files_in(archive: RunningArchive) -> list[Path]:
    return [path for path in archive.storage.rglob("*") if path.is_file() and ".thumbnails" not in path.parts]


async def test_a_frame_declaring_too_many_pixels_is_refused_and_not_stored(
    client: Client, archive: RunningArchive
) -> None:
    status, body = await client.upload(compressed_frame_claiming(HUGE), "huge.fits.fz")
    assert status == 422
    assert body["detail"] == (
        f"HDU 1 declares {HUGE} x {HUGE} = {HUGE**2} pixels, more than max_frame_pixels (100000000)"
    )
    assert files_in(archive) == []
    assert (await client.get("/frames/"))[1]["count"] == 0


def test_a_thumbnail_reads_no_more_than_its_limit(tmp_path: Path) -> None:
    """A frame stored before the limit was lowered: refused before any pixel is read; a large frame
    within the limit is read every n-th row and column, a block at a time (a fraction of the 32 MB
    the whole image takes as float64)."""
    claimed = tmp_path / "claimed.fits.fz"
    claimed.write_bytes(compressed_frame_claiming(HUGE))
    with pytest.raises(ValueError, match=f"declares {HUGE**2} pixels, more than 100000000"):
        blocking_thumbnail(claimed, tmp_path / "1.png", 256, max_pixels=100_000_000)
    large = tmp_path / "large.fits"
    fits.PrimaryHDU(np.ones((4000, 1000), np.float64)).writeto(large)
    tracemalloc.start()
    try:
        png = blocking_thumbnail(large, tmp_path / "2.png", 256, max_pixels=100_000_000)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert png.startswith(b"\x89PNG") and peak < 16_000_000, peak


async def test_ids_beyond_64_bits_name_no_frame(client: Client) -> None:
    for path in ("/frames/99999999999999999999999/", "/frames/99999999999999999999999/thumbnail/"):
        status, body = await client.get(path)
        assert (status, body["detail"]) == (404, "no frame with id 99999999999999999999999")


async def test_a_fits_gz_upload_is_stored_as_sent_and_shown(client: Client) -> None:
    packed = gzip.compress(fits_frame(shape=(40, 30), seed=3))
    status, frame = await client.upload(packed, "night.fits.gz")
    assert status == 201, frame
    assert frame["basename"] == "night.fits.gz" and frame["size"] == len(packed)
    assert (await client.get_bytes(f"/frames/{frame['id']}/download/"))[1] == packed
    status, png, kind = await client.get_bytes(f"/frames/{frame['id']}/thumbnail/")
    assert (status, kind) == (200, "image/png")
    assert (int.from_bytes(png[16:20], "big"), int.from_bytes(png[20:24], "big")) == (30, 40)


async def test_gzip_that_disagrees_with_its_name_or_unpacks_too_far_is_refused(
    tmp_path: Path, database: str | None
) -> None:
    async with running_archive(tmp_path, database=database, max_upload_bytes=100_000) as archive:
        client = Client(archive)
        try:
            frame = fits_frame()
            status, body = await client.upload(gzip.compress(frame), "a.fits")
            assert (status, body["detail"]) == (400, "a.fits is gzip-compressed: name it .fits.gz")
            status, body = await client.upload(frame, "b.fits.gz")
            assert (status, body["detail"]) == (400, "b.fits.gz ends in .gz but is not gzip-compressed")
            bomb = gzip.compress(frame + bytes(2880 * 1000))  # 2.9 MB of FITS in a few kB
            status, body = await client.upload(bomb, "c.fits.gz")
            assert (status, body["detail"]) == (
                413,
                "c.fits.gz unpacks to more than the limit of 100000 bytes",
            )
            status, body = await client.upload(gzip.compress(frame)[:-20], "d.fits.gz")
            assert status == 400 and "truncated gzip file" in body["detail"]
        finally:
            await client.close()
        assert files_in(archive) == []


async def test_a_thin_frame_gets_a_thumbnail(client: Client) -> None:
    status, frame = await client.upload(fits_frame(shape=(1, 3000)), "spectrum.fits")
    assert status == 201, frame
    status, png, kind = await client.get_bytes(f"/frames/{frame['id']}/thumbnail/", size=256)
    assert (status, kind) == (200, "image/png")
    assert (int.from_bytes(png[16:20], "big"), int.from_bytes(png[20:24], "big")) == (250, 1)
