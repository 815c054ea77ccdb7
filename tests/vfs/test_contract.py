"""The behaviour every root shares, run through the VFS on each root type (see conftest)."""

from __future__ import annotations

import hashlib

import numpy as np
import pytest

from nightcrew.errors import InvalidArgumentError
from nightcrew.vfs import FileRoot, VfsError, VfsFileNotFoundError, VirtualFileSystem


async def test_bytes_round_trip(vfs: VirtualFileSystem) -> None:
    data = bytes(range(256)) * 3
    await vfs.write_bytes("/cache/raw/frame.bin", data)
    assert await vfs.read_bytes("/cache/raw/frame.bin") == data
    assert await vfs.size("/cache/raw/frame.bin") == len(data)


async def test_write_accepts_bytearray_and_memoryview(vfs: VirtualFileSystem) -> None:
    await vfs.write_bytes("/cache/a.bin", bytearray(b"abc"))
    await vfs.write_bytes("/cache/b.bin", memoryview(b"xyz"))
    assert await vfs.read_bytes("/cache/a.bin") == b"abc"
    assert await vfs.read_bytes("/cache/b.bin") == b"xyz"


async def test_overwrite_replaces_content(vfs: VirtualFileSystem) -> None:
    await vfs.write_bytes("/cache/x.txt", b"a long first version")
    await vfs.write_bytes("/cache/x.txt", b"short")
    assert await vfs.read_bytes("/cache/x.txt") == b"short"


async def test_equivalent_spellings_name_one_file(vfs: VirtualFileSystem) -> None:
    await vfs.write_bytes("/cache/night/./a//b.fits", b"1")
    assert await vfs.read_bytes("/cache/night/x/../a/b.fits") == b"1"
    assert await vfs.read_bytes("//cache/night/a/b.fits") == b"1"


async def test_exists_for_files_directories_and_root(vfs: VirtualFileSystem) -> None:
    assert await vfs.exists("/cache")
    assert not await vfs.exists("/cache/night/a.fits")
    await vfs.write_bytes("/cache/night/a.fits", b"")
    assert await vfs.exists("/cache/night/a.fits")
    assert await vfs.exists("/cache/night")
    assert not await vfs.exists("/cache/night/a.fits/inside")


async def test_listdir_names_files_and_directories(vfs: VirtualFileSystem) -> None:
    assert await vfs.listdir("/cache") == []
    for path in ("/cache/n1/b.fits", "/cache/n1/a.fits", "/cache/n1/sub/c.fits", "/cache/top.yaml"):
        await vfs.write_bytes(path, b"x")
    assert await vfs.listdir("/cache") == ["n1", "top.yaml"]
    assert await vfs.listdir("/cache/n1") == ["a.fits", "b.fits", "sub"]


async def test_listdir_of_missing_directory_fails(vfs: VirtualFileSystem) -> None:
    with pytest.raises(VfsFileNotFoundError, match=r"^/cache/nope: no such"):
        await vfs.listdir("/cache/nope")


async def test_listdir_of_a_file_fails(vfs: VirtualFileSystem) -> None:
    await vfs.write_bytes("/cache/a.fits", b"x")
    with pytest.raises(VfsError, match=r"^/cache/a\.fits: "):
        await vfs.listdir("/cache/a.fits")


async def test_remove(vfs: VirtualFileSystem) -> None:
    await vfs.write_bytes("/cache/n/a.fits", b"x")
    await vfs.remove("/cache/n/a.fits")
    assert not await vfs.exists("/cache/n/a.fits")
    with pytest.raises(VfsFileNotFoundError, match=r"^/cache/n/a\.fits: no such file"):
        await vfs.remove("/cache/n/a.fits")


async def test_remove_refuses_a_directory(vfs: VirtualFileSystem) -> None:
    await vfs.write_bytes("/cache/n/a.fits", b"x")
    with pytest.raises(VfsError, match=r"^/cache/n: is a directory"):
        await vfs.remove("/cache/n")
    assert await vfs.exists("/cache/n/a.fits")


@pytest.mark.parametrize("method", ["read_bytes", "size", "checksum"])
async def test_missing_file_is_named(vfs: VirtualFileSystem, method: str) -> None:
    with pytest.raises(VfsFileNotFoundError, match=r"^/cache/night/missing\.fits: no such file"):
        await getattr(vfs, method)("/cache/night/missing.fits")


async def test_reading_a_directory_fails(vfs: VirtualFileSystem) -> None:
    await vfs.write_bytes("/cache/n/a.fits", b"x")
    with pytest.raises(VfsError, match=r"^/cache/n: is a directory"):
        await vfs.read_bytes("/cache/n")


async def test_writing_below_a_file_fails(vfs: VirtualFileSystem) -> None:
    await vfs.write_bytes("/cache/a.fits", b"x")
    with pytest.raises(VfsError, match=r"^/cache/a\.fits/b\.fits: "):
        await vfs.write_bytes("/cache/a.fits/b.fits", b"y")
    assert await vfs.read_bytes("/cache/a.fits") == b"x"


async def test_writing_the_root_itself_fails(vfs: VirtualFileSystem) -> None:
    with pytest.raises(VfsError, match="is a directory"):
        await vfs.write_bytes("/cache", b"x")


async def test_checksum_matches_hashlib(vfs: VirtualFileSystem) -> None:
    data = b"photons" * 1000
    await vfs.write_bytes("/cache/a.fits", data)
    assert await vfs.checksum("/cache/a.fits") == hashlib.sha256(data).hexdigest()
    assert await vfs.checksum("/cache/a.fits", "md5") == hashlib.md5(data).hexdigest()


async def test_checksum_rejects_unknown_algorithm(vfs: VirtualFileSystem) -> None:
    await vfs.write_bytes("/cache/a.fits", b"x")
    with pytest.raises(InvalidArgumentError, match="unknown checksum algorithm 'crc99'"):
        await vfs.checksum("/cache/a.fits", "crc99")


async def test_find(vfs: VirtualFileSystem) -> None:
    paths = [
        "/cache/2024-11-01/a.fits",
        "/cache/2024-11-01/a.yaml",
        "/cache/2024-11-02/b.fits",
        "/cache/2024-11-02/deep/c.fits",
        "/cache/top.fits",
    ]
    for path in paths:
        await vfs.write_bytes(path, b"x")
    assert await vfs.find("/cache/2024-*/*.fits") == ["/cache/2024-11-01/a.fits", "/cache/2024-11-02/b.fits"]
    assert await vfs.find("/cache/**/*.fits") == [p for p in paths if p.endswith(".fits")]
    assert await vfs.find("/cache/2024-11-0[2]/**") == [
        "/cache/2024-11-02/b.fits",
        "/cache/2024-11-02/deep/c.fits",
    ]
    assert await vfs.find("/cache/2024-11-01/?.y???") == ["/cache/2024-11-01/a.yaml"]
    assert await vfs.find("/cache/top.fits") == ["/cache/top.fits"]
    assert await vfs.find("/cache/missing/*.fits") == []


async def test_open_file_text_and_binary(vfs: VirtualFileSystem) -> None:
    async with vfs.open_file("/cache/log.txt", "w") as text:
        text.write("first line\nsecond line, ünïcode ß\n")
    async with vfs.open_file("/cache/log.txt") as text:
        assert text.readlines() == ["first line\n", "second line, ünïcode ß\n"]
    async with vfs.open_file("/cache/blob.bin", "wb") as binary:
        binary.write(b"\x00\x01")
    async with vfs.open_file("/cache/blob.bin", "rb") as binary:
        assert binary.read() == b"\x00\x01"


async def test_open_file_writes_nothing_when_the_block_fails(vfs: VirtualFileSystem) -> None:
    await vfs.write_bytes("/cache/log.txt", b"old")
    with pytest.raises(RuntimeError, match="boom"):
        async with vfs.open_file("/cache/log.txt", "w") as text:
            text.write("new")
            raise RuntimeError("boom")
    assert await vfs.read_bytes("/cache/log.txt") == b"old"


async def test_yaml_round_trip(vfs: VirtualFileSystem) -> None:
    value = {"name": "M 42", "exposures": [1.5, 30], "filters": {"V": True}, "note": None, "ü": "ß"}
    await vfs.write_yaml("/cache/task.yaml", value)
    assert await vfs.read_yaml("/cache/task.yaml") == value
    assert list(await vfs.read_yaml("/cache/task.yaml")) == list(value)  # key order kept


async def test_csv_round_trip(vfs: VirtualFileSystem) -> None:
    rows: list[dict[str, object]] = [
        {"time": "2024-11-02T20:00:00", "focus": 12.5, "fwhm": 2.1},
        {"time": "2024-11-02T20:01:00", "focus": 13.0, "note": "cloud, thin"},
    ]
    await vfs.write_csv("/cache/focus.csv", rows)
    assert await vfs.read_csv("/cache/focus.csv") == [
        {"time": "2024-11-02T20:00:00", "focus": "12.5", "fwhm": "2.1", "note": ""},
        {"time": "2024-11-02T20:01:00", "focus": "13.0", "fwhm": "", "note": "cloud, thin"},
    ]


async def test_fits_round_trip(vfs: VirtualFileSystem) -> None:
    from astropy.io import fits  # type: ignore[import-untyped]

    rng = np.random.default_rng(42)
    image = rng.integers(0, 65535, size=(16, 24)).astype(np.uint16)
    primary = fits.PrimaryHDU(image)
    primary.header["EXPTIME"] = (30.0, "exposure time [s]")
    table = fits.BinTableHDU.from_columns([fits.Column(name="flux", format="D", array=np.arange(4.0))])
    await vfs.write_fits("/cache/img.fits", fits.HDUList([primary, table]))

    hdul = await vfs.read_fits("/cache/img.fits")
    assert len(hdul) == 2
    np.testing.assert_array_equal(hdul[0].data, image)
    assert hdul[0].header["EXPTIME"] == 30.0
    np.testing.assert_array_equal(hdul[1].data["flux"], np.arange(4.0))
    hdul[0].data[0, 0] = 1  # data is an ordinary writable array, not a view on a closed buffer


async def test_root_used_directly_normalises_and_guards_paths(root: FileRoot) -> None:
    try:
        await root.write_bytes("/a/./b.txt", b"x")  # a leading slash stays inside the root
        assert await root.read_bytes("a/b.txt") == b"x"
        assert await root.find("**/*.txt") == ["a/b.txt"]
        with pytest.raises(VfsError, match=r"'\.\.' leaves the root"):
            await root.read_bytes("../outside.txt")
    finally:
        await root.close()
