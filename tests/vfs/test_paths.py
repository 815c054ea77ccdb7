"""Paths that try to leave their root, or are malformed, are refused before any I/O."""

from __future__ import annotations

import pytest

from nightcrew.vfs import MemoryFile, UnknownRootError, VfsPathError, VirtualFileSystem
from nightcrew.vfs._paths import glob_regex, normalise_relative, split_vfs_path, static_prefix


@pytest.fixture
def memory_vfs() -> VirtualFileSystem:
    return VirtualFileSystem({"cache": MemoryFile(), "archive": MemoryFile()})


@pytest.mark.parametrize(
    ("path", "message"),
    [
        ("/cache/../../etc/passwd", r"^/cache/\.\./\.\./etc/passwd: '\.\.' leaves the root '/cache'$"),
        ("/cache/a/../../x", r"'\.\.' leaves the root '/cache'"),
        ("/cache/..", r"'\.\.' leaves the root '/cache'"),
        ("/cache/a/../../archive/x", r"'\.\.' leaves the root '/cache'"),  # even into another root
        ("/../cache/x", r"'\.\.' leaves the file system"),
        ("/./../etc/passwd", r"'\.\.' leaves the file system"),
        ("", r"^empty path$"),
        ("/", r"no root named in path"),
        ("//", r"no root named in path"),
        ("cache/x.fits", r"must start with '/<root>/'"),
        ("../cache/x.fits", r"must start with '/<root>/'"),
        ("/cache/x\x00.fits", r"NUL byte in path"),
        ("/cache/..\\..\\etc\\passwd", r"backslash in path"),
        ("/cache/x\n.fits", r"control character in path"),
    ],
)
async def test_bad_paths_are_refused(memory_vfs: VirtualFileSystem, path: str, message: str) -> None:
    with pytest.raises(VfsPathError, match=message):
        await memory_vfs.read_bytes(path)
    with pytest.raises(VfsPathError, match=message):
        await memory_vfs.write_bytes(path, b"x")


async def test_non_string_path_is_refused(memory_vfs: VirtualFileSystem) -> None:
    with pytest.raises(VfsPathError, match="a path must be a string, got bytes"):
        await memory_vfs.read_bytes(b"/cache/x")  # type: ignore[arg-type]


async def test_unknown_root_names_it_and_the_known_ones(memory_vfs: VirtualFileSystem) -> None:
    with pytest.raises(
        UnknownRootError, match=r"^/etc/passwd: unknown root '/etc' \(known roots: /archive, /cache\)$"
    ):
        await memory_vfs.read_bytes("/etc/passwd")


async def test_unknown_root_without_any_roots() -> None:
    with pytest.raises(UnknownRootError, match=r"known roots: none"):
        await VirtualFileSystem().exists("/cache/x")


async def test_find_pattern_is_checked_like_a_path(memory_vfs: VirtualFileSystem) -> None:
    with pytest.raises(VfsPathError, match="leaves the root '/cache'"):
        await memory_vfs.find("/cache/../*/passwd")
    with pytest.raises(UnknownRootError, match=r"unknown root '/\*'"):
        await memory_vfs.find("/*/x.fits")


@pytest.mark.parametrize(
    ("path", "expected"),
    [
        ("/cache", ("cache", "")),
        ("/cache/", ("cache", "")),
        ("/cache/a/./b//c.fits", ("cache", "a/b/c.fits")),
        ("/cache/a/x/../b.fits", ("cache", "a/b.fits")),
        ("//cache/a", ("cache", "a")),
        ("/./cache/a", ("cache", "a")),
        ("/cache/~/a", ("cache", "~/a")),  # no home-directory expansion
    ],
)
def test_split_vfs_path(path: str, expected: tuple[str, str]) -> None:
    assert split_vfs_path(path) == expected


def test_normalise_relative_keeps_absolute_paths_inside() -> None:
    assert normalise_relative("/etc/passwd") == "etc/passwd"
    assert normalise_relative("") == ""
    with pytest.raises(VfsPathError, match=r"'\.\.' leaves the root"):
        normalise_relative("a/../..")


@pytest.mark.parametrize(
    ("pattern", "matches", "misses"),
    [
        ("*.fits", ["a.fits", ".hidden.fits"], ["d/a.fits", "a.fits.gz"]),
        ("**/*.fits", ["a.fits", "d/a.fits", "d/e/a.fits"], ["a.fit"]),
        ("d/**", ["d/a", "d/e/f"], ["a", "dd/a"]),
        ("img-[0-9][!a].fits", ["img-1b.fits"], ["img-xb.fits", "img-1a.fits"]),
        ("a+b(1).fits", ["a+b(1).fits"], ["aab1.fits"]),  # regex characters are literal
        ("[x.fits", ["[x.fits"], ["x.fits"]),  # an unclosed '[' is literal
    ],
)
def test_glob_regex(pattern: str, matches: list[str], misses: list[str]) -> None:
    regex = glob_regex(pattern)
    assert [m for m in matches if regex.fullmatch(m)] == matches
    assert [m for m in misses if regex.fullmatch(m)] == []


@pytest.mark.parametrize(
    ("pattern", "prefix"),
    [("2024/11/*.fits", "2024/11"), ("*.fits", ""), ("a/*/b/c.fits", "a"), ("a/b.fits", "a"), ("**/x", "")],
)
def test_static_prefix(pattern: str, prefix: str) -> None:
    assert static_prefix(pattern) == prefix
