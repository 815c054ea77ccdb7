"""VirtualFileSystem construction, public surface, format errors and light imports."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path
from typing import Any

import pytest

import nightcrew.vfs
from nightcrew.errors import ConfigError, InvalidArgumentError, NightcrewError, error_class
from nightcrew.vfs import (
    MemoryFile,
    UnknownRootError,
    VfsError,
    VfsFileNotFoundError,
    VfsFormatError,
    VfsPathError,
    VirtualFileSystem,
)


def test_public_surface_is_curated() -> None:
    assert sorted(nightcrew.vfs.__all__) == [
        "ArchiveFile",
        "FileRoot",
        "HttpFile",
        "LocalFile",
        "MemoryFile",
        "SMBFile",
        "SSHFile",
        "TempFile",
        "UnknownRootError",
        "VfsError",
        "VfsFileNotFoundError",
        "VfsFormatError",
        "VfsPathError",
        "VirtualFileSystem",
    ]
    for name in nightcrew.vfs.__all__:
        assert getattr(nightcrew.vfs, name).__module__.startswith("nightcrew.vfs.")


def test_errors_belong_to_the_nightcrew_tree_and_travel_by_name() -> None:
    for cls in (VfsError, VfsPathError, UnknownRootError, VfsFileNotFoundError, VfsFormatError):
        assert issubclass(cls, NightcrewError)
        assert error_class(cls.__name__) is cls
    # Over RPC only class and message travel; the message still names the path.
    remote = VfsFileNotFoundError(
        str(VfsFileNotFoundError("no such file", path="/cache/a.fits")), module="cam"
    )
    assert str(remote) == "cam: /cache/a.fits: no such file"


@pytest.mark.parametrize(
    ("roots", "message"),
    [
        ({"": MemoryFile()}, r"invalid root name ''"),
        ({"a/b": MemoryFile()}, r"invalid root name 'a/b'"),
        ({"..": MemoryFile()}, r"invalid root name '\.\.'"),
        ({"a\\b": MemoryFile()}, r"invalid root name 'a\\\\b': backslash"),
        ({"cache": {"class": "nightcrew.vfs.LocalFile"}}, r"key 'roots\.cache': expected a FileRoot"),
    ],
)
def test_bad_roots_fail_at_construction(roots: dict[str, Any], message: str) -> None:
    with pytest.raises(ConfigError, match=message):
        VirtualFileSystem(roots)


def test_roots_are_read_only() -> None:
    root = MemoryFile()
    vfs = VirtualFileSystem({"cache": root})
    assert vfs.roots["cache"] is root
    with pytest.raises(TypeError):
        vfs.roots["other"] = MemoryFile()  # type: ignore[index]


def test_open_file_rejects_unknown_mode_and_bad_path_immediately() -> None:
    vfs = VirtualFileSystem({"cache": MemoryFile()})
    with pytest.raises(InvalidArgumentError, match="unsupported mode 'a'"):
        vfs.open_file("/cache/x", "a")  # type: ignore[call-overload]
    with pytest.raises(VfsPathError, match="leaves the root"):
        vfs.open_file("/cache/../x")


@pytest.fixture
def vfs() -> VirtualFileSystem:
    return VirtualFileSystem({"cache": MemoryFile()})


async def test_reading_garbage_as_fits_fails_clearly(vfs: VirtualFileSystem) -> None:
    await vfs.write_bytes("/cache/bad.fits", b"this is not a FITS file")
    with pytest.raises(VfsFormatError, match=r"^/cache/bad\.fits: not a valid FITS file"):
        await vfs.read_fits("/cache/bad.fits")


async def test_truncated_fits_is_an_error_not_a_warning(vfs: VirtualFileSystem) -> None:
    import numpy as np
    from astropy.io import fits  # type: ignore[import-untyped]

    await vfs.write_fits("/cache/full.fits", fits.HDUList([fits.PrimaryHDU(np.zeros((64, 64)))]))
    data = await vfs.read_bytes("/cache/full.fits")
    await vfs.write_bytes("/cache/half.fits", data[: len(data) // 2])  # e.g. a copy in progress
    with pytest.raises(VfsFormatError, match=r"^/cache/half\.fits: not a valid FITS file: .*truncated"):
        await vfs.read_fits("/cache/half.fits")


async def test_invalid_fits_header_is_refused_before_writing(vfs: VirtualFileSystem) -> None:
    from astropy.io import fits

    hdu = fits.PrimaryHDU()
    hdu.header["NAXIS"] = "two"
    with pytest.raises(VfsFormatError, match=r"^/cache/x\.fits: cannot write FITS"):
        await vfs.write_fits("/cache/x.fits", fits.HDUList([hdu]))
    assert not await vfs.exists("/cache/x.fits")


async def test_bad_yaml_and_csv_fail_clearly(vfs: VirtualFileSystem) -> None:
    await vfs.write_bytes("/cache/bad.yaml", b"key: [unclosed")
    with pytest.raises(VfsFormatError, match=r"^/cache/bad\.yaml: not valid YAML"):
        await vfs.read_yaml("/cache/bad.yaml")
    await vfs.write_bytes("/cache/bad.csv", b"a,b\n\xff\xfe,1\n")
    with pytest.raises(VfsFormatError, match=r"^/cache/bad\.csv: not valid CSV"):
        await vfs.read_csv("/cache/bad.csv")


async def test_yaml_refuses_python_objects(vfs: VirtualFileSystem) -> None:
    await vfs.write_bytes("/cache/evil.yaml", b"!!python/object/apply:os.system ['true']")
    with pytest.raises(VfsFormatError, match="not valid YAML"):
        await vfs.read_yaml("/cache/evil.yaml")


async def test_csv_with_fieldnames(vfs: VirtualFileSystem) -> None:
    await vfs.write_csv("/cache/empty.csv", [], fieldnames=["time", "flux"])
    assert await vfs.read_bytes("/cache/empty.csv") == b"time,flux\n"
    assert await vfs.read_csv("/cache/empty.csv") == []
    with pytest.raises(VfsFormatError, match=r"cannot write CSV: .*'extra'"):
        await vfs.write_csv("/cache/x.csv", [{"time": 1, "extra": 2}], fieldnames=["time"])


def test_importing_the_vfs_does_not_import_astropy() -> None:
    code = "import sys, nightcrew.vfs; sys.exit('astropy' in sys.modules)"
    assert subprocess.run([sys.executable, "-c", code], check=False).returncode == 0


async def test_built_from_the_paper_config(tmp_path: Path) -> None:
    from nightcrew.config import build_object, load_config

    images = tmp_path / "images"
    config_file = tmp_path / "vfs.yaml"
    config_file.write_text(
        "class: nightcrew.vfs.VirtualFileSystem\n"
        "roots:\n"
        f"  cache: {{class: nightcrew.vfs.LocalFile, root: {images}}}\n"
        "  shared: {class: nightcrew.vfs.MemoryFile, name: exchange}\n"
    )
    vfs = build_object(load_config(config_file))
    assert isinstance(vfs, VirtualFileSystem)
    assert not images.exists()  # building did no I/O
    await vfs.write_bytes("/cache/a.fits", b"x")
    assert (images / "a.fits").read_bytes() == b"x"
